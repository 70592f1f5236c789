#pragma once
/// @file The station's link layer as the GeoNetworking router sees it: broadcast or unicast
/// Ethernet-style frames with an ethertype, and received frames with the kernel's receive time.

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <system_error>

#include "common/clock/clock.hpp"

namespace tb::its::link {

using MacAddress = std::array<std::uint8_t, 6>;

inline constexpr MacAddress kBroadcastMac{0xff, 0xff, 0xff, 0xff, 0xff, 0xff};
/// GeoNetworking ethertype (EN 302 636-4-1 / IEEE registry; ITS-G5 frames carry it in LLC SNAP).
inline constexpr std::uint16_t kEtherTypeGeoNetworking = 0x8947;
/// Largest payload of one frame: the Ethernet MTU, which veth and 802.11 OCB interfaces share.
inline constexpr std::size_t kMaxPayload = 1500;

/// "aa:bb:cc:dd:ee:ff".
std::string to_string(const MacAddress& mac);

struct ReceivedFrame {
  MacAddress source{};
  MacAddress destination{};
  std::uint16_t ethertype = 0;
  std::span<const std::uint8_t> payload;
  /// When the kernel received the frame (SO_TIMESTAMPNS); the test double stamps injection time.
  clock::WallTime rx_time{};
};

using ReceiveHandler = std::function<void(const ReceivedFrame&)>;

/// A link that sends frames to a MAC address and hands received frames to one handler. Frames
/// are delivered from the thread that drives the implementation (the program's io_context).
class LinkLayer {
 public:
  virtual ~LinkLayer() = default;
  /// The interface's own MAC address (the GN address's MID is derived from it).
  virtual MacAddress address() const = 0;
  /// Sends one frame; an empty error_code means the kernel took it.
  virtual std::error_code send(const MacAddress& destination, std::uint16_t ethertype,
                               std::span<const std::uint8_t> payload) = 0;
  virtual void set_receive_handler(ReceiveHandler handler) = 0;
};

}  // namespace tb::its::link
