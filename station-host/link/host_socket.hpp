#pragma once
/// @file The host's one packet socket on its radio interface, shared by all its stations.
///
/// Reads GeoNetworking (0x8947) and pooled-delivery (0x88B5) frames only (a socket filter
/// drops the rest in the kernel), many per wake-up with recvmmsg, each with the kernel's
/// receive time (SO_TIMESTAMPNS) as PacketSocketLink gives a full station: GN and CAM timing
/// read it. The interface is made promiscuous: a unicast frame to a pooled station's MAC is
/// not addressed to the interface's own.

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>

#include "common/clock/clock.hpp"
#include "common/util/expected.hpp"
#include "its-station/link/link_layer.hpp"
#include "its-station/link/packet_socket_link.hpp"
#include "station-host/link/pooled_links.hpp"

namespace tb::host {

struct HostSocketStats {
  std::uint64_t frames = 0;
  std::uint64_t wakeups = 0;
  std::uint64_t truncated = 0;
  std::uint64_t ignored_outgoing = 0;
  std::uint64_t receive_errors = 0;
};

class HostSocket final : public FrameOutput {
 public:
  using FrameHandler = std::function<void(std::span<const std::uint8_t>, clock::WallTime)>;
  /// Frames read per recvmmsg call.
  static constexpr std::size_t kBatch = 32;

  /// Opens the socket on @p interface; receiving starts at once, driven by @p io. Errors as
  /// PacketSocketLink's (its-station/link), naming the interface.
  static Expected<std::unique_ptr<HostSocket>, its::link::OpenError> open(
      boost::asio::io_context& io, const std::string& interface);
  ~HostSocket() override;
  HostSocket(const HostSocket&) = delete;
  HostSocket& operator=(const HostSocket&) = delete;

  void set_handler(FrameHandler h) { handler_ = std::move(h); }
  std::error_code send_frame(std::span<const std::uint8_t> frame) override;
  const HostSocketStats& stats() const { return stats_; }

 private:
  HostSocket(boost::asio::io_context& io, int fd, std::string interface, int ifindex,
             std::size_t mtu);
  void arm();
  void drain();

  boost::asio::posix::stream_descriptor socket_;
  std::string interface_;
  int ifindex_;
  FrameHandler handler_;
  HostSocketStats stats_;
  /// A header and the interface's MTU (radio-medium gives a host's veth 9000 for its pooled
  /// deliveries), plus one byte to tell an oversized frame.
  std::size_t frame_capacity_;
  std::vector<std::uint8_t> buffers_;
};

}  // namespace tb::host
