#include "network-emulator/app/batch_io.hpp"

#include <netinet/in.h>
#include <unistd.h>

#include <cerrno>

#include "common/can/cannelloni.hpp"
#include "common/can/netns.hpp"

namespace tb::emu {

UdpBatchSocket::UdpBatchSocket(int family, const std::string& netns,
                               const Destination* connect_to) {
  int err = 0;
  const std::error_code ns_ec = tb::can::run_in_netns(netns, [&] {
    fd_ = ::socket(family, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd_ < 0)
      err = errno;
  });
  if (ns_ec)
    throw std::system_error(ns_ec, "netns " + netns);
  if (fd_ < 0)
    throw std::system_error(err, std::system_category(), "socket");
  const int on = 1;
  const bool v6 = family == AF_INET6;
  if (::setsockopt(fd_, v6 ? SOL_IPV6 : SOL_IP, v6 ? IPV6_RECVERR : IP_RECVERR, &on, sizeof on) !=
      0) {
    err = errno;
    ::close(fd_);
    throw std::system_error(err, std::system_category(), "setsockopt IP_RECVERR");
  }
  // DF set and the path MTU not followed (our datagrams stay under 1400 bytes): the kernel then
  // gives an unconnected socket's datagrams IP ID 0 instead of hashing one per datagram
  // (__ip_select_ident, a few % of the emulator's CPU at 100k datagrams/s). Best effort.
  if (!v6) {
    const int probe = IP_PMTUDISC_PROBE;
    ::setsockopt(fd_, SOL_IP, IP_MTU_DISCOVER, &probe, sizeof probe);
  }
  // A batch of 1000 stations' NMEA and CAN is about 700 kB; on loopback and veth the kernel
  // frees each datagram during the send, elsewhere the buffer must hold the burst. Best effort.
  const int size = 4 << 20;
  if (::setsockopt(fd_, SOL_SOCKET, SO_SNDBUFFORCE, &size, sizeof size) != 0)
    ::setsockopt(fd_, SOL_SOCKET, SO_SNDBUF, &size, sizeof size);
  if (connect_to &&
      ::connect(fd_, reinterpret_cast<const sockaddr*>(&connect_to->addr), connect_to->len) != 0) {
    err = errno;
    ::close(fd_);
    throw std::system_error(err, std::system_category(), "connect to " + connect_to->to_string());
  }
}

UdpBatchSocket::~UdpBatchSocket() {
  if (fd_ >= 0)
    ::close(fd_);
}

int UdpBatchSocket::send_many(std::span<mmsghdr> msgs) {
  const auto n = static_cast<unsigned>(std::min<std::size_t>(msgs.size(), 1024));
  const int r = ::sendmmsg(fd_, msgs.data(), n, MSG_DONTWAIT);
  return r < 0 ? -errno : r;
}

std::optional<QueuedError> UdpBatchSocket::read_error() {
  sockaddr_storage from{};
  alignas(cmsghdr) std::array<char, 512> control{};
  std::array<std::uint8_t, 64> payload{};  // the datagram that failed; only its address counts
  iovec iov{payload.data(), payload.size()};
  msghdr msg{};
  msg.msg_name = &from;
  msg.msg_namelen = sizeof from;
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = control.data();
  msg.msg_controllen = control.size();
  if (::recvmsg(fd_, &msg, MSG_ERRQUEUE | MSG_DONTWAIT) < 0)
    return std::nullopt;  // EAGAIN: the queue is empty
  if (auto e = parse_error_queue_message(msg))
    return e;
  return QueuedError{};  // read, but not an error about a destination
}

std::error_code BatchedCanBus::send(std::span<const tb::can::CanFrame> frames) {
  // The parked error first, so that a receiver that is gone pauses the feed before anything
  // is queued, as one error of a connected socket's send did.
  if (const std::error_code ec = sender_.take_error(sink_))
    return ec;
  while (!frames.empty()) {
    std::size_t n = 0, size = tb::can::kCannelloniHeaderSize;
    while (n < frames.size()) {
      const std::size_t next =
          tb::can::cannelloni_size(frames.subspan(n, 1)) - tb::can::kCannelloniHeaderSize;
      if (size + next > buffer_.size() && n > 0)
        break;
      size += next;
      ++n;
    }
    const std::size_t len = tb::can::encode_cannelloni(sequence_, frames.first(n), buffer_);
    if (len == 0)
      return std::make_error_code(std::errc::message_size);
    if (const std::error_code ec = sender_.send(sink_, {buffer_.data(), len}))
      return ec;
    ++sequence_;
    frames = frames.subspan(n);
  }
  return {};
}

BatchSender& BatchSenders::get(const std::string& netns, int family) {
  auto [it, added] = senders_.try_emplace({netns, family});
  if (added) {
    try {
      it->second.socket = std::make_unique<UdpBatchSocket>(family, netns);
    } catch (...) {
      senders_.erase(it);
      throw;
    }
    it->second.sender = std::make_unique<BatchSender>(*it->second.socket);
    all_.push_back(it->second.sender.get());
  }
  return *it->second.sender;
}

void BatchSenders::flush() {
  for (BatchSender* s : all_)
    if (!s->empty())
      s->flush();
}

BatchSender& BatchSenders::get_connected(const std::string& netns, const Destination& to) {
  auto [it, added] = connected_.try_emplace({netns, to.to_string()});
  if (added) {
    try {
      it->second.socket = std::make_unique<UdpBatchSocket>(to.family(), netns, &to);
    } catch (...) {
      connected_.erase(it);
      throw;
    }
    it->second.sender = std::make_unique<BatchSender>(*it->second.socket, 512, /*connected=*/true);
    all_.push_back(it->second.sender.get());
  }
  return *it->second.sender;
}

BatchStats BatchSenders::stats() const {
  BatchStats t;
  for (const BatchSender* s : all_) {
    const BatchStats& x = s->stats();
    t.queued += x.queued;
    t.sent += x.sent;
    t.dropped += x.dropped;
    t.failed += x.failed;
    t.late_errors += x.late_errors;
    t.calls += x.calls;
  }
  return t;
}

}  // namespace tb::emu
