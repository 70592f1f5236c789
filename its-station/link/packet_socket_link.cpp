#include "its-station/link/packet_socket_link.hpp"
#include "common/util/kernel_stamp.hpp"

#include <arpa/inet.h>
#include <linux/ethtool.h>
#include <linux/if_arp.h>
#include <linux/if_packet.h>
#include <linux/sockios.h>
#include <net/ethernet.h>
#include <net/if.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "common/util/bytes.hpp"

namespace tb::its::link {

std::string to_string(OpenErrorKind kind) {
  switch (kind) {
    case OpenErrorKind::kNoSuchInterface:
      return "no such interface";
    case OpenErrorKind::kSocket:
      return "cannot open packet socket (needs CAP_NET_RAW)";
    case OpenErrorKind::kBind:
      return "cannot bind packet socket to the interface";
    case OpenErrorKind::kHardwareAddress:
      return "cannot read the interface's MAC address";
    case OpenErrorKind::kSocketOption:
      return "cannot enable kernel receive timestamps (SO_TIMESTAMPNS)";
  }
  return "unknown error";
}

std::string OpenError::message() const {
  std::string text = "link: interface '" + interface + "': " + to_string(kind);
  if (error_number != 0)
    text += std::string(" (") + std::strerror(error_number) + ")";
  return text;
}

namespace {

struct FdGuard {
  int fd;
  ~FdGuard() {
    if (fd >= 0)
      ::close(fd);
  }
  int release() { return std::exchange(fd, -1); }
};

}  // namespace

Expected<std::unique_ptr<PacketSocketLink>, OpenError> PacketSocketLink::open(
    boost::asio::io_context& io, const std::string& interface, std::uint16_t ethertype) {
  auto fail = [&](OpenErrorKind kind, int err) {
    return Unexpected{OpenError{kind, interface, err}};
  };
  if (interface.empty() || interface.size() >= IFNAMSIZ)
    return fail(OpenErrorKind::kNoSuchInterface, EINVAL);
  const unsigned ifindex = ::if_nametoindex(interface.c_str());
  if (ifindex == 0)
    return fail(OpenErrorKind::kNoSuchInterface, errno);

  FdGuard guard{::socket(AF_PACKET, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, htons(ethertype))};
  if (guard.fd < 0)
    return fail(OpenErrorKind::kSocket, errno);

  ifreq req{};
  std::memcpy(req.ifr_name, interface.c_str(), interface.size() + 1);
  if (::ioctl(guard.fd, SIOCGIFHWADDR, &req) < 0)
    return fail(OpenErrorKind::kHardwareAddress, errno);
  // wlan interfaces report ARPHRD_ETHER too once their type is OCB/managed (mac80211 netdevs).
  if (req.ifr_hwaddr.sa_family != ARPHRD_ETHER)
    return fail(OpenErrorKind::kHardwareAddress, EAFNOSUPPORT);
  MacAddress mac;
  std::memcpy(mac.data(), req.ifr_hwaddr.sa_data, mac.size());

  const int on = 1;
  if (::setsockopt(guard.fd, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on) < 0)
    return fail(OpenErrorKind::kSocketOption, errno);

  sockaddr_ll addr{};
  addr.sll_family = AF_PACKET;
  addr.sll_protocol = htons(ethertype);
  addr.sll_ifindex = static_cast<int>(ifindex);
  if (::bind(guard.fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) < 0)
    return fail(OpenErrorKind::kBind, errno);

  std::unique_ptr<PacketSocketLink> link{
      new PacketSocketLink(io, guard.release(), interface, static_cast<int>(ifindex), mac)};
  // The driver name only informs the log, so a driver that does not answer is no error.
  ethtool_drvinfo info{};
  info.cmd = ETHTOOL_GDRVINFO;
  ifreq drv{};
  std::memcpy(drv.ifr_name, interface.c_str(), interface.size() + 1);
  drv.ifr_data = reinterpret_cast<char*>(&info);
  if (::ioctl(link->socket_.native_handle(), SIOCETHTOOL, &drv) == 0)
    link->driver_.assign(info.driver, ::strnlen(info.driver, sizeof info.driver));
  link->arm();
  return link;
}

PacketSocketLink::PacketSocketLink(boost::asio::io_context& io, int fd, std::string interface,
                                   int ifindex, MacAddress address)
    : socket_(io, fd), interface_(std::move(interface)), ifindex_(ifindex), address_(address) {}

PacketSocketLink::~PacketSocketLink() {
  boost::system::error_code ignored;
  socket_.close(ignored);
}

std::error_code PacketSocketLink::send(const MacAddress& destination, std::uint16_t ethertype,
                                       std::span<const std::uint8_t> payload) {
  if (payload.size() > kMaxPayload)
    return std::make_error_code(std::errc::message_size);
  ByteWriter w{tx_buffer_};
  w.write(destination);
  w.write(address_);
  w.be<std::uint16_t>(ethertype);
  w.write(payload);

  sockaddr_ll to{};
  to.sll_family = AF_PACKET;
  to.sll_protocol = htons(ethertype);
  to.sll_ifindex = ifindex_;
  to.sll_halen = 6;
  std::memcpy(to.sll_addr, destination.data(), destination.size());
  const ssize_t n = ::sendto(socket_.native_handle(), tx_buffer_.data(), w.position(), 0,
                             reinterpret_cast<const sockaddr*>(&to), sizeof to);
  if (n < 0)
    return {errno, std::system_category()};
  if (static_cast<std::size_t>(n) != w.position())
    return std::make_error_code(std::errc::message_size);
  return {};
}

void PacketSocketLink::arm() {
  socket_.async_wait(boost::asio::posix::stream_descriptor::wait_read,
                     [this](const boost::system::error_code& ec) {
                       // Aborted means the link is being destroyed: touch nothing.
                       if (ec == boost::asio::error::operation_aborted)
                         return;
                       drain();
                       arm();
                     });
}

RxVerdict classify_received(unsigned char pkttype, std::size_t length, bool truncated,
                            std::size_t capacity) {
  if (pkttype == PACKET_OUTGOING)
    return RxVerdict::kOutgoing;
  if (pkttype == PACKET_OTHERHOST)
    return RxVerdict::kOtherHost;
  // The buffer has a byte more than the largest frame: a frame that fills it is too large.
  if (truncated || length > capacity - 1)
    return RxVerdict::kTruncated;
  return RxVerdict::kDeliver;
}

std::optional<ReceivedFrame> parse_ethernet(std::span<const std::uint8_t> bytes,
                                            clock::WallTime rx_time) {
  ByteReader r{bytes};
  ReceivedFrame frame;
  r.read(frame.destination);
  r.read(frame.source);
  frame.ethertype = r.be<std::uint16_t>();
  if (!r.ok())
    return std::nullopt;
  frame.payload = r.rest();
  frame.rx_time = rx_time;
  return frame;
}

void PacketSocketLink::drain() {
  using Control = std::array<char, CMSG_SPACE(sizeof(timespec))>;
  for (;;) {
    std::array<sockaddr_ll, kBatch> from{};
    std::array<iovec, kBatch> iov{};
    alignas(cmsghdr) std::array<Control, kBatch> control{};
    std::array<mmsghdr, kBatch> msgs{};
    for (std::size_t i = 0; i < kBatch; ++i) {
      iov[i] = {rx_buffers_[i].data(), rx_buffers_[i].size()};
      msghdr& m = msgs[i].msg_hdr;
      m.msg_name = &from[i];
      m.msg_namelen = sizeof from[i];
      m.msg_iov = &iov[i];
      m.msg_iovlen = 1;
      m.msg_control = control[i].data();
      m.msg_controllen = control[i].size();
    }
    const int n =
        ::recvmmsg(socket_.native_handle(), msgs.data(), kBatch, MSG_DONTWAIT | MSG_TRUNC, nullptr);
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK)
        return;
      if (errno == EINTR)
        continue;
      ++stats_.receive_errors;
      return;
    }
    for (int k = 0; k < n; ++k) {
      msghdr& m = msgs[static_cast<std::size_t>(k)].msg_hdr;
      const std::size_t length = msgs[static_cast<std::size_t>(k)].msg_len;
      switch (classify_received(from[static_cast<std::size_t>(k)].sll_pkttype, length,
                                (m.msg_flags & MSG_TRUNC) != 0, kRxFrameSize)) {
        case RxVerdict::kOutgoing:
          ++stats_.ignored_outgoing;
          continue;
        case RxVerdict::kOtherHost:
          ++stats_.ignored_other_host;
          continue;
        case RxVerdict::kTruncated:
          ++stats_.truncated;
          continue;
        case RxVerdict::kDeliver:
          break;
      }
      const auto stamp = kernel_rx_unix_ns(m);
      const clock::WallTime rx_time = stamp ? clock::from_unix_ns(*stamp) : clock::WallClock::now();
      const auto frame = parse_ethernet(
          std::span<const std::uint8_t>(rx_buffers_[static_cast<std::size_t>(k)].data(), length),
          rx_time);
      if (!frame) {
        ++stats_.truncated;
        continue;
      }
      ++stats_.delivered;
      if (handler_)
        handler_(*frame);
    }
    // Fewer than a batch: the socket had no more. A frame that arrives from now on makes the
    // socket readable again, which the wait armed next sees.
    if (static_cast<std::size_t>(n) < kBatch)
      return;
  }
}

}  // namespace tb::its::link
