#pragma once
/// @file For the medium's unit tests: a FrameSink that keeps what reaches a station, and a
/// broadcast GeoNetworking-typed frame from station 1's MAC carrying one tag byte.

#include <cstdint>
#include <span>
#include <vector>

#include "network-emulator/radio/medium.hpp"

namespace tb::emu::radio::testing {

struct RecordingSink : FrameSink {
  void transmit(std::span<const std::uint8_t> frame) override {
    frames.emplace_back(frame.begin(), frame.end());
  }
  std::vector<std::vector<std::uint8_t>> frames;
};

inline std::vector<std::uint8_t> frame(std::uint8_t tag) {
  return {0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 2, 0, 0, 0, 0, 1, 0x89, 0x47, tag};
}

}  // namespace tb::emu::radio::testing
