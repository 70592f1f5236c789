#pragma once
/// @file The federated medium's datagram (issue 35, docs/wire.md "Federated medium"): what one
/// node's radio-medium sends another over UDP — a frame a local station put on the air, with
/// its sender, the sender's position and the transmit time; or a heartbeat that says the node
/// is alive while its stations are quiet. Big-endian. Decoded without reading outside the
/// datagram (fuzzed: emu_radio_federation_datagram_fuzz); anything malformed is refused with
/// its reason.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "common/util/expected.hpp"
#include "network-emulator/radio/channel.hpp"

namespace tb::emu::radio {

inline constexpr std::array<std::uint8_t, 4> kFederationMagic = {'T', 'B', 'F', 'M'};
inline constexpr std::uint8_t kFederationVersion = 1;
/// Node names are what swarm calls its nodes (hostnames): 64 bytes are plenty.
inline constexpr std::size_t kMaxFederationNodeName = 64;
/// A veth frame is at most 1514 bytes; the medium's own frame limit (VethPorts::kMaxFrame).
inline constexpr std::size_t kMaxFederatedFrame = 4096;
/// Magic, version, kind, name length.
inline constexpr std::size_t kFederationHeadSize = 7;
/// Sender, flags, reserved, frame length, tx time, x, y, z.
inline constexpr std::size_t kFederationFrameFieldsSize = 4 + 1 + 1 + 2 + 8 + 3 * 8;
inline constexpr std::size_t kFederationHeartbeatFieldsSize = 8;

enum class FederationKind : std::uint8_t { kFrame = 1, kHeartbeat = 2 };

enum class FederationError {
  kTooShort,            ///< fewer bytes than the head
  kBadMagic,            ///< not "TBFM"
  kUnsupportedVersion,  ///< another version
  kUnknownKind,         ///< neither frame nor heartbeat
  kBadNodeName,         ///< name length 0, over the limit, or beyond the datagram
  kTruncated,           ///< the kind's fields do not fit
  kBadFrameLength,      ///< frame length disagrees with the bytes left, or is over the limit
  kTrailingBytes,       ///< a heartbeat with bytes after its fields
  kBadPosition,         ///< a position that is not a finite number
};
inline constexpr std::size_t kFederationErrorCount = 9;
std::string_view to_string(FederationError e);

/// A decoded datagram: views into the bytes it came from.
struct FederationDatagram {
  FederationKind kind = FederationKind::kHeartbeat;
  std::string_view node;  ///< the sending node's name
  std::int64_t tx_unix_ns = 0;
  // kFrame only:
  StationId sender = 0;
  bool has_position = false;
  std::array<double, 3> position{};  ///< local ENU, m (the sending medium's view at tx)
  std::span<const std::uint8_t> frame;
};

/// Appends a frame datagram to @p out (cleared first). @p frame must be at most
/// kMaxFederatedFrame bytes and @p node 1 to kMaxFederationNodeName: false (nothing written)
/// otherwise.
bool encode_federated_frame(std::string_view node, StationId sender,
                            const std::array<double, 3>* position, std::int64_t tx_unix_ns,
                            std::span<const std::uint8_t> frame, std::vector<std::uint8_t>& out);
bool encode_federation_heartbeat(std::string_view node, std::int64_t tx_unix_ns,
                                 std::vector<std::uint8_t>& out);

Expected<FederationDatagram, FederationError> decode_federation_datagram(
    std::span<const std::uint8_t> bytes);

}  // namespace tb::emu::radio
