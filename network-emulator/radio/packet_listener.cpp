#include "network-emulator/radio/packet_listener.hpp"
#include "common/util/kernel_stamp.hpp"

#include <linux/if_ether.h>
#include <linux/if_packet.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include "network-emulator/radio/packet_tap.hpp"
#include "network-emulator/radio/read_loop.hpp"

namespace tb::emu::radio {
namespace {
[[noreturn]] void fail(int err, const std::string& what) {
  throw std::system_error(err, std::generic_category(), "frame listener: " + what);
}
}  // namespace

PacketListener::PacketListener(boost::asio::io_context& io, std::uint16_t ethertype,
                               int exclude_ifindex, Handler handler)
    : descriptor_(io), handler_(std::move(handler)) {
  // Protocol 0 until bind(): nothing comes in before the filter is set.
  fd_ = ::socket(AF_PACKET, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0)
    fail(errno, "AF_PACKET socket (needs CAP_NET_RAW)");
  try {
    int one = 1;
    if (::setsockopt(fd_, SOL_PACKET, PACKET_IGNORE_OUTGOING, &one, sizeof one) != 0)
      fail(errno, "PACKET_IGNORE_OUTGOING (Linux >= 4.20)");
    ::setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one);
    const int rcvbuf = 8 << 20;
    if (::setsockopt(fd_, SOL_SOCKET, SO_RCVBUFFORCE, &rcvbuf, sizeof rcvbuf) != 0)
      ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf);
    attach_ethertype_filter(fd_, ethertype, exclude_ifindex);
    sockaddr_ll addr{};
    addr.sll_family = AF_PACKET;
    addr.sll_protocol = htons(ETH_P_ALL);  // the filter picks the ethertype
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0)
      fail(errno, "bind");
  } catch (...) {
    ::close(fd_);
    throw;
  }
  buffers_.resize(kBatch);
  headers_.resize(kBatch);
  iovecs_.resize(kBatch);
  from_.resize(kBatch);
  control_.resize(kBatch);
}

PacketListener::~PacketListener() {
  if (fd_ >= 0)
    ::close(fd_);
}

void PacketListener::start() {
  descriptor_.assign(::dup(fd_));  // the descriptor closes its own copy
  drain_when_readable(descriptor_, [this] { drain(); });
}

std::size_t PacketListener::drain() {
  std::size_t total = 0;
  for (int round = 0; round < 4; ++round) {
    for (std::size_t i = 0; i < kBatch; ++i) {
      iovecs_[i] = {buffers_[i].data(), kMaxFrame};
      msghdr& m = headers_[i].msg_hdr;
      m = {};
      m.msg_name = &from_[i];
      m.msg_namelen = sizeof(sockaddr_storage);
      m.msg_iov = &iovecs_[i];
      m.msg_iovlen = 1;
      m.msg_control = control_[i].data();
      m.msg_controllen = control_[i].size();
    }
    const int n = ::recvmmsg(fd_, headers_.data(), kBatch, MSG_DONTWAIT | MSG_TRUNC, nullptr);
    if (n <= 0) {
      if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK)
        ++errors_;
      return total;
    }
    for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) {
      const msghdr& m = headers_[i].msg_hdr;
      const auto& from = reinterpret_cast<const sockaddr_ll&>(from_[i]);
      const std::size_t len = headers_[i].msg_len;
      if (from.sll_pkttype == PACKET_OUTGOING)
        continue;
      if (len > kMaxFrame || (m.msg_flags & MSG_TRUNC)) {
        ++errors_;
        continue;
      }
      const std::int64_t unix_ns = kernel_rx_unix_ns(m).value_or(0);
      ++total;
      handler_(from.sll_ifindex, std::span<const std::uint8_t>(buffers_[i].data(), len), unix_ns);
    }
    if (static_cast<std::size_t>(n) < kBatch)
      return total;
  }
  return total;
}

}  // namespace tb::emu::radio
