#pragma once
/// @file Reads the frames of a little-endian pcapng file (Enhanced Packet Blocks), for tests
/// that replay captures of other stacks.

#include <cstdint>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace tb::its::security::test {

inline std::vector<std::vector<std::uint8_t>> read_pcapng(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw std::runtime_error("cannot open " + path);
  const std::vector<std::uint8_t> f((std::istreambuf_iterator<char>(in)),
                                    std::istreambuf_iterator<char>());
  auto u32 = [&](std::size_t at) {
    if (at + 4 > f.size())
      throw std::runtime_error(path + ": truncated block at " + std::to_string(at));
    return std::uint32_t{f[at]} | std::uint32_t{f[at + 1]} << 8 | std::uint32_t{f[at + 2]} << 16 |
           std::uint32_t{f[at + 3]} << 24;
  };
  std::vector<std::vector<std::uint8_t>> frames;
  std::size_t at = 0;
  while (at + 12 <= f.size()) {
    const std::uint32_t type = u32(at);
    const std::uint32_t len = u32(at + 4);
    if (len < 12 || at + len > f.size())
      throw std::runtime_error(path + ": bad block length at " + std::to_string(at));
    if (type == 6) {  // Enhanced Packet Block: if, ts hi, ts lo, captured, original, data
      const std::uint32_t cap = u32(at + 20);
      if (28 + cap > len)
        throw std::runtime_error(path + ": bad captured length at " + std::to_string(at));
      frames.emplace_back(f.begin() + static_cast<std::ptrdiff_t>(at + 28),
                          f.begin() + static_cast<std::ptrdiff_t>(at + 28 + cap));
    }
    at += len;
  }
  return frames;
}

}  // namespace tb::its::security::test
