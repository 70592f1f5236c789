#pragma once
/// @file A raw AF_PACKET socket bound to one interface: a station's wlan0 in radio-probe, the
/// tests and the benchmark.

#include <cstdint>
#include <span>
#include <string>

#include "network-emulator/radio/frame_tag.hpp"

namespace tb::emu::radio {

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

}  // namespace tb::emu::radio
