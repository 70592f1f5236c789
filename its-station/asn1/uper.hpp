#pragma once
/// @file Bit-level writer and reader for ASN.1 unaligned PER (ITU-T X.691, "UPER").
///
/// Both are cursors over a caller-provided buffer with a sticky error: the first failure
/// (end of input, value outside its constraint, output full) is recorded with the field name
/// passed to the call and the bit offset, later calls do nothing, and the message codec checks
/// ok() when it is done. Every read is bounds checked; nothing allocates.
///
/// Constraints known at compile time go through the template forms (put_constrained<Lb, Ub>),
/// so that the field width is a constant.

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

#include "its-station/asn1/error.hpp"

namespace tb::its::asn1 {

/// Bits of a constrained whole number with @p range = ub - lb + 1 values (X.691 11.5.7.1:
/// the minimum number of bits to hold range - 1; none for a single value).
constexpr unsigned bits_for_range(std::uint64_t range) {
  return range <= 1 ? 0u : static_cast<unsigned>(std::bit_width(range - 1));
}
template <std::int64_t Lb, std::int64_t Ub>
inline constexpr unsigned kConstrainedBits = bits_for_range(static_cast<std::uint64_t>(Ub) -
                                                            static_cast<std::uint64_t>(Lb) + 1);

/// Longest length determinant handled: X.691 11.9.3.8 fragments lengths of 16K and more, which
/// no CAM or DENM component reaches.
inline constexpr std::size_t kMaxUnfragmentedLength = 16383;

class UperWriter {
 public:
  explicit UperWriter(std::span<std::uint8_t> out) : out_(out) {}

  /// Appends the @p n (0..64) low bits of @p v, most significant first.
  void put_bits(std::uint64_t v, unsigned n) {
    if (n == 0 || failed_)
      return;
    if (n < 64)
      v &= (std::uint64_t{1} << n) - 1;
    const unsigned free = 64 - fill_;  // 1..64: fill_ is never 64 between calls
    if (n < free) {
      acc_ |= v << (free - n);
      fill_ += n;
      return;
    }
    const unsigned rest = n - free;  // 0..63
    acc_ |= v >> rest;
    flush_word();
    acc_ = rest == 0 ? 0 : v << (64 - rest);
    fill_ = rest;
  }
  void put_bool(bool b) { put_bits(b ? 1 : 0, 1); }

  /// X.691 11.5.6 / 13.2.2: value - lb in the minimum bits for the range. Fails with
  /// kValueOutOfRange outside lb..ub.
  template <std::int64_t Lb, std::int64_t Ub>
  void put_constrained(std::int64_t v, const char* field) {
    static_assert(Lb <= Ub);
    if (v < Lb || v > Ub) {
      fail(Error::kValueOutOfRange, field, v);
      return;
    }
    put_bits(static_cast<std::uint64_t>(v) - static_cast<std::uint64_t>(Lb),
             kConstrainedBits<Lb, Ub>);
  }
  void put_constrained(std::int64_t v, std::int64_t lb, std::int64_t ub, const char* field) {
    if (v < lb || v > ub) {
      fail(Error::kValueOutOfRange, field, v);
      return;
    }
    put_bits(static_cast<std::uint64_t>(v) - static_cast<std::uint64_t>(lb),
             bits_for_range(static_cast<std::uint64_t>(ub) - static_cast<std::uint64_t>(lb) + 1));
  }

  /// An integer with an extensible constraint (lb..ub, ...), X.691 13.1: a bit saying whether
  /// the value is outside the root, then the root encoding or an unconstrained whole number.
  template <std::int64_t Lb, std::int64_t Ub>
  void put_constrained_ext(std::int64_t v, const char* field) {
    if (v >= Lb && v <= Ub) {
      put_bool(false);
      put_constrained<Lb, Ub>(v, field);
    } else {
      put_bool(true);
      put_unconstrained(v);
    }
  }

  /// X.691 11.9.4.1 with 11.9.3.5-7 (unaligned, no upper bound): 8 bits for n < 128, 16 bits
  /// (10 + 14-bit n) for n < 16384.
  void put_length(std::size_t n, const char* field) {
    if (n < 128) {
      put_bits(n, 8);
    } else if (n <= kMaxUnfragmentedLength) {
      put_bits(0x8000 | n, 16);
    } else {
      fail(Error::kUnsupported, field, static_cast<std::int64_t>(n));
    }
  }

  /// X.691 11.6: normally small non-negative whole number (choice/enumeration extension index).
  void put_normally_small(std::uint64_t n) {
    if (n < 64) {
      put_bits(n, 7);  // leading 0 then 6 bits
    } else {
      put_bool(true);
      put_semi_constrained(n, 0);
    }
  }

  /// X.691 11.7 + 13.2.3: semi-constrained (lb..MAX): length in octets, then value - lb in that
  /// many octets.
  void put_semi_constrained(std::uint64_t v, std::uint64_t lb) {
    const std::uint64_t off = v - lb;
    const unsigned octets = off == 0 ? 1 : (static_cast<unsigned>(std::bit_width(off)) + 7) / 8;
    put_length(octets, "");
    put_bits(off, octets * 8);
  }
  /// X.691 11.8 + 13.2.4: unconstrained: length in octets, then two's complement.
  void put_unconstrained(std::int64_t v) {
    unsigned octets = 1;
    while (octets < 8) {
      const std::int64_t lo = -(std::int64_t{1} << (octets * 8 - 1));
      const std::int64_t hi = (std::int64_t{1} << (octets * 8 - 1)) - 1;
      if (v >= lo && v <= hi)
        break;
      ++octets;
    }
    put_length(octets, "");
    put_bits(static_cast<std::uint64_t>(v), octets * 8);
  }

  /// X.691 14.2/14.3: index of a root enumeration of @p root_count values; with an extension
  /// marker, a leading 0 bit (only root values are written here).
  void put_enumerated(unsigned index, unsigned root_count, bool extensible, const char* field) {
    if (index >= root_count) {
      fail(Error::kValueOutOfRange, field, index);
      return;
    }
    if (extensible)
      put_bool(false);
    put_bits(index, bits_for_range(root_count));
  }

  void put_octets(std::span<const std::uint8_t> bytes) {
    for (std::uint8_t b : bytes)
      put_bits(b, 8);
  }

  /// Pads with zero bits to a whole octet and returns the octets written (X.691 11.1: a
  /// complete encoding is at least one octet), or 0 when failed.
  std::size_t finish() {
    if (failed_)
      return 0;
    if (pos_ == 0 && fill_ == 0)
      put_bits(0, 8);
    const unsigned bytes = (fill_ + 7) / 8;
    if (pos_ + bytes > out_.size()) {
      fail(Error::kBufferTooSmall, "output", static_cast<std::int64_t>(pos_ + bytes));
      return 0;
    }
    for (unsigned i = 0; i < bytes; ++i)
      out_[pos_ + i] = static_cast<std::uint8_t>(acc_ >> (56 - 8 * i));
    pos_ += bytes;
    acc_ = 0;
    fill_ = 0;
    return pos_;
  }

  std::size_t bit_position() const { return pos_ * 8 + fill_; }
  bool ok() const { return !failed_; }
  const CodecError& error() const { return error_; }

  void fail(Error code, const char* field, std::int64_t value) {
    if (failed_)
      return;
    failed_ = true;
    error_ = CodecError{code, field, value, bit_position()};
  }

 private:
  void flush_word() {
    if (pos_ + 8 > out_.size()) {
      fill_ = 0;  // keep bit_position() meaningful for the error
      fail(Error::kBufferTooSmall, "output", static_cast<std::int64_t>(pos_ + 8));
      return;
    }
    const std::uint64_t be = std::endian::native == std::endian::little ? byteswap(acc_) : acc_;
    std::memcpy(out_.data() + pos_, &be, 8);
    pos_ += 8;
  }
  static std::uint64_t byteswap(std::uint64_t v) { return __builtin_bswap64(v); }

  std::span<std::uint8_t> out_;
  std::size_t pos_ = 0;    // whole octets written to out_
  std::uint64_t acc_ = 0;  // pending bits, left-aligned
  unsigned fill_ = 0;      // pending bit count, 0..63
  bool failed_ = false;
  CodecError error_{};
};

class UperReader {
 public:
  explicit UperReader(std::span<const std::uint8_t> in) : in_(in), size_bits_(in.size() * 8) {}

  /// Reads @p n (0..64) bits, most significant first; 0 after any failure.
  std::uint64_t get_bits(unsigned n, const char* field) {
    if (n == 0 || failed_)
      return 0;
    if (n > size_bits_ - pos_) {
      fail(Error::kTruncated, field, 0);
      return 0;
    }
    const std::size_t byte = pos_ >> 3;
    const unsigned off = static_cast<unsigned>(pos_ & 7);
    std::uint64_t r;
    if (off + n <= 64 && byte + 8 <= in_.size()) {
      std::uint64_t w;
      std::memcpy(&w, in_.data() + byte, 8);
      if constexpr (std::endian::native == std::endian::little)
        w = __builtin_bswap64(w);
      r = (w << off) >> (64 - n);
    } else {
      r = slow_bits(n);
    }
    pos_ += n;
    return r;
  }
  bool get_bool(const char* field) { return get_bits(1, field) != 0; }

  template <std::int64_t Lb, std::int64_t Ub>
  std::int64_t get_constrained(const char* field) {
    static_assert(Lb <= Ub);
    const std::size_t at = pos_;
    const std::uint64_t off = get_bits(kConstrainedBits<Lb, Ub>, field);
    // A field whose width holds more values than the range can carry an out-of-range value.
    if (off > static_cast<std::uint64_t>(Ub) - static_cast<std::uint64_t>(Lb)) {
      fail_at(Error::kValueOutOfRange, field,
              static_cast<std::int64_t>(off + static_cast<std::uint64_t>(Lb)), at);
      return Lb;
    }
    return static_cast<std::int64_t>(off + static_cast<std::uint64_t>(Lb));
  }
  std::int64_t get_constrained(std::int64_t lb, std::int64_t ub, const char* field) {
    const std::size_t at = pos_;
    const std::uint64_t range = static_cast<std::uint64_t>(ub) - static_cast<std::uint64_t>(lb);
    const std::uint64_t off = get_bits(bits_for_range(range + 1), field);
    if (off > range) {
      fail_at(Error::kValueOutOfRange, field,
              static_cast<std::int64_t>(off + static_cast<std::uint64_t>(lb)), at);
      return lb;
    }
    return static_cast<std::int64_t>(off + static_cast<std::uint64_t>(lb));
  }

  /// (lb..ub, ...): a value outside the root is decoded and reported as kUnknownExtension, since
  /// the message types here hold only root values.
  template <std::int64_t Lb, std::int64_t Ub>
  std::int64_t get_constrained_ext(const char* field) {
    const std::size_t at = pos_;
    if (get_bool(field)) {
      const std::int64_t v = get_unconstrained(field);
      if (!failed_)
        fail_at(Error::kUnknownExtension, field, v, at);
      return Lb;
    }
    return get_constrained<Lb, Ub>(field);
  }

  /// X.691 11.9.3.5-8 (unaligned, no upper bound); fragmented lengths are kUnsupported.
  std::size_t get_length(const char* field) {
    const std::size_t at = pos_;
    if (!get_bool(field))
      return get_bits(7, field);
    if (!get_bool(field))
      return get_bits(14, field);
    fail_at(Error::kUnsupported, field, static_cast<std::int64_t>(get_bits(6, field)), at);
    return 0;
  }

  /// X.691 11.6.
  std::uint64_t get_normally_small(const char* field) {
    if (!get_bool(field))
      return get_bits(6, field);
    return get_semi_constrained(0, field);
  }

  /// X.691 13.2.3; values wider than 64 bits are kValueOutOfRange.
  std::uint64_t get_semi_constrained(std::uint64_t lb, const char* field) {
    const std::size_t at = pos_;
    const std::size_t octets = get_length(field);
    if (failed_)
      return lb;
    if (octets == 0 || octets > 8) {
      fail_at(Error::kValueOutOfRange, field, static_cast<std::int64_t>(octets), at);
      return lb;
    }
    return lb + get_bits(static_cast<unsigned>(octets * 8), field);
  }
  /// X.691 13.2.4; values wider than 64 bits are kValueOutOfRange.
  std::int64_t get_unconstrained(const char* field) {
    const std::size_t at = pos_;
    const std::size_t octets = get_length(field);
    if (failed_)
      return 0;
    if (octets == 0 || octets > 8) {
      fail_at(Error::kValueOutOfRange, field, static_cast<std::int64_t>(octets), at);
      return 0;
    }
    const unsigned n = static_cast<unsigned>(octets * 8);
    std::uint64_t raw = get_bits(n, field);
    if (n < 64 && (raw >> (n - 1)) != 0)  // sign-extend
      raw |= ~std::uint64_t{0} << n;
    return static_cast<std::int64_t>(raw);
  }

  /// X.691 14: the root index of an enumeration; an extension value is kUnknownExtension.
  unsigned get_enumerated(unsigned root_count, bool extensible, const char* field) {
    const std::size_t at = pos_;
    if (extensible && get_bool(field)) {
      const std::uint64_t ext = get_normally_small(field);
      if (!failed_)
        fail_at(Error::kUnknownExtension, field, static_cast<std::int64_t>(ext), at);
      return 0;
    }
    return static_cast<unsigned>(
        get_constrained(0, static_cast<std::int64_t>(root_count) - 1, field));
  }

  /// X.691 19.7-19.9: after the root components of an extensible SEQUENCE whose extension bit
  /// was set, reads the presence bitmap of the extension additions and skips every present one
  /// (each an open type: length + octets), as a decoder of an earlier version does.
  void skip_sequence_extensions(const char* field) {
    // 11.9.3.4 "normally small length": bit 0 then n-1 in 6 bits for n <= 64.
    const std::size_t at = pos_;
    std::uint64_t count;
    if (!get_bool(field)) {
      count = get_bits(6, field) + 1;
    } else {
      count = get_length(field);
      if (!failed_ && count == 0) {
        fail_at(Error::kSizeOutOfRange, field, 0, at);
        return;
      }
    }
    if (failed_)
      return;
    // The bitmap can be long in hostile input: read it in pieces and skip each open type
    // only after the whole bitmap, as the encoding orders them.
    std::size_t present = 0;
    for (std::uint64_t left = count; left > 0 && !failed_;) {
      const unsigned chunk = left > 64 ? 64u : static_cast<unsigned>(left);
      present += static_cast<std::size_t>(std::popcount(get_bits(chunk, field)));
      left -= chunk;
    }
    for (std::size_t i = 0; i < present && !failed_; ++i)
      skip_open_type(field);
  }

  /// X.691 11.2: an open type field (length determinant + that many octets), skipped.
  void skip_open_type(const char* field) {
    const std::size_t octets = get_length(field);
    skip_bits(octets * 8, field);
  }

  void skip_bits(std::size_t n, const char* field) {
    if (failed_)
      return;
    if (n > size_bits_ - pos_) {
      fail(Error::kTruncated, field, 0);
      return;
    }
    pos_ += n;
  }

  std::size_t bit_position() const { return pos_; }
  std::size_t bits_left() const { return size_bits_ - pos_; }
  /// Octets the encoding occupies so far, padding included.
  std::size_t octets_consumed() const { return (pos_ + 7) / 8; }
  bool ok() const { return !failed_; }
  const CodecError& error() const { return error_; }

  void fail(Error code, const char* field, std::int64_t value) {
    fail_at(code, field, value, pos_);
  }
  void fail_at(Error code, const char* field, std::int64_t value, std::size_t bit) {
    if (failed_)
      return;
    failed_ = true;
    error_ = CodecError{code, field, value, bit};
  }

 private:
  // Near the end of the buffer, where an 8-byte load would overrun: one octet at a time.
  std::uint64_t slow_bits(unsigned n) const {
    std::uint64_t r = 0;
    std::size_t p = pos_;
    unsigned need = n;
    while (need > 0) {
      const unsigned off = static_cast<unsigned>(p & 7);
      const unsigned avail = 8 - off;
      const unsigned take = need < avail ? need : avail;
      const unsigned b = in_[p >> 3];
      const std::uint64_t bits = (b >> (avail - take)) & ((1u << take) - 1);
      r = (r << take) | bits;
      need -= take;
      p += take;
    }
    return r;
  }

  std::span<const std::uint8_t> in_;
  std::size_t size_bits_;
  std::size_t pos_ = 0;
  bool failed_ = false;
  CodecError error_{};
};

}  // namespace tb::its::asn1
