#include "common/can/socketcan_bus.hpp"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

#include "common/can/netns.hpp"
#include "common/util/kernel_stamp.hpp"

namespace tb::can {

namespace {
std::error_code last_error() {
  return {errno, std::generic_category()};
}
}  // namespace

bool socketcan_available() {
  const int fd = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
  if (fd < 0)
    return false;
  ::close(fd);
  return true;
}

Expected<std::unique_ptr<SocketCanBus>, std::error_code> SocketCanBus::open(
    boost::asio::io_context& io, const std::string& interface, const std::string& netns) {
  int fd = -1;
  std::error_code ec;
  const std::error_code ns_ec = run_in_netns(netns, [&] {
    fd = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
    if (fd < 0) {
      ec = last_error();
      return;
    }
    const unsigned index = ::if_nametoindex(interface.c_str());
    if (index == 0) {
      ec = last_error();
      return;
    }
    sockaddr_can addr{};
    addr.can_family = AF_CAN;
    addr.can_ifindex = static_cast<int>(index);
    if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
      ec = last_error();
      return;
    }
    // Receive times from the kernel, and a count of frames dropped for a full socket buffer.
    const int on = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on);
    ::setsockopt(fd, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on);
  });
  if (ns_ec)
    ec = ns_ec;
  if (ec) {
    if (fd >= 0)
      ::close(fd);
    return Unexpected{ec};
  }
  return std::unique_ptr<SocketCanBus>(new SocketCanBus(io, fd));
}

SocketCanBus::SocketCanBus(boost::asio::io_context& io, int fd) : descriptor_(io, fd), fd_(fd) {}

SocketCanBus::~SocketCanBus() {
  if (backstop_)
    backstop_->cancel();
  if (released_)
    ::close(fd_);
}

std::error_code SocketCanBus::send(std::span<const CanFrame> frames) {
  for (const CanFrame& f : frames) {
    if (f.fd)
      return std::make_error_code(std::errc::not_supported);  // CAN_RAW_FD_FRAMES not enabled
    can_frame out{};
    out.can_id = f.can_id;
    out.can_dlc = std::min<std::uint8_t>(f.len, CAN_MAX_DLEN);
    std::memcpy(out.data, f.data.data(), out.can_dlc);
    const ssize_t n = ::write(fd_, &out, sizeof out);
    if (n < 0)
      return last_error();
    if (n != static_cast<ssize_t>(sizeof out))
      return std::make_error_code(std::errc::io_error);
  }
  return {};
}

void SocketCanBus::start_receive(FrameHandler handler) {
  handler_ = std::move(handler);
  wait_next();
}

void SocketCanBus::start_on_demand(FrameHandler handler, std::chrono::milliseconds backstop) {
  handler_ = std::move(handler);
  on_demand_ = true;
  backstop_period_ = backstop;
  backstop_ = std::make_unique<boost::asio::steady_timer>(descriptor_.get_executor());
  // A descriptor stays in the io_context's epoll set whether or not anyone waits on it, so each
  // frame (100 a second at the vehicle's dynamics rate) would wake the io thread for nothing
  // (issue 33, as UdpCanBus). release() takes it out; the socket is non-blocking already.
  if (!released_) {
    fd_ = descriptor_.release();
    released_ = true;
  }
  arm_backstop();
}

void SocketCanBus::arm_backstop() {
  backstop_->expires_after(backstop_period_);
  backstop_->async_wait([this](const boost::system::error_code& ec) {
    if (ec == boost::asio::error::operation_aborted)
      return;
    read_all();
    arm_backstop();
  });
}

std::size_t SocketCanBus::poll() {
  return on_demand_ ? read_all() : 0;
}

void SocketCanBus::wait_next() {
  descriptor_.async_wait(boost::asio::posix::stream_descriptor::wait_read,
                         [this](const boost::system::error_code& ec) {
                           if (ec == boost::asio::error::operation_aborted)
                             return;
                           if (!ec)
                             read_all();
                           wait_next();
                         });
}

std::size_t SocketCanBus::read_all() {
  // One recvmmsg takes what queued since the last read (a few frames at 100 Hz and a poll every
  // few ms) where a recvmsg per frame and one more for EAGAIN made several system calls. A
  // batch shorter than kReadBatch means the queue was empty when the kernel looked.
  static constexpr std::size_t kControl =
      CMSG_SPACE(sizeof(timespec)) + CMSG_SPACE(sizeof(std::uint32_t));
  std::array<can_frame, kReadBatch> in{};
  std::array<iovec, kReadBatch> iov{};
  std::array<mmsghdr, kReadBatch> msgs{};
  alignas(cmsghdr) std::array<std::array<char, kControl>, kReadBatch> control{};
  std::size_t frames = 0;
  for (;;) {
    for (std::size_t i = 0; i < kReadBatch; ++i) {
      iov[i] = {&in[i], sizeof in[i]};
      msgs[i] = {};
      msgs[i].msg_hdr.msg_iov = &iov[i];
      msgs[i].msg_hdr.msg_iovlen = 1;
      msgs[i].msg_hdr.msg_control = control[i].data();
      msgs[i].msg_hdr.msg_controllen = kControl;  // the kernel shrinks it to what it wrote
    }
    const int n = ::recvmmsg(fd_, msgs.data(), kReadBatch, MSG_DONTWAIT, nullptr);
    if (n <= 0)
      return frames;  // EAGAIN: drained
    ++stats_.reads;
    for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) {
      msghdr& m = msgs[i].msg_hdr;
      if (msgs[i].msg_len != sizeof(can_frame) || (m.msg_flags & MSG_TRUNC) != 0) {
        // CAN_RAW hands out whole struct can_frame only (no CAN_RAW_FD_FRAMES here).
        ++stats_.unexpected_size;
        continue;
      }
      for (cmsghdr* c = CMSG_FIRSTHDR(&m); c; c = CMSG_NXTHDR(&m, c)) {
        if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_RXQ_OVFL) {
          std::uint32_t dropped = 0;
          std::memcpy(&dropped, CMSG_DATA(c), sizeof dropped);
          dropped_ = dropped;
        }
      }
      CanFrame f;
      f.can_id = in[i].can_id;
      f.len = std::min<std::uint8_t>(in[i].can_dlc, CAN_MAX_DLEN);
      std::memcpy(f.data.data(), in[i].data, f.len);
      ++frames;
      ++stats_.frames;
      if (handler_)
        handler_(f, kernel_rx_unix_ns(m).value_or(0));
    }
    if (static_cast<std::size_t>(n) < kReadBatch)
      return frames;
  }
}

}  // namespace tb::can
