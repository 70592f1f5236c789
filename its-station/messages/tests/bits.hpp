#pragma once
/// @file Editing encoded messages bit by bit, to build malformed and extended inputs from the
/// golden vectors.

#include <cstdint>
#include <string>
#include <vector>

namespace tb::its::messages::testing {

inline std::string to_bits(const std::vector<std::uint8_t>& bytes) {
  std::string s;
  for (std::uint8_t b : bytes)
    for (int i = 7; i >= 0; --i)
      s += ((b >> i) & 1) ? '1' : '0';
  return s;
}

/// Packs a '0'/'1' string, padding the last octet with zeros.
inline std::vector<std::uint8_t> from_bits(const std::string& s) {
  std::vector<std::uint8_t> out((s.size() + 7) / 8);
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s[i] == '1')
      out[i / 8] |= static_cast<std::uint8_t>(0x80 >> (i % 8));
  return out;
}

inline std::string bits_of(std::uint64_t v, unsigned width) {
  std::string s;
  for (unsigned i = width; i-- > 0;)
    s += ((v >> i) & 1) ? '1' : '0';
  return s;
}

/// Overwrites @p width bits at @p offset with @p value.
inline std::vector<std::uint8_t> with_bits(const std::vector<std::uint8_t>& bytes,
                                           std::size_t offset, unsigned width,
                                           std::uint64_t value) {
  std::string s = to_bits(bytes);
  s.replace(offset, width, bits_of(value, width));
  return from_bits(s);
}

}  // namespace tb::its::messages::testing
