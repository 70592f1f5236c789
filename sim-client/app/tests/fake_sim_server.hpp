#pragma once
// An in-process stand-in for sim-server, speaking the real protocol on loopback in its own
// thread: greets, accepts drivers, streams states at 100 Hz and applies the controls it gets to
// the state records (so tests see what the server saw). Used until and besides the real one.

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>

#include "common/wire/sim_protocol.hpp"
#include "sim-client/net/tests/fake_server.hpp"

namespace tb::client::testing {

class FakeSimServer {
 public:
  FakeSimServer() : acceptor_(io_, {boost::asio::ip::address_v4::loopback(), 0}), timer_(io_) {
    accept();
    tick();
    thread_ = std::thread([this] { io_.run(); });
  }
  ~FakeSimServer() {
    io_.stop();
    thread_.join();
  }
  std::uint16_t port() const { return port_; }

  /// Closes the current connection, as a crashed server would.
  void hang_up() {
    boost::asio::post(io_, [this] {
      if (conn_)
        conn_->close();
      conn_.reset();
      attached_.clear();
    });
  }

  int accepted() const { return accepted_; }
  std::vector<wire::sim::ClientMessage> received() {
    std::lock_guard l(mutex_);
    return received_;
  }
  std::optional<wire::sim::ControlsMsg> last_controls(std::uint16_t vehicle) {
    std::lock_guard l(mutex_);
    const auto it = controls_.find(vehicle);
    if (it == controls_.end())
      return std::nullopt;
    return it->second;
  }
  /// The state records sent for station @p station, by tick.
  std::map<std::uint64_t, wire::VehicleState> sent(std::uint32_t station) {
    std::lock_guard l(mutex_);
    std::map<std::uint64_t, wire::VehicleState> out;
    for (const auto& [tick, f] : frames_) {
      for (const auto& v : f.vehicles) {
        if (v.station_id == station)
          out[tick] = v;
      }
    }
    return out;
  }

 private:
  void accept() {
    port_ = acceptor_.local_endpoint().port();
    acceptor_.async_accept(
        [this](const boost::system::error_code& ec, boost::asio::ip::tcp::socket s) {
          if (ec)
            return;
          ++accepted_;
          conn_ = std::make_shared<boost::asio::ip::tcp::socket>(std::move(s));
          parser_ = wire::sim::FrameParser(wire::sim::Sender::kClient);
          attached_.clear();
          read(conn_);
          accept();
        });
  }
  void read(std::shared_ptr<boost::asio::ip::tcp::socket> c) {
    c->async_read_some(boost::asio::buffer(buf_),
                       [this, c](const boost::system::error_code& ec, std::size_t n) {
                         if (ec || c != conn_)
                           return;
                         std::span<const std::uint8_t> bytes(buf_.data(), n);
                         while (!bytes.empty()) {
                           auto st = parser_.parse(bytes);
                           if (!st || *st != wire::sim::FrameParser::Status::kFrame)
                             break;
                           auto m = wire::sim::decode_client(parser_.frame());
                           if (!m)
                             break;
                           on_message(*m);
                         }
                         read(c);
                       });
  }
  void send(std::vector<std::uint8_t> bytes) {
    if (!conn_)
      return;
    boost::system::error_code ec;
    boost::asio::write(*conn_, boost::asio::buffer(bytes), ec);
  }
  void on_message(const wire::sim::ClientMessage& m) {
    {
      std::lock_guard l(mutex_);
      received_.push_back(m);
      if (const auto* c = std::get_if<wire::sim::ControlsMsg>(&m))
        controls_[c->vehicle] = *c;
      if (const auto* b = std::get_if<wire::sim::ControlsBatch>(&m)) {
        for (const auto& c : b->entries)
          controls_[c.vehicle] = c;
      }
    }
    if (std::holds_alternative<wire::sim::Hello>(m))
      send(wire::sim::encode(welcome()));
    if (const auto* a = std::get_if<wire::sim::Attach>(&m)) {
      attached_.push_back(a->vehicle);
      if (a->role == wire::sim::Role::kDriver)
        send(wire::sim::encode(
            wire::sim::AttachResult{a->role, a->vehicle, wire::sim::AttachStatus::kOk, ""}));
    }
  }
  void tick() {
    timer_.expires_after(std::chrono::milliseconds(10));
    timer_.async_wait([this](const boost::system::error_code& ec) {
      if (ec)
        return;
      if (conn_ && !attached_.empty()) {
        ++tick_;
        wire::sim::StateFrame f = frame(tick_);
        {
          std::lock_guard l(mutex_);
          for (auto& v : f.vehicles) {
            const auto idx = static_cast<std::uint16_t>(v.station_id - 1001);
            if (const auto it = controls_.find(idx); it != controls_.end()) {
              v.controls = it->second.controls;
              v.lights = it->second.lights;
            }
          }
          frames_[tick_] = f;
        }
        send(wire::sim::encode(f));
      }
      tick();
    });
  }

  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  boost::asio::steady_timer timer_;
  std::thread thread_;
  std::atomic<std::uint16_t> port_{0};
  std::atomic<int> accepted_{0};
  std::shared_ptr<boost::asio::ip::tcp::socket> conn_;
  wire::sim::FrameParser parser_{wire::sim::Sender::kClient};
  std::array<std::uint8_t, 4096> buf_{};
  std::vector<std::uint16_t> attached_;
  std::uint64_t tick_ = 0;
  std::mutex mutex_;
  std::vector<wire::sim::ClientMessage> received_;
  std::map<std::uint16_t, wire::sim::ControlsMsg> controls_;
  std::map<std::uint64_t, wire::sim::StateFrame> frames_;
};

}  // namespace tb::client::testing
