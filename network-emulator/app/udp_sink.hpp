#pragma once
/// @file A DatagramSink on a connected, non-blocking UDP socket.

#include <memory>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>

#include "network-emulator/app/emulator.hpp"

namespace tb::emu {

class UdpSink final : public DatagramSink {
 public:
  /// Connecting lets the kernel report an absent receiver (ICMP unreachable) on a later send.
  /// A socket that cannot be made reports its error on every send, so that the station is
  /// paused like any other that is gone.
  UdpSink(boost::asio::io_context& io, const boost::asio::ip::udp::endpoint& peer,
          const std::string& netns);
  std::error_code send(std::span<const std::uint8_t> datagram) override;

 private:
  boost::asio::ip::udp::socket socket_;
  std::error_code open_error_;
};

}  // namespace tb::emu
