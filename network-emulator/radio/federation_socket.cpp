#include "network-emulator/radio/federation_socket.hpp"

#include <sys/socket.h>

#include <fmt/format.h>
#include <boost/asio/post.hpp>

#include "common/trace/tracer.hpp"
#include "common/util/kernel_stamp.hpp"

namespace tb::emu::radio {

namespace asio = boost::asio;
using asio::ip::udp;

FederationSocket::FederationSocket(asio::io_context& io, const udp::endpoint& listen,
                                   const std::vector<PlacementNode>& peers,
                                   DatagramHandler on_datagram, ErrorHandler on_error)
    : io_(io),
      listen_(io, listen),
      resolver_(io),
      resolve_timer_(io),
      on_datagram_(std::move(on_datagram)),
      on_error_(std::move(on_error)) {
  // Room for a burst of frames from every peer while this thread is busy.
  listen_.set_option(asio::socket_base::receive_buffer_size(4 << 20));
  // The kernel's receive stamp splits the hop (medium.hop) into the way to this host and this
  // medium's wake-up; without it the datagram is dated at its read alone.
  const int on = 1;
  ::setsockopt(listen_.native_handle(), SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on);
  listen_.non_blocking(true);
  for (const auto& n : peers)
    peers_.push_back(Peer{n.medium_host, n.medium_port, n.name, nullptr, std::nullopt});
}

FederationSocket::~FederationSocket() {
  *alive_ = false;
}

void FederationSocket::start() {
  receive();
  resolve_all();
}

void FederationSocket::receive() {
  listen_.async_wait(asio::socket_base::wait_read, [this](const boost::system::error_code& ec) {
    if (ec == asio::error::operation_aborted)
      return;
    if (!ec)
      drain();
    receive();
  });
}

void FederationSocket::drain() {
  // Bounded, so that a flood from a peer cannot keep the medium from its local frames.
  for (int k = 0; k < 64; ++k) {
    iovec iov{buf_.data(), buf_.size()};
    msghdr m{};
    m.msg_iov = &iov;
    m.msg_iovlen = 1;
    m.msg_control = control_.data();
    m.msg_controllen = control_.size();
    const ssize_t n = ::recvmsg(listen_.native_handle(), &m, MSG_DONTWAIT);
    if (n < 0)
      return;  // EAGAIN: all read; ICMP errors on the listener are not this socket's to report
    on_datagram_(std::span<const std::uint8_t>(buf_.data(), static_cast<std::size_t>(n)),
                 trace::Tracer::now_ns(), kernel_rx_unix_ns(m).value_or(0));
  }
}

void FederationSocket::resolve_all() {
  for (std::size_t k = 0; k < peers_.size(); ++k) {
    resolver_.async_resolve(
        udp::v4(), peers_[k].host, std::to_string(peers_[k].port),
        [this, k, alive = alive_](const boost::system::error_code& ec,
                                  udp::resolver::results_type results) {
          if (!*alive || ec == asio::error::operation_aborted)
            return;
          if (ec || results.empty()) {
            report(k, fmt::format("its medium's name {} does not resolve ({})", peers_[k].host,
                                  ec ? ec.message() : "no address"));
            return;
          }
          resolved(k, results.begin()->endpoint());
        });
  }
  resolve_timer_.expires_after(kResolveInterval);
  resolve_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec)
      resolve_all();
  });
}

void FederationSocket::resolved(std::size_t k, const udp::endpoint& ep) {
  Peer& p = peers_[k];
  if (p.endpoint == ep && p.socket)
    return;
  auto socket = std::make_unique<udp::socket>(io_, udp::v4());
  boost::system::error_code ec;
  socket->non_blocking(true, ec);
  socket->connect(ep, ec);
  if (ec) {
    report(k, fmt::format("cannot connect to {}:{} ({})", ep.address().to_string(), ep.port(),
                          ec.message()));
    return;
  }
  p.socket = std::move(socket);
  p.endpoint = ep;
}

std::optional<udp::endpoint> FederationSocket::peer_endpoint(std::size_t peer) const {
  return peers_.at(peer).endpoint;
}

void FederationSocket::send(std::size_t peer, std::span<const std::uint8_t> datagram) {
  Peer& p = peers_.at(peer);
  if (!p.socket) {
    ++not_resolved_drops_;
    return;
  }
  boost::system::error_code ec;
  p.socket->send(asio::buffer(datagram.data(), datagram.size()), 0, ec);
  if (!ec || ec == asio::error::would_block || ec == asio::error::no_buffer_space)
    return;  // a full buffer loses this datagram, as the air would; the peer is not at fault
  ++send_errors_;
  std::string why = ec.message();
  if (ec == asio::error::connection_refused)
    why = "connection refused: nothing listens there (ICMP port unreachable)";
  else if (ec == asio::error::host_unreachable || ec == asio::error::network_unreachable)
    why = ec.message() + " (ICMP unreachable)";
  report(peer, fmt::format("sending to {}:{} ({}:{}): {}", p.host, p.port,
                           p.endpoint->address().to_string(), p.endpoint->port(), why));
}

void FederationSocket::report(std::size_t k, std::string why) {
  asio::post(io_, [this, k, why = std::move(why), alive = alive_] {
    if (*alive)
      on_error_(k, why);
  });
}

}  // namespace tb::emu::radio
