#pragma once
/// @file CanBus: where CAN frames go to and come from, whatever carries them.
///
/// Two transports (DESIGN.md, "Real parts, and what stands in"): SocketCAN (a vcan or real
/// interface, socketcan_bus.hpp) and CAN frames over UDP in cannelloni's format
/// (udp_can_bus.hpp), the stand-in where the kernel has no CAN. Code above this interface
/// cannot tell them apart.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string_view>
#include <system_error>
#include <utility>

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
  /// Delivers frames when asked instead of at each arrival: they wait in the socket until
  /// poll() hands them to @p handler, and at the latest every @p backstop (so that the
  /// socket's buffer cannot overflow while nobody asks). A reader that needs the bus's state
  /// only now and then (the station: when it makes a CAM or evaluates LCRW) saves the wake-up
  /// of each frame: 100 a second at the vehicle's 100 Hz dynamics, the most frequent wake-up of
  /// a station (issue 33, docs/latency.md). A transport that cannot wait keeps delivering at
  /// arrival, as start_receive.
  virtual void start_on_demand(FrameHandler handler, std::chrono::milliseconds backstop) {
    (void)backstop;
    start_receive(std::move(handler));
  }
  /// Hands every frame received so far to the handler of start_on_demand, without waiting;
  /// returns how many. Does nothing (0) before start_on_demand or on a transport that
  /// delivers at arrival.
  virtual std::size_t poll() { return 0; }
};

}  // namespace tb::can
