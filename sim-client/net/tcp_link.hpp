#pragma once
/// @file The TCP connection to sim-server: connects, carries a SimSession's bytes, and on a lost
/// server says so and reconnects with exponential backoff.

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

#include "common/clock/runtime.hpp"
#include "sim-client/net/session.hpp"

namespace tb::client {

/// Reconnection delays: doubling from `initial` up to `max`; reset after a good connection.
class Backoff {
 public:
  Backoff(clock::Duration initial, clock::Duration max) : initial_(initial), max_(max) {}
  clock::Duration next();
  void reset() { attempts_ = 0; }
  int attempts() const { return attempts_; }

 private:
  clock::Duration initial_, max_;
  int attempts_ = 0;
};

class TcpLink {
 public:
  /// Bytes queued beyond this are dropped: a server that does not read gets the latest
  /// controls soon enough once it does, and the client's memory stays bounded. In bytes, not
  /// messages: a client attaching 4096 vehicles queues 4096 small Attach messages at once, and
  /// a second of 1000 vehicles' controls is 100 batches of 25 kB.
  static constexpr std::size_t kMaxQueuedBytes = 4u << 20;

  TcpLink(boost::asio::io_context& io, clock::Runtime& runtime, std::string host,
          std::uint16_t port, SimSession& session);
  ~TcpLink();

  void start();
  void stop();
  /// Queues a complete frame for the server (dropped while disconnected).
  void send(std::vector<std::uint8_t> frame);
  bool connected() const { return connected_; }
  /// For the view: "connected to HOST:PORT", "connecting ...", "lost ...: retry in N s".
  const std::string& status() const { return status_; }

 private:
  void connect();
  void on_connected();
  void read();
  void write();
  void lost(const std::string& why);

  boost::asio::io_context& io_;
  clock::Runtime& runtime_;
  std::string host_;
  std::uint16_t port_;
  SimSession& session_;
  boost::asio::ip::tcp::resolver resolver_;
  std::unique_ptr<boost::asio::ip::tcp::socket> socket_;
  std::vector<std::uint8_t> read_buffer_;
  std::deque<std::vector<std::uint8_t>> queue_;
  std::size_t queued_bytes_ = 0;
  /// The messages being written (all that was queued when the write began) and their buffers.
  std::vector<std::vector<std::uint8_t>> batch_;
  std::vector<boost::asio::const_buffer> buffers_;
  bool writing_ = false;
  bool connected_ = false;
  bool stopped_ = false;
  std::uint64_t generation_ = 0;  ///< ignores handlers of a socket already replaced
  clock::TimerId retry_timer_ = 0;
  Backoff backoff_;
  std::string status_;
  std::uint64_t dropped_ = 0;
};

}  // namespace tb::client
