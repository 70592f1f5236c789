// The link against an in-process TCP server on loopback: handshake, a lost server and the
// reconnection with backoff.
#include <gtest/gtest.h>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/write.hpp>

#include "common/clock/asio_runtime.hpp"
#include "sim-client/net/tcp_link.hpp"
#include "sim-client/net/tests/fake_server.hpp"

namespace tb::client {
namespace {

namespace asio = boost::asio;
namespace sim = wire::sim;
using asio::ip::tcp;

TEST(Backoff, DoublesUpToTheLimitAndResets) {
  Backoff b(std::chrono::milliseconds(250), std::chrono::seconds(2));
  EXPECT_EQ(b.next(), std::chrono::milliseconds(250));
  EXPECT_EQ(b.next(), std::chrono::milliseconds(500));
  EXPECT_EQ(b.next(), std::chrono::milliseconds(1000));
  EXPECT_EQ(b.next(), std::chrono::milliseconds(2000));
  EXPECT_EQ(b.next(), std::chrono::milliseconds(2000));
  b.reset();
  EXPECT_EQ(b.next(), std::chrono::milliseconds(250));
}

// A server that greets one client per accept and then hangs up.
class OneShotServer {
 public:
  explicit OneShotServer(asio::io_context& io, std::uint16_t port = 0)
      : acceptor_(io, tcp::endpoint(asio::ip::address_v4::loopback(), port)) {
    accept();
  }
  std::uint16_t port() const { return acceptor_.local_endpoint().port(); }
  int accepted = 0;
  int hellos = 0;

 private:
  void accept() {
    acceptor_.async_accept([this](const boost::system::error_code& ec, tcp::socket s) {
      if (ec)
        return;
      ++accepted;
      socket_ = std::make_unique<tcp::socket>(std::move(s));
      // Read the Hello frame (header + payload), then greet, send one state and hang up.
      header_.resize(sim::kHeaderSize);
      asio::read(*socket_, asio::buffer(header_));
      const std::uint32_t len = header_[4] | header_[5] << 8 | header_[6] << 16 | header_[7] << 24;
      std::vector<std::uint8_t> payload(len);
      asio::read(*socket_, asio::buffer(payload));
      if (header_[3] == static_cast<std::uint8_t>(sim::MessageType::kHello))
        ++hellos;
      auto w = sim::encode(testing::welcome());
      auto f = sim::encode(testing::frame(1));
      w.insert(w.end(), f.begin(), f.end());
      asio::write(*socket_, asio::buffer(w));
      socket_->close();
      accept();
    });
  }
  tcp::acceptor acceptor_;
  std::unique_ptr<tcp::socket> socket_;
  std::vector<std::uint8_t> header_;
};

TEST(TcpLink, ReconnectsAfterTheServerHangsUp) {
  asio::io_context io;
  clock::AsioRuntime rt(io);
  OneShotServer server(io);
  TcpLink* link_ptr = nullptr;
  SimSession session(
      {}, [&](std::vector<std::uint8_t> b) { link_ptr->send(std::move(b)); }, nullptr);
  TcpLink link(io, rt, "127.0.0.1", server.port(), session);
  link_ptr = &link;
  link.start();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (server.accepted < 3 && std::chrono::steady_clock::now() < deadline)
    io.run_for(std::chrono::milliseconds(20));
  EXPECT_GE(server.accepted, 3);
  EXPECT_GE(server.hellos, 2);
  EXPECT_GE(session.frames(), 2u);
  link.stop();
}

TEST(TcpLink, WaitsForAServerThatStartsLater) {
  asio::io_context io;
  clock::AsioRuntime rt(io);
  std::uint16_t port = 0;
  {
    tcp::acceptor probe(io, tcp::endpoint(asio::ip::address_v4::loopback(), 0));
    port = probe.local_endpoint().port();
  }
  TcpLink* link_ptr = nullptr;
  SimSession session(
      {}, [&](std::vector<std::uint8_t> b) { link_ptr->send(std::move(b)); }, nullptr);
  TcpLink link(io, rt, "127.0.0.1", port, session);
  link_ptr = &link;
  link.start();
  io.run_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(link.connected());
  EXPECT_NE(link.status().find("retry in"), std::string::npos) << link.status();
  OneShotServer server(io, port);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (server.accepted < 1 && std::chrono::steady_clock::now() < deadline)
    io.run_for(std::chrono::milliseconds(20));
  EXPECT_EQ(server.accepted, 1);
  link.stop();
}

}  // namespace
}  // namespace tb::client
