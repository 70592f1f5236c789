#include "common/can/checksum.hpp"

#include <array>

namespace tb::can {
namespace {

constexpr std::array<std::uint8_t, 256> make_table() {
  std::array<std::uint8_t, 256> t{};
  for (unsigned i = 0; i < 256; ++i) {
    std::uint8_t c = static_cast<std::uint8_t>(i);
    for (int b = 0; b < 8; ++b)
      c = static_cast<std::uint8_t>((c & 0x80) ? (c << 1) ^ 0x1D : (c << 1));
    t[i] = c;
  }
  return t;
}
constexpr auto kTable = make_table();

}  // namespace

std::uint8_t crc8_sae_j1850(std::span<const std::uint8_t> bytes) {
  std::uint8_t crc = 0xFF;
  for (std::uint8_t b : bytes)
    crc = kTable[crc ^ b];
  return static_cast<std::uint8_t>(crc ^ 0xFF);
}

}  // namespace tb::can
