#include "sim-client/net/tcp_link.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <boost/asio/connect.hpp>
#include <boost/asio/write.hpp>

namespace tb::client {

namespace asio = boost::asio;
using asio::ip::tcp;

clock::Duration Backoff::next() {
  clock::Duration d = initial_;
  for (int i = 0; i < attempts_ && d < max_; ++i)
    d *= 2;
  ++attempts_;
  return std::min(d, max_);
}

TcpLink::TcpLink(asio::io_context& io, clock::Runtime& runtime, std::string host,
                 std::uint16_t port, SimSession& session)
    : io_(io),
      runtime_(runtime),
      host_(std::move(host)),
      port_(port),
      session_(session),
      resolver_(io),
      read_buffer_(64 * 1024),
      backoff_(std::chrono::milliseconds(250), std::chrono::seconds(8)) {}

TcpLink::~TcpLink() {
  stop();
}

void TcpLink::start() {
  stopped_ = false;
  connect();
}

void TcpLink::stop() {
  stopped_ = true;
  ++generation_;
  if (retry_timer_ != 0)
    runtime_.cancel(retry_timer_);
  retry_timer_ = 0;
  resolver_.cancel();
  if (socket_) {
    boost::system::error_code ignored;
    socket_->shutdown(tcp::socket::shutdown_both, ignored);
    socket_->close(ignored);
  }
  if (connected_)
    session_.on_disconnected();
  connected_ = false;
}

void TcpLink::connect() {
  const std::uint64_t gen = ++generation_;
  status_ = fmt::format("connecting to {}:{}", host_, port_);
  socket_ = std::make_unique<tcp::socket>(io_);
  resolver_.async_resolve(
      host_, std::to_string(port_),
      [this, gen](const boost::system::error_code& ec, tcp::resolver::results_type results) {
        if (gen != generation_ || stopped_)
          return;
        if (ec) {
          lost(fmt::format("cannot resolve {}: {}", host_, ec.message()));
          return;
        }
        asio::async_connect(
            *socket_, results,
            [this, gen](const boost::system::error_code& ec2, const tcp::endpoint&) {
              if (gen != generation_ || stopped_)
                return;
              if (ec2) {
                lost(ec2.message());
                return;
              }
              on_connected();
            });
      });
}

void TcpLink::on_connected() {
  connected_ = true;
  boost::system::error_code ignored;
  socket_->set_option(tcp::no_delay(true), ignored);
  status_ = fmt::format("connected to {}:{}", host_, port_);
  spdlog::info("connected to sim-server {}:{}", host_, port_);
  queue_.clear();
  queued_bytes_ = 0;
  writing_ = false;
  read();
  session_.on_connected();
}

void TcpLink::read() {
  const std::uint64_t gen = generation_;
  socket_->async_read_some(
      asio::buffer(read_buffer_), [this, gen](const boost::system::error_code& ec, std::size_t n) {
        if (gen != generation_ || stopped_)
          return;
        if (ec) {
          lost(ec == asio::error::eof ? "the server closed the connection" : ec.message());
          return;
        }
        const bool keep = session_.on_bytes({read_buffer_.data(), n});
        if (session_.welcomed())
          backoff_.reset();
        if (!keep) {
          if (session_.ended()) {
            if (session_.phase() == SimSession::Phase::kFinished) {
              spdlog::info("sim-server: the scenario finished");
              status_ = "scenario finished";
            }
            stop();
            return;
          }
          lost(session_.last_error());
          return;
        }
        read();
      });
}

void TcpLink::send(std::vector<std::uint8_t> frame) {
  if (!connected_)
    return;
  if (queued_bytes_ + frame.size() > kMaxQueuedBytes) {
    if (dropped_++ % 1000 == 0)
      spdlog::warn("sim-server is not reading: dropped {} messages", dropped_);
    return;
  }
  queued_bytes_ += frame.size();
  queue_.push_back(std::move(frame));
  if (!writing_)
    write();
}

void TcpLink::write() {
  writing_ = true;
  const std::uint64_t gen = generation_;
  // Everything queued goes out in one gathered write: one system call, not one per message.
  batch_.clear();
  buffers_.clear();
  for (auto& m : queue_)
    batch_.push_back(std::move(m));
  queue_.clear();
  queued_bytes_ = 0;
  for (const auto& m : batch_)
    buffers_.push_back(asio::buffer(m));
  asio::async_write(*socket_, buffers_,
                    [this, gen](const boost::system::error_code& ec, std::size_t) {
                      if (gen != generation_ || stopped_)
                        return;
                      if (ec) {
                        lost(ec.message());
                        return;
                      }
                      batch_.clear();
                      if (queue_.empty()) {
                        writing_ = false;
                      } else {
                        write();
                      }
                    });
}

void TcpLink::lost(const std::string& why) {
  ++generation_;
  if (socket_) {
    boost::system::error_code ignored;
    socket_->close(ignored);
  }
  const bool was_connected = connected_;
  connected_ = false;
  queue_.clear();
  queued_bytes_ = 0;
  writing_ = false;
  if (was_connected)
    session_.on_disconnected();
  const clock::Duration delay = backoff_.next();
  const double seconds = std::chrono::duration<double>(delay).count();
  status_ = fmt::format("no server at {}:{} ({}); retry in {:.2f} s", host_, port_, why, seconds);
  if (was_connected) {
    spdlog::error("lost sim-server {}:{}: {}; reconnecting in {:.2f} s", host_, port_, why,
                  seconds);
  } else if (backoff_.attempts() <= 1 || backoff_.attempts() % 10 == 0) {
    spdlog::warn("cannot connect to sim-server {}:{}: {}; retrying in {:.2f} s", host_, port_, why,
                 seconds);
  }
  retry_timer_ = runtime_.schedule_in(delay, [this] {
    retry_timer_ = 0;
    if (!stopped_)
      connect();
  });
}

}  // namespace tb::client
