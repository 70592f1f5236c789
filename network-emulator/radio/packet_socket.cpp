#include "network-emulator/radio/packet_socket.hpp"

#include <arpa/inet.h>
#include <linux/if_packet.h>
#include <net/ethernet.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

namespace tb::emu::radio {

namespace {
[[noreturn]] void fail(const std::string& what) {
  throw std::system_error(errno, std::generic_category(), what);
}
}  // namespace

PacketSocket::PacketSocket(const std::string& ifname, std::uint16_t ethertype, int rcvbuf_bytes)
    : ifname_(ifname) {
  ifindex_ = static_cast<int>(if_nametoindex(ifname.c_str()));
  if (ifindex_ == 0)
    fail("no interface " + ifname);
  fd_ = ::socket(AF_PACKET, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, htons(ethertype));
  if (fd_ < 0)
    fail("AF_PACKET socket for " + ifname + " (needs CAP_NET_RAW)");
  // Frames we send ourselves must not come back as received ones (Linux ≥ 4.20).
  int one = 1;
  setsockopt(fd_, SOL_PACKET, PACKET_IGNORE_OUTGOING, &one, sizeof one);
  // The medium sends into a veth: its peer's receive path runs in softirq anyway, the qdisc
  // only adds a lock and a queue.
  setsockopt(fd_, SOL_PACKET, PACKET_QDISC_BYPASS, &one, sizeof one);
  if (rcvbuf_bytes > 0 &&
      setsockopt(fd_, SOL_SOCKET, SO_RCVBUFFORCE, &rcvbuf_bytes, sizeof rcvbuf_bytes) != 0)
    setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &rcvbuf_bytes, sizeof rcvbuf_bytes);
  sockaddr_ll addr{};
  addr.sll_family = AF_PACKET;
  addr.sll_protocol = htons(ethertype);
  addr.sll_ifindex = ifindex_;
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    const int e = errno;
    ::close(fd_);
    errno = e;
    fail("cannot bind AF_PACKET socket to " + ifname);
  }
}

PacketSocket::~PacketSocket() {
  if (fd_ >= 0)
    ::close(fd_);
}

int PacketSocket::release() {
  const int fd = fd_;
  fd_ = -1;
  return fd;
}

bool PacketSocket::send(std::span<const std::uint8_t> frame) {
  // Bound sockets send on their interface; the frame carries its own Ethernet header.
  return ::send(fd_, frame.data(), frame.size(), 0) == static_cast<ssize_t>(frame.size());
}

long PacketSocket::receive(std::span<std::uint8_t> buf, bool wait) {
  for (;;) {
    sockaddr_ll from{};
    socklen_t len = sizeof from;
    const ssize_t n = ::recvfrom(fd_, buf.data(), buf.size(), MSG_DONTWAIT | MSG_TRUNC,
                                 reinterpret_cast<sockaddr*>(&from), &len);
    if (n < 0) {
      if (errno != EAGAIN && errno != EWOULDBLOCK)
        return -1;
      if (!wait)
        return 0;
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, -1) < 0 && errno != EINTR)
        return -1;
      continue;
    }
    // Kernels without PACKET_IGNORE_OUTGOING still show our own transmissions.
    if (from.sll_pkttype == PACKET_OUTGOING)
      continue;
    if (static_cast<std::size_t>(n) > buf.size()) {
      errno = EMSGSIZE;
      return -1;
    }
    return n;
  }
}

}  // namespace tb::emu::radio
