#include "network-emulator/app/batch_sender.hpp"

#include <arpa/inet.h>
#include <linux/errqueue.h>
#include <netinet/in.h>

#include <algorithm>
#include <cstring>
#include <utility>

#include <fmt/format.h>

#include "network-emulator/app/peer_health.hpp"

namespace tb::emu {

Destination Destination::from(const sockaddr* a, socklen_t len) {
  Destination d;
  d.len = std::min<socklen_t>(len, sizeof d.addr);
  std::memcpy(&d.addr, a, d.len);
  return d;
}

bool Destination::operator==(const Destination& o) const {
  if (family() != o.family())
    return false;
  if (family() == AF_INET) {
    const auto& a = reinterpret_cast<const sockaddr_in&>(addr);
    const auto& b = reinterpret_cast<const sockaddr_in&>(o.addr);
    return a.sin_port == b.sin_port && a.sin_addr.s_addr == b.sin_addr.s_addr;
  }
  if (family() == AF_INET6) {
    const auto& a = reinterpret_cast<const sockaddr_in6&>(addr);
    const auto& b = reinterpret_cast<const sockaddr_in6&>(o.addr);
    return a.sin6_port == b.sin6_port &&
           std::memcmp(&a.sin6_addr, &b.sin6_addr, sizeof a.sin6_addr) == 0;
  }
  return len == o.len && std::memcmp(&addr, &o.addr, len) == 0;
}

std::size_t DestinationHash::operator()(const Destination& d) const {
  // FNV-1a over the bytes operator== compares.
  std::uint64_t h = 0xcbf29ce484222325ULL;
  auto mix = [&h](const void* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
      h ^= static_cast<const std::uint8_t*>(p)[i];
      h *= 0x100000001b3ULL;
    }
  };
  if (d.family() == AF_INET) {
    const auto& a = reinterpret_cast<const sockaddr_in&>(d.addr);
    mix(&a.sin_port, sizeof a.sin_port);
    mix(&a.sin_addr, sizeof a.sin_addr);
  } else if (d.family() == AF_INET6) {
    const auto& a = reinterpret_cast<const sockaddr_in6&>(d.addr);
    mix(&a.sin6_port, sizeof a.sin6_port);
    mix(&a.sin6_addr, sizeof a.sin6_addr);
  }
  return static_cast<std::size_t>(h);
}

std::string Destination::to_string() const {
  char text[INET6_ADDRSTRLEN] = "?";
  if (family() == AF_INET) {
    const auto& a = reinterpret_cast<const sockaddr_in&>(addr);
    ::inet_ntop(AF_INET, &a.sin_addr, text, sizeof text);
    return fmt::format("{}:{}", text, ntohs(a.sin_port));
  }
  if (family() == AF_INET6) {
    const auto& a = reinterpret_cast<const sockaddr_in6&>(addr);
    ::inet_ntop(AF_INET6, &a.sin6_addr, text, sizeof text);
    return fmt::format("[{}]:{}", text, ntohs(a.sin6_port));
  }
  return "?";
}

std::optional<QueuedError> parse_error_queue_message(const msghdr& msg) {
  if (msg.msg_name == nullptr || msg.msg_namelen < sizeof(sa_family_t))
    return std::nullopt;
  // CMSG_FIRSTHDR/NXTHDR take a non-const msghdr but only read it.
  auto& m = const_cast<msghdr&>(msg);
  for (cmsghdr* c = CMSG_FIRSTHDR(&m); c != nullptr; c = CMSG_NXTHDR(&m, c)) {
    const bool v4 = c->cmsg_level == SOL_IP && c->cmsg_type == IP_RECVERR;
    const bool v6 = c->cmsg_level == SOL_IPV6 && c->cmsg_type == IPV6_RECVERR;
    if (!v4 && !v6)
      continue;
    if (c->cmsg_len < CMSG_LEN(sizeof(sock_extended_err)))
      return std::nullopt;
    sock_extended_err ee;
    std::memcpy(&ee, CMSG_DATA(c), sizeof ee);
    // Time stamps and zero-copy completions use the error queue too; they are no error.
    if (ee.ee_errno == 0 ||
        (ee.ee_origin != SO_EE_ORIGIN_ICMP && ee.ee_origin != SO_EE_ORIGIN_ICMP6 &&
         ee.ee_origin != SO_EE_ORIGIN_LOCAL))
      return std::nullopt;
    // msg_name is the destination of the datagram that failed (the offender, SO_EE_OFFENDER,
    // is whoever sent the ICMP error: a router for host unreachable, so not the key).
    return QueuedError{
        Destination::from(static_cast<const sockaddr*>(msg.msg_name), msg.msg_namelen),
        std::error_code(static_cast<int>(ee.ee_errno), std::system_category())};
  }
  return std::nullopt;
}

BatchSender::BatchSender(BatchSocketOps& ops, std::size_t max_batch, bool connected)
    : ops_(ops), max_batch_(std::max<std::size_t>(1, max_batch)), connected_(connected) {
  queued_.reserve(max_batch_);
  headers_.reserve(max_batch_);
  iovecs_.reserve(max_batch_);
}

BatchSender::Sink BatchSender::add_sink(const Destination& to) {
  auto [it, added] = destination_index_.try_emplace(to, destinations_.size());
  if (added) {
    destinations_.push_back(to);
    sinks_of_destination_.emplace_back();
  }
  const Sink sink = destination_of_sink_.size();
  destination_of_sink_.push_back(it->second);
  sinks_of_destination_[it->second].push_back(sink);
  parked_.emplace_back();
  return sink;
}

std::error_code BatchSender::take_error(Sink sink) {
  return std::exchange(parked_[sink], std::error_code{});
}

std::error_code BatchSender::send(Sink sink, std::span<const std::uint8_t> datagram) {
  if (const std::error_code ec = take_error(sink))
    return ec;
  if (queued_.size() >= max_batch_)
    flush();
  // Flushing may have learnt of an error for this very sink; the datagram is still queued:
  // the error is returned by its next send, as a connected socket would.
  const std::size_t offset = arena_.size();
  arena_.insert(arena_.end(), datagram.begin(), datagram.end());
  queued_.push_back({sink, offset, datagram.size()});
  ++stats_.queued;
  return {};
}

std::size_t BatchSender::read_errors() {
  std::size_t n = 0;
  // Bounded: a flood of errors must not keep the emulator from its states.
  for (; n < 4096; ++n) {
    const auto e = ops_.read_error();
    if (!e)
      break;
    if (!e->error)
      continue;
    ++stats_.late_errors;
    const auto it = destination_index_.find(e->destination);
    if (it == destination_index_.end())
      continue;  // a destination this sender no longer feeds
    for (const Sink s : sinks_of_destination_[it->second])
      parked_[s] = e->error;
  }
  return n;
}

void BatchSender::flush() {
  if (queued_.empty())
    return;
  // The arena no longer grows until the batch is sent: its addresses are stable now.
  headers_.resize(queued_.size());
  iovecs_.resize(queued_.size());
  for (std::size_t i = 0; i < queued_.size(); ++i) {
    const Queued& q = queued_[i];
    Destination& d = destinations_[destination_of_sink_[q.sink]];
    iovecs_[i] = {arena_.data() + q.offset, q.size};
    msghdr& h = headers_[i].msg_hdr;
    h = {};
    h.msg_name = connected_ ? nullptr : &d.addr;
    h.msg_namelen = connected_ ? 0 : d.len;
    h.msg_iov = &iovecs_[i];
    h.msg_iovlen = 1;
    headers_[i].msg_len = 0;
  }
  std::size_t next = 0;
  bool retried = false;
  while (next < queued_.size()) {
    ++stats_.calls;
    const int n = ops_.send_many(std::span(headers_).subspan(next));
    if (n > 0) {
      stats_.sent += static_cast<std::size_t>(n);
      next += static_cast<std::size_t>(n);
      retried = false;
      continue;  // a short count: the next call reports what stopped the kernel
    }
    const std::error_code ec(n < 0 ? -n : EIO, std::system_category());
    if (PeerHealth::is_transient(ec)) {
      ++stats_.dropped;  // full buffer: this datagram is lost, the others may still fit
      ++next;
      continue;
    }
    // With IP_RECVERR an ICMP error also sets the socket's pending error, which the kernel
    // returns from the next send whatever its destination. If the error queue held entries,
    // that is where this error came from, and this datagram is innocent: send it again.
    if (!retried && read_errors() > 0) {
      retried = true;
      continue;
    }
    // An error of this datagram's own (no route, say): park it on its sink.
    ++stats_.failed;
    parked_[queued_[next].sink] = ec;
    ++next;
    retried = false;
  }
  queued_.clear();
  arena_.clear();
  // On loopback and veth the ICMP answer is queued during the send itself: read it now, so
  // that the station's next send already reports it.
  read_errors();
}

}  // namespace tb::emu
