#pragma once
/// @file CanBus: where CAN frames go to and come from, whatever carries them.
///
/// Two transports (DESIGN.md, "Real parts, and what stands in"): SocketCAN (a vcan or real
/// interface, socketcan_bus.hpp) and CAN frames over UDP in cannelloni's format
/// (udp_can_bus.hpp), the stand-in where the kernel has no CAN. Code above this interface
/// cannot tell them apart.

#include <cstdint>
#include <functional>
#include <span>
#include <string_view>
#include <system_error>

#include "common/can/frame.hpp"

namespace tb::can {

class CanBus {
 public:
  /// A received frame and its receive time (CLOCK_REALTIME, ns since the Unix epoch).
  using FrameHandler = std::function<void(const CanFrame&, std::int64_t rx_unix_ns)>;

  virtual ~CanBus() = default;
  /// "vcan" (SocketCAN) or "udp" (cannelloni over UDP), for logs.
  virtual std::string_view kind() const = 0;
  /// Sends @p frames without blocking (one datagram where the transport allows). An error
  /// means the frames were not sent: would_block when the socket buffer is full,
  /// connection_refused / host_unreachable when the peer is gone.
  virtual std::error_code send(std::span<const CanFrame> frames) = 0;
  /// Delivers every frame received from now on to @p handler, on the io_context's thread.
  virtual void start_receive(FrameHandler handler) = 0;
};

}  // namespace tb::can
