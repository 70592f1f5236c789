#pragma once
/// @file The signal feed's datagram (issue 34 contract): one UDP datagram is exactly one
/// sim-protocol frame (8-byte header, version 7, type SignalStates 0x86), as the network
/// emulator sends each RSU its junction's groups (UDP port 4720).

#include <cstdint>
#include <span>
#include <string>

#include "common/util/expected.hpp"
#include "common/wire/sim_protocol.hpp"

namespace tb::its::rsu {

/// The RSU's default feed port.
inline constexpr std::uint16_t kSignalFeedPort = 4720;

/// Why a datagram is not a feed datagram.
struct FeedError {
  enum class Kind : std::uint8_t {
    kProtocol,         ///< the frame parser or decoder refused it (`protocol` says why)
    kIncomplete,       ///< shorter than its header declares
    kTrailingBytes,    ///< more than one frame
    kNotSignalStates,  ///< a valid frame of another type
  };
  Kind kind = Kind::kProtocol;
  wire::sim::ProtocolError protocol = wire::sim::ProtocolError::kBadLength;
};
std::string to_string(const FeedError& e);

/// Parses one datagram with the sim protocol's own parser and decoder. Never reads outside
/// @p datagram.
Expected<wire::sim::SignalStates, FeedError> parse_signal_datagram(
    std::span<const std::uint8_t> datagram);

}  // namespace tb::its::rsu
