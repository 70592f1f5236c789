#pragma once
/// @file FederationSocket: the federated medium's UDP side (issue 35), a thin adapter between
/// Boost.Asio and Federation, which holds all the logic. One socket listens for the peers'
/// datagrams (--federation-listen, 0.0.0.0:4730 by default); one connected socket per peer
/// sends to it, so that the kernel reports an ICMP port or host unreachable as an error of that
/// peer's next send. Peer names (swarm service names) are resolved at start and again every
/// kResolveInterval — swarm's DNS may not know a service yet, and a service that comes back may
/// have another address; while a name does not resolve, the peer is reported with that reason.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/asio/steady_timer.hpp>

#include "network-emulator/radio/federation.hpp"

namespace tb::emu::radio {

class FederationSocket final : public FederationTransport {
 public:
  static constexpr std::chrono::seconds kResolveInterval{5};
  /// A datagram, the time it was read (CLOCK_REALTIME) and the kernel's receive stamp of it
  /// (SO_TIMESTAMPNS; 0 when none came): their difference is this medium's wake-up.
  using DatagramHandler = std::function<void(std::span<const std::uint8_t>, std::int64_t rx_ns,
                                             std::int64_t kernel_rx_ns)>;
  using ErrorHandler = std::function<void(std::size_t peer, const std::string& why)>;

  /// Listens on @p listen (@throws boost::system::system_error when it cannot) for datagrams
  /// to @p on_datagram; sends to @p peers (their medium HOST:PORT) once resolved, and reports
  /// send and resolution failures to @p on_error, posted (never from inside send()).
  FederationSocket(boost::asio::io_context& io, const boost::asio::ip::udp::endpoint& listen,
                   const std::vector<PlacementNode>& peers, DatagramHandler on_datagram,
                   ErrorHandler on_error);
  ~FederationSocket() override;

  void start();
  void send(std::size_t peer, std::span<const std::uint8_t> datagram) override;

  boost::asio::ip::udp::endpoint local_endpoint() const { return listen_.local_endpoint(); }
  /// The address @p peer's name resolved to last, if it did.
  std::optional<boost::asio::ip::udp::endpoint> peer_endpoint(std::size_t peer) const;
  std::uint64_t send_errors() const { return send_errors_; }
  std::uint64_t not_resolved_drops() const { return not_resolved_drops_; }

 private:
  struct Peer {
    std::string host;
    std::uint16_t port = 0;
    std::string name;  ///< the node's
    std::unique_ptr<boost::asio::ip::udp::socket> socket;
    std::optional<boost::asio::ip::udp::endpoint> endpoint;
  };
  void receive();
  void drain();
  void resolve_all();
  void resolved(std::size_t k, const boost::asio::ip::udp::endpoint& ep);
  void report(std::size_t k, std::string why);

  boost::asio::io_context& io_;
  boost::asio::ip::udp::socket listen_;
  boost::asio::ip::udp::resolver resolver_;
  boost::asio::steady_timer resolve_timer_;
  std::vector<Peer> peers_;
  DatagramHandler on_datagram_;
  ErrorHandler on_error_;
  std::array<std::uint8_t, 65536> buf_{};
  std::array<std::uint8_t, 64> control_{};  ///< room for one SCM_TIMESTAMPNS
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
  std::uint64_t send_errors_ = 0;
  std::uint64_t not_resolved_drops_ = 0;
};

}  // namespace tb::emu::radio
