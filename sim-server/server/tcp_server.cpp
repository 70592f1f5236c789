#include "sim-server/server/tcp_server.hpp"

#include <spdlog/spdlog.h>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/write.hpp>

#include <array>
#include <deque>

namespace tb::server {

namespace asio = boost::asio;
using asio::ip::tcp;

class TcpConnection final : public ClientLink, public std::enable_shared_from_this<TcpConnection> {
 public:
  TcpConnection(tcp::socket socket, Hub& hub, std::size_t max_frames,
                std::shared_ptr<std::size_t> live)
      : socket_(std::move(socket)),
        hub_(hub),
        max_frames_(max_frames),
        live_(std::move(live)),
        linger_(socket_.get_executor()) {
    ++*live_;
  }
  ~TcpConnection() override { --*live_; }

  /// Closes the socket now, whatever is queued or lingering (the server is going).
  void close_now() { shut(); }

  void start() {
    boost::system::error_code ec;
    // States are small and latency matters more than packet count.
    socket_.set_option(tcp::no_delay(true), ec);
    const auto ep = socket_.remote_endpoint(ec);
    const std::string peer =
        ec ? "unknown peer" : ep.address().to_string() + ":" + std::to_string(ep.port());
    self_ = shared_from_this();
    id_ = hub_.connect(*this, peer);
    read();
  }

  bool send(SharedBytes frame, FrameKind kind) override {
    if (closing_)
      return true;
    if (kind == FrameKind::kState) {
      if (states_queued_ >= max_frames_)
        return false;
      ++states_queued_;
    }
    queue_.push_back(std::move(frame));
    if (!writing_)
      write();
    return true;
  }

  void close() override {
    if (closing_)
      return;
    closing_ = true;
    in_hub_ = false;
    if (!writing_)
      finish_sending();
  }

 private:
  void read() {
    socket_.async_read_some(asio::buffer(buf_), [this, self = shared_from_this()](
                                                    boost::system::error_code ec, std::size_t n) {
      if (ec) {
        gone(ec);
        return;
      }
      if (in_hub_)
        hub_.receive(id_, std::span<const std::uint8_t>(buf_.data(), n));
      // Closing, the client's bytes are read and dropped until it closes too (finish_sending).
      if (!shut_)
        read();
    });
  }

  void write() {
    writing_ = true;
    // Everything queued goes out in one gathered write.
    batch_.assign(queue_.begin(), queue_.end());
    queue_.clear();
    states_queued_ = 0;
    buffers_.clear();
    for (const auto& f : batch_)
      buffers_.push_back(asio::buffer(*f));
    asio::async_write(socket_, buffers_,
                      [this, self = shared_from_this()](boost::system::error_code ec, std::size_t) {
                        writing_ = false;
                        batch_.clear();
                        if (ec) {
                          gone(ec);
                          return;
                        }
                        if (!queue_.empty())
                          write();
                        else if (closing_)
                          finish_sending();
                      });
  }

  /// The peer closed or the socket failed.
  void gone(const boost::system::error_code& ec) {
    if (in_hub_) {
      in_hub_ = false;
      if (ec != asio::error::eof)
        spdlog::info("client {}: {}", id_, ec.message());
      hub_.disconnect(id_);
    }
    closing_ = true;
    shut();
  }

  /// Everything queued (Closing last) is out: half-close, and close once the client has closed
  /// its end or after kLinger. Closing at once would reset the connection whenever the client's
  /// bytes are still unread (a client driving 1000 vehicles always has controls in flight), and
  /// a reset discards what the client has not read yet: Closing(scenario finished) with it.
  void finish_sending() {
    if (shut_ || half_closed_)
      return;
    half_closed_ = true;
    boost::system::error_code ignored;
    socket_.shutdown(tcp::socket::shutdown_send, ignored);
    linger_.expires_after(kLinger);
    linger_.async_wait([this, self = shared_from_this()](boost::system::error_code ec) {
      if (!ec)
        shut();
    });
  }

  void shut() {
    if (shut_)
      return;
    shut_ = true;
    linger_.cancel();
    // Dropping self_ may release the last reference: hold it until the function returns.
    const std::shared_ptr<TcpConnection> keep = std::move(self_);
    boost::system::error_code ignored;
    socket_.shutdown(tcp::socket::shutdown_both, ignored);
    socket_.close(ignored);
    queue_.clear();
  }

  tcp::socket socket_;
  Hub& hub_;
  std::size_t max_frames_;
  std::shared_ptr<std::size_t> live_;
  Hub::ClientId id_ = 0;
  /// A client's controls for one step come in one ControlsBatch (25 bytes a vehicle): read one
  /// in a single call.
  std::array<std::uint8_t, 64 * 1024> buf_{};
  std::deque<SharedBytes> queue_;
  std::size_t states_queued_ = 0;  ///< kState frames in queue_
  std::vector<SharedBytes> batch_;
  std::vector<asio::const_buffer> buffers_;
  bool writing_ = false;
  bool closing_ = false;
  bool half_closed_ = false;
  bool shut_ = false;
  static constexpr std::chrono::seconds kLinger{2};
  boost::asio::steady_timer linger_;
  bool in_hub_ = true;
  /// Keeps the connection alive while the hub knows it, even between I/O operations.
  std::shared_ptr<TcpConnection> self_;
};

TcpServer::TcpServer(asio::io_context& io, Hub& hub, TcpOptions options)
    : io_(io), hub_(hub), options_(std::move(options)), acceptor_(io) {
  const tcp::endpoint ep(asio::ip::make_address(options_.bind), options_.port);
  acceptor_.open(ep.protocol());
  acceptor_.set_option(tcp::acceptor::reuse_address(true));
  acceptor_.bind(ep);
  acceptor_.listen();
  accept();
}

TcpServer::~TcpServer() {
  stop();
  for (const auto& weak : connections_)
    if (const auto c = weak.lock())
      c->close_now();
}

std::uint16_t TcpServer::port() const {
  boost::system::error_code ec;
  return acceptor_.local_endpoint(ec).port();
}

void TcpServer::stop() {
  boost::system::error_code ignored;
  acceptor_.close(ignored);
}

void TcpServer::accept() {
  acceptor_.async_accept([this](boost::system::error_code ec, tcp::socket socket) {
    if (ec == asio::error::operation_aborted || !acceptor_.is_open())
      return;
    if (!ec) {
      std::erase_if(connections_, [](const auto& weak) { return weak.expired(); });
      auto c = std::make_shared<TcpConnection>(std::move(socket), hub_, options_.max_queued_frames,
                                               live_);
      connections_.push_back(c);
      c->start();
    } else {
      spdlog::warn("accept failed: {}", ec.message());
    }
    accept();
  });
}

}  // namespace tb::server
