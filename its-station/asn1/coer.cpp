#include "its-station/asn1/coer.hpp"

#include <bit>

namespace tb::its::asn1 {
namespace {

unsigned unsigned_octets(std::uint64_t v) {
  return v == 0 ? 1u : static_cast<unsigned>((std::bit_width(v) + 7) / 8);
}

unsigned signed_octets(std::int64_t v) {
  // Fewest octets whose two's complement holds v: the sign bit of the top octet must match.
  unsigned n = 1;
  while (n < 8) {
    const std::int64_t lo = -(std::int64_t{1} << (8 * n - 1));
    const std::int64_t hi = (std::int64_t{1} << (8 * n - 1)) - 1;
    if (v >= lo && v <= hi)
      break;
    ++n;
  }
  return n;
}

}  // namespace

void CoerWriter::length(std::size_t n) {
  if (n < 128) {
    u8(static_cast<std::uint8_t>(n));
    return;
  }
  const unsigned k = unsigned_octets(n);
  u8(static_cast<std::uint8_t>(0x80 | k));
  be(n, k);
}

void CoerWriter::unsigned_integer(std::uint64_t v) {
  const unsigned k = unsigned_octets(v);
  length(k);
  be(v, k);
}

void CoerWriter::signed_integer(std::int64_t v) {
  const unsigned k = signed_octets(v);
  length(k);
  be(static_cast<std::uint64_t>(v), k);
}

void CoerWriter::preamble(bool extensible, bool extensions_present, std::uint32_t flags,
                          unsigned count) {
  const unsigned bits = count + (extensible ? 1 : 0);
  if (bits == 0)
    return;
  std::uint64_t all = flags & ((std::uint64_t{1} << count) - 1);
  if (extensible)
    all |= std::uint64_t{extensions_present ? 1u : 0u} << count;
  const unsigned octets = (bits + 7) / 8;
  be(all << (octets * 8 - bits), octets);
}

void CoerWriter::extension_bitmap(std::uint32_t flags, unsigned count) {
  const unsigned octets = (count + 7) / 8;
  length(octets + 1);
  const unsigned unused = octets * 8 - count;
  u8(static_cast<std::uint8_t>(unused));
  be(static_cast<std::uint64_t>(flags & ((std::uint64_t{1} << count) - 1)) << unused, octets);
}

std::size_t CoerReader::length(const char* field) {
  const std::uint8_t first = u8(field);
  if (failed_)
    return 0;
  std::size_t n = first;
  if (first >= 0x80) {
    const unsigned k = first & 0x7f;
    // X.696 8.6.5: the fewest octets, and the long form only from 128 on.
    if (k == 0 || k > 4) {
      fail(Error::kValueOutOfRange, field, first);
      return 0;
    }
    if (remaining() >= 1 && in_[pos_] == 0) {
      fail(Error::kValueOutOfRange, field, 0);
      return 0;
    }
    n = static_cast<std::size_t>(be(k, field));
    if (!failed_ && n < 128) {
      fail(Error::kValueOutOfRange, field, static_cast<std::int64_t>(n));
      return 0;
    }
  }
  if (!failed_ && n > remaining()) {
    fail(Error::kTruncated, field, static_cast<std::int64_t>(n));
    return 0;
  }
  return failed_ ? 0 : n;
}

std::uint64_t CoerReader::unsigned_integer(const char* field) {
  const std::size_t k = length(field);
  if (failed_)
    return 0;
  if (k == 0 || k > 8) {
    fail(Error::kValueOutOfRange, field, static_cast<std::int64_t>(k));
    return 0;
  }
  if (k > 1 && in_[pos_] == 0) {
    fail(Error::kValueOutOfRange, field, 0);  // a leading zero octet: not canonical
    return 0;
  }
  return be(static_cast<unsigned>(k), field);
}

std::int64_t CoerReader::signed_integer(const char* field) {
  const std::size_t k = length(field);
  if (failed_)
    return 0;
  if (k == 0 || k > 8) {
    fail(Error::kValueOutOfRange, field, static_cast<std::int64_t>(k));
    return 0;
  }
  const auto raw = be(static_cast<unsigned>(k), field);
  const unsigned shift = 64 - 8 * static_cast<unsigned>(k);
  const auto v = shift == 0 ? static_cast<std::int64_t>(raw)
                            : static_cast<std::int64_t>(raw << shift) >> shift;
  if (signed_octets(v) != k)
    fail(Error::kValueOutOfRange, field, v);  // more octets than the value needs
  return v;
}

unsigned CoerReader::enumerated(unsigned max, const char* field) {
  const std::uint8_t v = u8(field);
  if (failed_)
    return 0;
  if (v >= 0x80) {
    fail(Error::kValueOutOfRange, field, v);
    return 0;
  }
  if (v > max) {
    fail(Error::kUnknownExtension, field, v);
    return 0;
  }
  return v;
}

unsigned CoerReader::choice_tag(const char* field) {
  const std::uint8_t t = u8(field);
  if (failed_)
    return 0;
  if ((t & 0xc0) != 0x80 || (t & 0x3f) == 0x3f) {
    fail(Error::kValueOutOfRange, field, t);
    return 0;
  }
  return t & 0x3fu;
}

std::uint32_t CoerReader::preamble(bool extensible, bool* extensions, unsigned count,
                                   const char* field) {
  const unsigned bits = count + (extensible ? 1 : 0);
  if (extensions != nullptr)
    *extensions = false;
  if (bits == 0)
    return 0;
  const unsigned octets = (bits + 7) / 8;
  const std::uint64_t all = be(octets, field);
  if (failed_)
    return 0;
  const unsigned pad = octets * 8 - bits;
  if ((all & ((std::uint64_t{1} << pad) - 1)) != 0) {
    fail(Error::kValueOutOfRange, field, static_cast<std::int64_t>(all));
    return 0;
  }
  const std::uint64_t v = all >> pad;
  if (extensions != nullptr && extensible)
    *extensions = ((v >> count) & 1) != 0;
  return static_cast<std::uint32_t>(v & ((std::uint64_t{1} << count) - 1));
}

std::size_t CoerReader::quantity(const char* field) {
  const std::uint64_t n = unsigned_integer(field);
  // Every element of a 1609.2 SEQUENCE OF takes at least one octet.
  if (!failed_ && n > remaining()) {
    fail(Error::kSizeOutOfRange, field, static_cast<std::int64_t>(n));
    return 0;
  }
  return failed_ ? 0 : static_cast<std::size_t>(n);
}

std::span<const std::uint8_t> CoerReader::octets(std::size_t n, const char* field) {
  if (failed_)
    return {};
  if (remaining() < n) {
    fail(Error::kTruncated, field, static_cast<std::int64_t>(n));
    return {};
  }
  auto b = in_.subspan(pos_, n);
  pos_ += n;
  return b;
}

std::uint32_t CoerReader::extension_bitmap(unsigned known, std::size_t* total_present,
                                           const char* field) {
  *total_present = 0;
  const std::size_t len = length(field);
  if (failed_)
    return 0;
  if (len < 2) {
    fail(Error::kSizeOutOfRange, field, static_cast<std::int64_t>(len));
    return 0;
  }
  const std::uint8_t unused = u8(field);
  if (unused > 7) {
    fail(Error::kValueOutOfRange, field, unused);
    return 0;
  }
  auto bits = octets(len - 1, field);
  if (failed_)
    return 0;
  const std::size_t nbits = bits.size() * 8 - unused;
  std::uint32_t flags = 0;
  for (std::size_t i = 0; i < nbits; ++i) {
    const bool set = ((bits[i / 8] >> (7 - i % 8)) & 1) != 0;
    if (!set)
      continue;
    ++*total_present;
    if (i < known)
      flags |= std::uint32_t{1} << (known - 1 - i);
  }
  // X.696 16.4: the unused trailing bits are zero.
  if (unused != 0 && (bits.back() & ((1u << unused) - 1)) != 0)
    fail(Error::kValueOutOfRange, field, bits.back());
  return flags;
}

}  // namespace tb::its::asn1
