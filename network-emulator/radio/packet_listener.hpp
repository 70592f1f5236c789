#pragma once
/// @file PacketListener: every frame of one ethertype that comes in on any interface of this
/// network namespace, one read per wake-up (recvmmsg), each with the kernel's receive time.
///
/// The kernel's forwarding (BridgeMedium) watches its frames through a PacketTap, whose blocks
/// are handed over up to 20 ms late (and the kernel's block timer ticks in jiffies: 4 ms at
/// HZ=250). A federated medium must pass each frame on to its peers at once, so under
/// federation the bridge reads its stations' frames a second time, here, as they come.

#include <sys/socket.h>

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>

namespace tb::emu::radio {

class PacketListener {
 public:
  static constexpr std::size_t kBatch = 32;
  static constexpr std::size_t kMaxFrame = 4096;
  using Handler =
      std::function<void(int ifindex, std::span<const std::uint8_t> frame, std::int64_t unix_ns)>;

  /// Frames of @p ethertype not coming in on @p exclude_ifindex (0: none), never those this
  /// host sends. @throws std::system_error.
  PacketListener(boost::asio::io_context& io, std::uint16_t ethertype, int exclude_ifindex,
                 Handler handler);
  ~PacketListener();
  PacketListener(const PacketListener&) = delete;
  PacketListener& operator=(const PacketListener&) = delete;

  void start();
  /// Reads what is there now; returns the number of frames handed over.
  std::size_t drain();
  std::uint64_t errors() const { return errors_; }

 private:
  int fd_ = -1;
  boost::asio::posix::stream_descriptor descriptor_;
  Handler handler_;
  std::vector<std::array<std::uint8_t, kMaxFrame>> buffers_;
  std::vector<mmsghdr> headers_;
  std::vector<iovec> iovecs_;
  std::vector<sockaddr_storage> from_;
  std::vector<std::array<char, 64>> control_;
  std::uint64_t errors_ = 0;
};

}  // namespace tb::emu::radio
