#include "station-host/link/host_socket.hpp"
#include "common/util/kernel_stamp.hpp"

#include <arpa/inet.h>
#include <linux/filter.h>
#include <linux/if_ether.h>
#include <linux/if_packet.h>
#include <linux/sockios.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "common/wire/pooled_delivery.hpp"

namespace tb::host {

namespace link = its::link;

namespace {

struct FdGuard {
  int fd;
  ~FdGuard() {
    if (fd >= 0)
      ::close(fd);
  }
  int release() { return std::exchange(fd, -1); }
};

// Classic BPF: accept the frame when the ethertype at offset 12 is GN or TBPD, else drop it.
constexpr sock_filter kFilter[] = {
    {BPF_LD | BPF_H | BPF_ABS, 0, 0, 12},
    {BPF_JMP | BPF_JEQ | BPF_K, 2, 0, link::kEtherTypeGeoNetworking},
    {BPF_JMP | BPF_JEQ | BPF_K, 1, 0, wire::kEthertypePooledDelivery},
    {BPF_RET | BPF_K, 0, 0, 0},
    {BPF_RET | BPF_K, 0, 0, 0xFFFF},
};

}  // namespace

Expected<std::unique_ptr<HostSocket>, link::OpenError> HostSocket::open(
    boost::asio::io_context& io, const std::string& interface) {
  auto fail = [&](link::OpenErrorKind kind, int err) {
    return Unexpected{link::OpenError{kind, interface, err}};
  };
  if (interface.empty() || interface.size() >= IFNAMSIZ)
    return fail(link::OpenErrorKind::kNoSuchInterface, EINVAL);
  const unsigned ifindex = ::if_nametoindex(interface.c_str());
  if (ifindex == 0)
    return fail(link::OpenErrorKind::kNoSuchInterface, errno);
  // Protocol 0 until bound: no frame of another interface is queued before the filter is on.
  FdGuard guard{::socket(AF_PACKET, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, 0)};
  if (guard.fd < 0)
    return fail(link::OpenErrorKind::kSocket, errno);
  sock_fprog prog{static_cast<unsigned short>(std::size(kFilter)),
                  const_cast<sock_filter*>(kFilter)};
  if (::setsockopt(guard.fd, SOL_SOCKET, SO_ATTACH_FILTER, &prog, sizeof prog) < 0)
    return fail(link::OpenErrorKind::kSocketOption, errno);
  const int on = 1;
  if (::setsockopt(guard.fd, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on) < 0)
    return fail(link::OpenErrorKind::kSocketOption, errno);
    // The host's own transmissions are looped back in-process when they must be; kernels
    // before 4.20 lack the option, and drain() skips PACKET_OUTGOING then.
#ifdef PACKET_IGNORE_OUTGOING
  (void)::setsockopt(guard.fd, SOL_PACKET, PACKET_IGNORE_OUTGOING, &on, sizeof on);
#endif
  sockaddr_ll addr{};
  addr.sll_family = AF_PACKET;
  addr.sll_protocol = htons(ETH_P_ALL);
  addr.sll_ifindex = static_cast<int>(ifindex);
  if (::bind(guard.fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) < 0)
    return fail(link::OpenErrorKind::kBind, errno);
  packet_mreq mr{};
  mr.mr_ifindex = static_cast<int>(ifindex);
  mr.mr_type = PACKET_MR_PROMISC;
  if (::setsockopt(guard.fd, SOL_PACKET, PACKET_ADD_MEMBERSHIP, &mr, sizeof mr) < 0)
    return fail(link::OpenErrorKind::kSocketOption, errno);
  ifreq req{};
  std::memcpy(req.ifr_name, interface.c_str(), interface.size() + 1);
  const std::size_t mtu =
      ::ioctl(guard.fd, SIOCGIFMTU, &req) == 0 && req.ifr_mtu > 0
          ? std::max<std::size_t>(link::kMaxPayload, static_cast<std::size_t>(req.ifr_mtu))
          : link::kMaxPayload;
  std::unique_ptr<HostSocket> s{
      new HostSocket(io, guard.release(), interface, static_cast<int>(ifindex), mtu)};
  s->arm();
  return s;
}

HostSocket::HostSocket(boost::asio::io_context& io, int fd, std::string interface, int ifindex,
                       std::size_t mtu)
    : socket_(io, fd),
      interface_(std::move(interface)),
      ifindex_(ifindex),
      frame_capacity_(14 + mtu + 1),
      buffers_(kBatch * frame_capacity_) {}

HostSocket::~HostSocket() {
  boost::system::error_code ignored;
  socket_.close(ignored);
}

std::error_code HostSocket::send_frame(std::span<const std::uint8_t> frame) {
  if (frame.size() < 14)
    return std::make_error_code(std::errc::invalid_argument);
  sockaddr_ll to{};
  to.sll_family = AF_PACKET;
  to.sll_protocol = htons(static_cast<std::uint16_t>(frame[12] << 8 | frame[13]));
  to.sll_ifindex = ifindex_;
  to.sll_halen = 6;
  std::memcpy(to.sll_addr, frame.data(), 6);
  const ssize_t n = ::sendto(socket_.native_handle(), frame.data(), frame.size(), 0,
                             reinterpret_cast<const sockaddr*>(&to), sizeof to);
  if (n < 0)
    return {errno, std::system_category()};
  if (static_cast<std::size_t>(n) != frame.size())
    return std::make_error_code(std::errc::message_size);
  return {};
}

void HostSocket::arm() {
  socket_.async_wait(boost::asio::posix::stream_descriptor::wait_read,
                     [this](const boost::system::error_code& ec) {
                       if (ec == boost::asio::error::operation_aborted)
                         return;
                       drain();
                       arm();
                     });
}

void HostSocket::drain() {
  ++stats_.wakeups;
  std::array<mmsghdr, kBatch> msgs{};
  std::array<iovec, kBatch> iovs{};
  std::array<sockaddr_ll, kBatch> from{};
  alignas(cmsghdr) std::array<std::array<char, CMSG_SPACE(sizeof(timespec))>, kBatch> control{};
  for (;;) {
    for (std::size_t i = 0; i < kBatch; ++i) {
      iovs[i] = {buffers_.data() + i * frame_capacity_, frame_capacity_};
      msgs[i] = {};
      msgs[i].msg_hdr.msg_name = &from[i];
      msgs[i].msg_hdr.msg_namelen = sizeof from[i];
      msgs[i].msg_hdr.msg_iov = &iovs[i];
      msgs[i].msg_hdr.msg_iovlen = 1;
      msgs[i].msg_hdr.msg_control = control[i].data();
      msgs[i].msg_hdr.msg_controllen = control[i].size();
    }
    const int n = ::recvmmsg(socket_.native_handle(), msgs.data(), kBatch, MSG_DONTWAIT, nullptr);
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK)
        return;
      if (errno == EINTR)
        continue;
      ++stats_.receive_errors;
      return;
    }
    for (int i = 0; i < n; ++i) {
      const msghdr& m = msgs[static_cast<std::size_t>(i)].msg_hdr;
      const std::size_t len = msgs[static_cast<std::size_t>(i)].msg_len;
      if (from[static_cast<std::size_t>(i)].sll_pkttype == PACKET_OUTGOING) {
        ++stats_.ignored_outgoing;
        continue;
      }
      if (len >= frame_capacity_ || (m.msg_flags & MSG_TRUNC)) {
        ++stats_.truncated;
        continue;
      }
      const auto stamp = kernel_rx_unix_ns(m);
      const clock::WallTime rx_time = stamp ? clock::from_unix_ns(*stamp) : clock::WallClock::now();
      ++stats_.frames;
      if (handler_)
        handler_({buffers_.data() + static_cast<std::size_t>(i) * frame_capacity_, len}, rx_time);
    }
    if (static_cast<std::size_t>(n) < kBatch)
      return;
  }
}

}  // namespace tb::host
