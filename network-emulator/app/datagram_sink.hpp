#pragma once
/// @file Where the emulator's UDP feeds go: one datagram at a time, never blocking.

#include <cstdint>
#include <span>
#include <system_error>

namespace tb::emu {

/// Sends one datagram without blocking.
class DatagramSink {
 public:
  virtual ~DatagramSink() = default;
  virtual std::error_code send(std::span<const std::uint8_t> datagram) = 0;
};

}  // namespace tb::emu
