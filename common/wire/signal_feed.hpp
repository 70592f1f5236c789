#pragma once
/// @file The signal feed (issue 34): how the traffic lights' states reach the road-side units.
///
/// Two UDP hops, one format: each datagram is exactly one sim-protocol frame (8-byte header,
/// version 7, type SignalStates 0x86; sim-server/PROTOCOL.md) made and read with the functions
/// of sim_protocol.hpp.
///   sim-client → network-emulator: every SignalStates the client gets from the server, to the
///     emulator's state address with the port + 1 (kSignalFeedPortOffset; 4700 → 4701);
///   network-emulator → each RSU station: the groups of its junction only, to the station's
///     address, port kRsuSignalPort (4720).
/// A real RSU gets these from its traffic controller; this is the testbed's stand-in for that
/// link (docs/wire.md, "Signal feed").

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "common/util/expected.hpp"
#include "common/wire/sim_protocol.hpp"

namespace tb::wire {

/// The emulator hears the signal feed on its state port + this.
inline constexpr std::uint16_t kSignalFeedPortOffset = 1;
/// Where an RSU station hears its junction's states (its-station --signals udp://0.0.0.0:4720).
inline constexpr std::uint16_t kRsuSignalPort = 4720;
/// Largest UDP payload over IPv4: a SignalStates frame beyond it (more than 3274 groups) is not
/// sent.
inline constexpr std::size_t kMaxSignalFeedDatagram = 65507;

enum class SignalFeedError : std::uint8_t {
  kBadFrame = 1,   ///< the header or payload does not decode (sim::ProtocolError)
  kTruncated,      ///< fewer bytes than the frame's header declares
  kTrailingBytes,  ///< more bytes than one frame
  kNotSignalStates,
  kTooLarge,  ///< encoding: the frame does not fit a datagram
};
inline constexpr std::size_t kSignalFeedErrorCount = 6;
std::string_view to_string(SignalFeedError e);

/// The datagram for @p states, or kTooLarge.
Expected<std::vector<std::uint8_t>, SignalFeedError> encode_signal_feed(
    const sim::SignalStates& states);

/// Reads one datagram. Never reads outside @p datagram.
Expected<sim::SignalStates, SignalFeedError> decode_signal_feed(
    std::span<const std::uint8_t> datagram);

}  // namespace tb::wire
