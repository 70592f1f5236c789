#include "network-emulator/app/udp_sink.hpp"

#include "common/can/netns.hpp"

namespace tb::emu {

UdpSink::UdpSink(boost::asio::io_context& io, const boost::asio::ip::udp::endpoint& peer,
                 const std::string& netns)
    : socket_(io) {
  const std::error_code ns_ec = tb::can::run_in_netns(netns, [&] {
    boost::system::error_code ec;
    socket_.open(peer.protocol(), ec);
    if (!ec)
      socket_.connect(peer, ec);
    if (!ec)
      socket_.non_blocking(true, ec);
    open_error_ = ec;
  });
  if (ns_ec)
    open_error_ = ns_ec;
}

std::error_code UdpSink::send(std::span<const std::uint8_t> datagram) {
  if (open_error_)
    return open_error_;
  boost::system::error_code ec;
  socket_.send(boost::asio::buffer(datagram.data(), datagram.size()), 0, ec);
  return ec;
}

}  // namespace tb::emu
