#pragma once
/// @file CanBus on a SocketCAN interface (vcan0 or a real CAN controller).

#include <cstdint>
#include <memory>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/steady_timer.hpp>

#include "common/can/can_bus.hpp"
#include "common/util/expected.hpp"

namespace tb::can {

/// Whether this kernel offers SocketCAN at all: socket(PF_CAN, SOCK_RAW, CAN_RAW) fails with
/// EAFNOSUPPORT or EPROTONOSUPPORT where the can / can-raw modules are missing.
bool socketcan_available();

/// Counters of the receiving side.
struct SocketCanStats {
  std::uint64_t frames = 0;           ///< handed to the handler
  std::uint64_t reads = 0;            ///< recvmmsg calls that returned frames
  std::uint64_t unexpected_size = 0;  ///< reads that were not one struct can_frame (skipped)
};

class SocketCanBus final : public CanBus {
 public:
  /// Opens a CAN_RAW socket on @p interface, created inside network namespace @p netns when
  /// given (see netns.hpp). Errors: no such device, address family not supported, ...
  static Expected<std::unique_ptr<SocketCanBus>, std::error_code> open(
      boost::asio::io_context& io, const std::string& interface, const std::string& netns = {});
  ~SocketCanBus() override;
  SocketCanBus(const SocketCanBus&) = delete;
  SocketCanBus& operator=(const SocketCanBus&) = delete;

  std::string_view kind() const override { return "vcan"; }
  std::error_code send(std::span<const CanFrame> frames) override;
  void start_receive(FrameHandler handler) override;
  /// As UdpCanBus: the descriptor leaves the io_context (and its epoll set), so that frames
  /// wake nobody; poll() and the backstop read what is queued.
  void start_on_demand(FrameHandler handler, std::chrono::milliseconds backstop) override;
  std::size_t poll() override;

  /// Frames the kernel dropped for a full socket buffer (SO_RXQ_OVFL), as of the last read.
  std::uint64_t dropped_by_kernel() const { return dropped_; }
  const SocketCanStats& stats() const { return stats_; }

  /// poll() reads up to kReadBatch frames per system call.
  static constexpr std::size_t kReadBatch = 16;

 private:
  SocketCanBus(boost::asio::io_context& io, int fd);
  void wait_next();
  void arm_backstop();
  /// Hands every queued frame to the handler, kReadBatch per recvmmsg; returns how many.
  std::size_t read_all();

  boost::asio::posix::stream_descriptor descriptor_;
  /// The socket, registered with the io_context through descriptor_ until start_on_demand
  /// releases it; from then on owned (and closed) here.
  int fd_;
  bool released_ = false;
  FrameHandler handler_;
  bool on_demand_ = false;
  std::chrono::milliseconds backstop_period_{};
  std::unique_ptr<boost::asio::steady_timer> backstop_;  ///< on demand only
  std::uint64_t dropped_ = 0;
  SocketCanStats stats_;
};

}  // namespace tb::can
