#pragma once
/// @file The Hub's clients over TCP (Boost.Asio): an acceptor and one connection per client
/// with a bounded send queue. Every handler runs on the io_context's single thread, the same
/// thread that steps the physics.

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sim-server/server/hub.hpp"

namespace tb::server {

class TcpConnection;

struct TcpOptions {
  std::string bind = "0.0.0.0";
  std::uint16_t port = 2000;
  /// Frames queued for one client before it counts as too slow: one second of states at
  /// 100 Hz, so that a client stalled for a moment (a GC pause, a window drag) survives.
  std::size_t max_queued_frames = 100;
};

class TcpServer {
 public:
  /// Binds and listens. @throws boost::system::system_error when the address is unusable.
  TcpServer(boost::asio::io_context& io, Hub& hub, TcpOptions options);
  ~TcpServer();
  std::uint16_t port() const;
  /// Connections whose socket is still open.
  std::size_t live_connections() const { return *live_; }
  /// Stops accepting; existing connections are closed through Hub::shutdown().
  void stop();

 private:
  void accept();

  boost::asio::io_context& io_;
  Hub& hub_;
  TcpOptions options_;
  boost::asio::ip::tcp::acceptor acceptor_;
  std::shared_ptr<std::size_t> live_ = std::make_shared<std::size_t>(0);
  /// Every connection made, so that those still lingering after their last frame are closed
  /// when the server goes (a lingering connection holds itself, and would outlive it).
  std::vector<std::weak_ptr<TcpConnection>> connections_;
};

}  // namespace tb::server
