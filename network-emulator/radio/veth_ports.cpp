#include "network-emulator/radio/veth_ports.hpp"
#include "common/util/kernel_stamp.hpp"

#include <arpa/inet.h>
#include <linux/if_packet.h>
#include <net/ethernet.h>
#include <net/if.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include <spdlog/spdlog.h>
#include <boost/asio/post.hpp>

#include "common/wire/pooled_delivery.hpp"
#include "network-emulator/radio/packet_tap.hpp"
#include "network-emulator/radio/read_loop.hpp"

namespace tb::emu::radio {

namespace {
[[noreturn]] void fail(int err, const std::string& what) {
  throw std::system_error(err, std::generic_category(), "radio: " + what);
}

int open_packet_socket(int protocol) {
  const int fd = ::socket(AF_PACKET, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, protocol);
  if (fd < 0)
    fail(errno, "AF_PACKET socket (needs CAP_NET_RAW)");
  return fd;
}
}  // namespace

VethPorts::VethPorts(boost::asio::io_context& io, std::uint16_t ethertype, Medium& medium)
    : io_(io), medium_(medium), descriptor_(io) {
  // Protocol 0 until bind(): nothing comes in before the options are set.
  rx_fd_ = open_packet_socket(0);
  try {
    tx_fd_ = open_packet_socket(0);  // sends only: protocol 0 receives nothing
    int one = 1;
    // The medium's own deliveries go out of the same host ends: they are not frames on the air.
    if (::setsockopt(rx_fd_, SOL_PACKET, PACKET_IGNORE_OUTGOING, &one, sizeof one) != 0)
      fail(errno, "PACKET_IGNORE_OUTGOING (Linux >= 4.20)");
    // The kernel's receive time of each frame, for the trace (medium.rx).
    ::setsockopt(rx_fd_, SOL_SOCKET, SO_TIMESTAMPNS, &one, sizeof one);
    const int rcvbuf = 8 << 20;
    if (::setsockopt(rx_fd_, SOL_SOCKET, SO_RCVBUFFORCE, &rcvbuf, sizeof rcvbuf) != 0)
      ::setsockopt(rx_fd_, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf);
    attach_ethertype_filter(rx_fd_, ethertype, 0);
    sockaddr_ll addr{};
    addr.sll_family = AF_PACKET;
    addr.sll_protocol = htons(ETH_P_ALL);  // the filter picks the ethertype
    addr.sll_ifindex = 0;                  // every interface; frames of non-ports are ignored
    if (::bind(rx_fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0)
      fail(errno, "bind");
    // A veth's peer receives in softirq anyway: the qdisc would only add a lock and a queue.
    ::setsockopt(tx_fd_, SOL_PACKET, PACKET_QDISC_BYPASS, &one, sizeof one);
    const int sndbuf = 8 << 20;
    if (::setsockopt(tx_fd_, SOL_SOCKET, SO_SNDBUFFORCE, &sndbuf, sizeof sndbuf) != 0)
      ::setsockopt(tx_fd_, SOL_SOCKET, SO_SNDBUF, &sndbuf, sizeof sndbuf);
  } catch (...) {
    ::close(rx_fd_);
    if (tx_fd_ >= 0)
      ::close(tx_fd_);
    throw;
  }
  rx_buffers_.resize(kBatch);
  rx_headers_.resize(kBatch);
  rx_iovecs_.resize(kBatch);
  rx_from_.resize(kBatch);
  rx_control_.resize(kBatch);
}

VethPorts::~VethPorts() {
  for (const auto& [id, port] : ports_)
    medium_.detach(id);
  for (const StationId id : pooled_)
    medium_.detach(id);
  ::close(rx_fd_);
  ::close(tx_fd_);
}

void VethPorts::attach(StationId id, const std::string& host_ifname) {
  const int ifindex = static_cast<int>(if_nametoindex(host_ifname.c_str()));
  if (ifindex == 0)
    fail(errno, "no interface " + host_ifname);
  detach(id);
  auto& port = ports_[id] = std::make_unique<Port>(*this, ifindex);
  attribution_.add_station_port(ifindex, id);
  medium_.attach(id, *port);
}

void VethPorts::attach_pooled_host(const std::string& host_ifname, std::span<const StationId> ids,
                                   unsigned mtu) {
  const int ifindex = static_cast<int>(if_nametoindex(host_ifname.c_str()));
  if (ifindex == 0)
    fail(errno, "no interface " + host_ifname);
  auto& host = hosts_[ifindex];
  if (!host)
    host = std::make_unique<HostPort>(*this, ifindex, mtu);
  for (const StationId id : ids) {
    detach(id);
    attribution_.add_pooled(ifindex, id);
    pooled_.push_back(id);
    medium_.attach_pooled(id, *host);
  }
}

void VethPorts::detach(StationId id) {
  const bool full = ports_.erase(id) > 0;
  const bool pooled = std::erase(pooled_, id) > 0;
  if (!full && !pooled)
    return;
  medium_.detach(id);
  attribution_.remove_station(id);
}

void VethPorts::start() {
  descriptor_.assign(::dup(rx_fd_));
  drain_when_readable(descriptor_, [this] { drain(); });
}

void VethPorts::drain() {
  // The deliveries of what is read now go out at the end of this call, not a turn of the
  // io_context later.
  draining_ = true;
  drain_batches();
  draining_ = false;
  flush();
}

void VethPorts::drain_batches() {
  // A bounded number of batches per wake-up, so that the timers and the positions get their
  // turn when the stations send more than the medium can take.
  for (int round = 0; round < 4; ++round) {
    for (std::size_t i = 0; i < kBatch; ++i) {
      rx_iovecs_[i] = {rx_buffers_[i].data(), kMaxFrame};
      msghdr& m = rx_headers_[i].msg_hdr;
      m = {};
      m.msg_name = &rx_from_[i];
      m.msg_namelen = sizeof(sockaddr_storage);
      m.msg_iov = &rx_iovecs_[i];
      m.msg_iovlen = 1;
      m.msg_control = rx_control_[i].data();
      m.msg_controllen = rx_control_[i].size();
    }
    const int n = ::recvmmsg(rx_fd_, rx_headers_.data(), kBatch, MSG_DONTWAIT | MSG_TRUNC, nullptr);
    if (n <= 0) {
      if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && receive_errors_++ == 0)
        spdlog::warn("radio: receive failed: {} (counted, reported once)",
                     std::system_category().message(errno));
      return;
    }
    for (int i = 0; i < n; ++i) {
      const msghdr& m = rx_headers_[static_cast<std::size_t>(i)].msg_hdr;
      const auto& from =
          reinterpret_cast<const sockaddr_ll&>(rx_from_[static_cast<std::size_t>(i)]);
      const std::size_t len = rx_headers_[static_cast<std::size_t>(i)].msg_len;
      if (!attribution_.is_port(from.sll_ifindex) || from.sll_pkttype == PACKET_OUTGOING)
        continue;  // not a station's port, or (kernels before 4.20) one of our own deliveries
      if (len > kMaxFrame || (m.msg_flags & MSG_TRUNC)) {
        if (receive_errors_++ == 0)
          spdlog::warn(
              "radio: a frame of {} bytes on interface {} is longer than {} (dropped, "
              "counted, reported once)",
              len, from.sll_ifindex, kMaxFrame);
        continue;
      }
      const std::span<const std::uint8_t> bytes(rx_buffers_[static_cast<std::size_t>(i)].data(),
                                                len);
      const auto sender = attribution_.sender(from.sll_ifindex, bytes);
      if (!sender) {
        if (attribution_.unknown_sender() == 1)
          spdlog::warn(
              "radio: a frame on a station-host's port (interface {}) from a MAC address that "
              "names none of its stations (dropped, counted as unknown_sender, reported once)",
              from.sll_ifindex);
        continue;
      }
      const std::int64_t unix_ns = kernel_rx_unix_ns(m).value_or(0);
      ++received_;
      medium_.on_frame(*sender, bytes, unix_ns);
    }
    if (static_cast<std::size_t>(n) < kBatch)
      return;
  }
}

void VethPorts::queue(int ifindex, std::span<const std::uint8_t> frame) {
  if (pending_.size() >= kMaxPending)
    flush();
  pending_.push_back({ifindex, arena_.size(), frame.size()});
  arena_.insert(arena_.end(), frame.begin(), frame.end());
  if (!draining_ && !flush_posted_) {  // a delayed delivery: flushed once the due ones are in
    flush_posted_ = true;
    boost::asio::post(io_, [this] { flush(); });
  }
}

void VethPorts::queue_pooled(int ifindex, unsigned mtu, std::span<const StationId> receivers,
                             std::span<const std::uint8_t> frame) {
  // One frame for all of them; more only where the list would not fit into the host's MTU.
  const std::size_t per_frame = wire::pooled_receivers_per_frame(mtu, frame.size());
  if (per_frame == 0 || frame.size() < wire::kEthernetHeaderSize) {
    ++send_errors_;
    if (oversized_++ == 0)
      spdlog::warn(
          "radio: a frame of {} bytes does not fit into a pooled delivery of at most {} bytes "
          "(dropped, counted as a send error, reported once)",
          frame.size(), mtu);
    return;
  }
  for (std::size_t first = 0; first < receivers.size(); first += per_frame) {
    const auto chunk = receivers.subspan(first, std::min(per_frame, receivers.size() - first));
    const std::size_t size = wire::pooled_delivery_frame_size(chunk.size(), frame.size());
    if (pending_.size() >= kMaxPending)
      flush();
    const std::size_t offset = arena_.size();
    arena_.resize(offset + size);
    wire::build_pooled_delivery_frame(chunk, frame, std::span(arena_).subspan(offset, size));
    pending_.push_back({ifindex, offset, size});
    ++pooled_frames_;
  }
  if (!draining_ && !flush_posted_) {
    flush_posted_ = true;
    boost::asio::post(io_, [this] { flush(); });
  }
}

void VethPorts::flush() {
  flush_posted_ = false;
  if (pending_.empty())
    return;
  std::vector<sockaddr_ll>& to = tx_to_;
  std::vector<iovec>& iov = tx_iovecs_;
  std::vector<mmsghdr>& msgs = tx_headers_;
  to.assign(pending_.size(), sockaddr_ll{});
  iov.resize(pending_.size());
  msgs.resize(pending_.size());
  for (std::size_t i = 0; i < pending_.size(); ++i) {
    const Pending& p = pending_[i];
    sockaddr_ll& a = to[i];
    a.sll_family = AF_PACKET;
    a.sll_ifindex = p.ifindex;
    // The frame carries its own Ethernet header; sll_protocol is the frame's type.
    if (p.size >= 14)
      std::memcpy(&a.sll_protocol, &arena_[p.offset + 12], 2);
    iov[i] = {&arena_[p.offset], p.size};
    msgs[i] = {};
    msgs[i].msg_hdr.msg_name = &a;
    msgs[i].msg_hdr.msg_namelen = sizeof a;
    msgs[i].msg_hdr.msg_iov = &iov[i];
    msgs[i].msg_hdr.msg_iovlen = 1;
  }
  std::size_t done = 0;
  while (done < msgs.size()) {
    ++send_calls_;
    const int r = ::sendmmsg(tx_fd_, msgs.data() + done, static_cast<unsigned>(msgs.size() - done),
                             MSG_DONTWAIT);
    if (r > 0) {  // sendmmsg stops at the first message that fails
      sent_ += static_cast<std::uint64_t>(r);
      done += static_cast<std::size_t>(r);
      continue;
    }
    // The first of the rest failed (its port went down, or the kernel is out of buffers):
    // that delivery is lost, the others still go.
    if (send_errors_++ == 0)
      spdlog::warn("radio: sending into interface {} failed: {} (counted, reported once)",
                   pending_[done].ifindex, std::system_category().message(errno));
    ++done;
  }
  pending_.clear();
  arena_.clear();
}

}  // namespace tb::emu::radio
