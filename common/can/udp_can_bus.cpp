#include "common/can/udp_can_bus.hpp"

#include <sys/socket.h>
#include <sys/uio.h>
#include <unistd.h>

#include <array>
#include <chrono>

namespace tb::can {

namespace {
std::int64_t now_unix_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}
}  // namespace

std::unique_ptr<UdpCanBus> UdpCanBus::connect(boost::asio::io_context& io,
                                              const udp::endpoint& peer) {
  udp::socket s(io, peer.protocol());
  s.connect(peer);
  s.non_blocking(true);
  return std::unique_ptr<UdpCanBus>(new UdpCanBus(std::move(s)));
}

std::unique_ptr<UdpCanBus> UdpCanBus::bind(boost::asio::io_context& io,
                                           const udp::endpoint& local) {
  udp::socket s(io, local.protocol());
  s.set_option(udp::socket::reuse_address(true));
  s.bind(local);
  return std::unique_ptr<UdpCanBus>(new UdpCanBus(std::move(s)));
}

std::error_code UdpCanBus::send(std::span<const CanFrame> frames) {
  while (!frames.empty()) {
    // Greedily take frames while the datagram stays under kMaxDatagram.
    std::size_t n = 0, size = kCannelloniHeaderSize;
    while (n < frames.size()) {
      const std::size_t next = cannelloni_size(frames.subspan(n, 1)) - kCannelloniHeaderSize;
      if (size + next > kMaxDatagram && n > 0)
        break;
      size += next;
      ++n;
    }
    const std::size_t len = encode_cannelloni(tx_sequence_, frames.first(n), tx_buffer_);
    if (len == 0)
      return std::make_error_code(std::errc::message_size);
    boost::system::error_code ec;
    socket_.send(boost::asio::buffer(tx_buffer_.data(), len), 0, ec);
    if (ec)
      return ec;
    ++tx_sequence_;
    frames = frames.subspan(n);
  }
  return {};
}

void UdpCanBus::start_receive(FrameHandler handler) {
  handler_ = std::move(handler);
  receive_next();
}

UdpCanBus::~UdpCanBus() {
  if (on_demand_fd_ >= 0)
    ::close(on_demand_fd_);
}

void UdpCanBus::start_on_demand(FrameHandler handler, std::chrono::milliseconds backstop) {
  handler_ = std::move(handler);
  on_demand_ = true;
  backstop_period_ = backstop;
  backstop_ = std::make_unique<boost::asio::steady_timer>(socket_.get_executor());
  // An asio socket stays in its io_context's epoll set (edge-triggered, EPOLLIN) whether or not
  // anyone waits on it, so every datagram still woke the thread for nothing: 100 empty
  // wake-ups a second at 100 Hz, two thirds of a full station's (issue 33). poll() needs none of
  // asio, so the socket leaves the io_context (release() removes it from the set).
  if (on_demand_fd_ < 0)
    on_demand_fd_ = socket_.release();  // poll() reads with MSG_DONTWAIT
  arm_backstop();
}

void UdpCanBus::arm_backstop() {
  backstop_->expires_after(backstop_period_);
  backstop_->async_wait([this](const boost::system::error_code& ec) {
    if (ec == boost::asio::error::operation_aborted)
      return;
    poll();
    arm_backstop();
  });
}

std::size_t UdpCanBus::poll() {
  if (!on_demand_)
    return 0;
  // One recvmmsg takes what queued since the last poll (2–3 datagrams at 100 Hz and a poll
  // every few ms), where a recvfrom per datagram and one more for EAGAIN made 3–4 system calls
  // (issue 33). A batch shorter than kPollBatch means the queue was empty when the kernel
  // looked; what arrives after waits for the next poll, as before.
  std::array<mmsghdr, kPollBatch> msgs{};
  std::array<iovec, kPollBatch> iov{};
  for (std::size_t i = 0; i < kPollBatch; ++i) {
    iov[i] = {rx_buffer_.data() + i * kPollSlot, kPollSlot};
    msgs[i].msg_hdr.msg_iov = &iov[i];
    msgs[i].msg_hdr.msg_iovlen = 1;
  }
  std::size_t packets = 0;
  for (;;) {
    const int n = ::recvmmsg(on_demand_fd_, msgs.data(), kPollBatch, MSG_DONTWAIT, nullptr);
    // EAGAIN: all read. Any other error (an ICMP error queued on the socket) is consumed by
    // the failed read; the next poll reads on.
    if (n <= 0)
      return packets;
    for (int i = 0; i < n; ++i) {
      const auto& h = msgs[static_cast<std::size_t>(i)];
      if ((h.msg_hdr.msg_flags & MSG_TRUNC) != 0) {
        // Longer than a slot (4 KiB; kMaxDatagram is 1400): not a datagram of ours.
        ++stats_.malformed;
        stats_.last_error = CannelloniError::kTruncatedFrame;
        continue;
      }
      on_packet(rx_buffer_.data() + static_cast<std::size_t>(i) * kPollSlot, h.msg_len);
      ++packets;
    }
    if (static_cast<std::size_t>(n) < kPollBatch)
      return packets;
  }
}

void UdpCanBus::receive_next() {
  socket_.async_receive_from(boost::asio::buffer(rx_buffer_), rx_from_,
                             [this](const boost::system::error_code& ec, std::size_t n) {
                               if (ec == boost::asio::error::operation_aborted)
                                 return;
                               if (!ec)
                                 on_packet(rx_buffer_.data(), n);
                               receive_next();
                             });
}

void UdpCanBus::on_packet(const std::uint8_t* data, std::size_t n) {
  const std::int64_t rx = now_unix_ns();
  auto packet = decode_cannelloni({data, n});
  if (!packet) {
    ++stats_.malformed;
    stats_.last_error = packet.error();
    return;
  }
  ++stats_.packets;
  if (rx_last_sequence_) {
    const auto expected = static_cast<std::uint8_t>(*rx_last_sequence_ + 1);
    const auto missing = static_cast<std::uint8_t>(packet->sequence - expected);
    // A packet that arrives late looks like a gap of almost 256; count only forward jumps.
    if (missing < 128)
      stats_.sequence_gaps += missing;
  }
  rx_last_sequence_ = packet->sequence;
  for (const CanFrame& f : packet->frames) {
    ++stats_.frames;
    if (handler_)
      handler_(f, rx);
  }
}

}  // namespace tb::can
