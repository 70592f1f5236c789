#include "common/can/socketcan_bus.hpp"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "common/can/netns.hpp"

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
    ::setsockopt(fd, SOL_SOCKET, SO_TIMESTAMP, &on, sizeof on);
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

SocketCanBus::SocketCanBus(boost::asio::io_context& io, int fd) : descriptor_(io, fd) {}

SocketCanBus::~SocketCanBus() = default;

std::error_code SocketCanBus::send(std::span<const CanFrame> frames) {
  for (const CanFrame& f : frames) {
    if (f.fd)
      return std::make_error_code(std::errc::not_supported);  // CAN_RAW_FD_FRAMES not enabled
    can_frame out{};
    out.can_id = f.can_id;
    out.can_dlc = std::min<std::uint8_t>(f.len, CAN_MAX_DLEN);
    std::memcpy(out.data, f.data.data(), out.can_dlc);
    const ssize_t n = ::write(descriptor_.native_handle(), &out, sizeof out);
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
  std::size_t frames = 0;
  for (;;) {
    can_frame in{};
    iovec iov{&in, sizeof in};
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timeval)) + CMSG_SPACE(sizeof(std::uint32_t))];
    msghdr msg{};
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = sizeof control;
    const ssize_t n = ::recvmsg(descriptor_.native_handle(), &msg, MSG_DONTWAIT);
    if (n < static_cast<ssize_t>(sizeof in))
      return frames;  // EAGAIN: drained (or a short read, which CAN_RAW never produces)
    std::int64_t rx_ns = 0;
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c; c = CMSG_NXTHDR(&msg, c)) {
      if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_TIMESTAMP) {
        timeval tv{};
        std::memcpy(&tv, CMSG_DATA(c), sizeof tv);
        rx_ns = std::int64_t{tv.tv_sec} * 1'000'000'000 + std::int64_t{tv.tv_usec} * 1000;
      } else if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_RXQ_OVFL) {
        std::uint32_t dropped = 0;
        std::memcpy(&dropped, CMSG_DATA(c), sizeof dropped);
        dropped_ = dropped;
      }
    }
    CanFrame f;
    f.can_id = in.can_id;
    f.len = std::min<std::uint8_t>(in.can_dlc, CAN_MAX_DLEN);
    std::memcpy(f.data.data(), in.data, f.len);
    ++frames;
    if (handler_)
      handler_(f, rx_ns);
  }
}

}  // namespace tb::can
