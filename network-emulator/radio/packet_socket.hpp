#pragma once
/// @file A raw AF_PACKET socket bound to one interface: the medium's end of a veth, and the
/// station's wlan0 in tests and the benchmark.

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>

#include "network-emulator/radio/frame_tag.hpp"
#include "network-emulator/radio/medium.hpp"

namespace tb::emu::radio {

/// Ethertype to capture: ETH_P_ALL for every frame, or one protocol such as
/// kEthertypeGeoNetworking (frame_tag.hpp).
inline constexpr std::uint16_t kEthertypeAll = 0x0003;

/// Blocking-free raw socket. Opened in the calling thread's network namespace.
class PacketSocket {
 public:
  /// @throws std::system_error naming the interface.
  PacketSocket(const std::string& ifname, std::uint16_t ethertype, int rcvbuf_bytes = 0);
  ~PacketSocket();
  PacketSocket(const PacketSocket&) = delete;
  PacketSocket& operator=(const PacketSocket&) = delete;

  int fd() const { return fd_; }
  int ifindex() const { return ifindex_; }
  const std::string& ifname() const { return ifname_; }
  /// Sends one whole Ethernet frame. Returns false (and errno) when the kernel refused it.
  bool send(std::span<const std::uint8_t> frame);
  /// Receives one frame that came in (never one this host sent) into @p buf; returns its
  /// length, 0 when nothing is waiting (and @p wait is false), -1 on error or when a frame did
  /// not fit.
  long receive(std::span<std::uint8_t> buf, bool wait = false);
  /// Gives up ownership of the descriptor (to Asio).
  int release();

 private:
  int fd_ = -1;
  int ifindex_ = 0;
  std::string ifname_;
};

/// The medium's port on one veth host end: frames read from it go to Medium::on_frame, frames
/// the medium hands to it are sent into the veth and come out of the station's wlan0.
class VethPort final : public FrameSink {
 public:
  VethPort(boost::asio::io_context& io, StationId id, const std::string& ifname,
           std::uint16_t ethertype, Medium& medium);
  void start();
  void transmit(std::span<const std::uint8_t> frame) override;

  std::uint64_t received() const { return received_; }
  std::uint64_t send_errors() const { return send_errors_; }
  std::uint64_t receive_errors() const { return receive_errors_; }

 private:
  void wait();
  void drain();

  StationId id_;
  PacketSocket socket_;
  boost::asio::posix::stream_descriptor descriptor_;
  Medium& medium_;
  std::vector<std::uint8_t> buffer_;
  std::uint64_t received_ = 0;
  std::uint64_t send_errors_ = 0;
  std::uint64_t receive_errors_ = 0;
};

}  // namespace tb::emu::radio
