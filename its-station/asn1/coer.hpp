#pragma once
/// @file Octet-level writer and reader for ASN.1 canonical octet encoding rules (ITU-T X.696,
/// "COER"), the encoding of IEEE 1609.2 and ETSI TS 103 097.
///
/// The reader is a cursor over the input with a sticky error like the UPER reader: the first
/// failure is recorded with the field name and the position (CodecError::bit_offset = 8 * octet
/// offset), later calls return zeros, and the caller checks ok() when done. Every read is
/// bounds checked. The writer appends to a vector: security structures are a few hundred
/// octets, built once per packet.
///
/// Canonical means one encoding per value, so the reader rejects what an encoder of COER cannot
/// produce (a long-form length below 128, leading zero octets of a length or an integer): the
/// verifier hashes received octets, and two encodings of one value would give two hashes.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "its-station/asn1/error.hpp"

namespace tb::its::asn1 {

class CoerWriter {
 public:
  explicit CoerWriter(std::vector<std::uint8_t>& out) : out_(out) {}

  /// Fixed-size unsigned integers (X.696 10.3: a constrained range fitting 1, 2, 4 or 8 octets).
  void u8(std::uint8_t v) { out_.push_back(v); }
  void u16(std::uint16_t v) { be(v, 2); }
  void u32(std::uint32_t v) { be(v, 4); }
  void u64(std::uint64_t v) { be(v, 8); }
  /// Signed range fitting 4 octets (X.696 10.4), two's complement.
  void i32(std::int32_t v) { be(static_cast<std::uint32_t>(v), 4); }

  /// Length determinant, X.696 8.6: short form below 128, else 0x80 | octet count and the
  /// length in the fewest octets.
  void length(std::size_t n);

  /// A semi-constrained unsigned integer (lb 0, no ub; Psid), X.696 10.7: length + fewest
  /// octets (at least one).
  void unsigned_integer(std::uint64_t v);
  /// An unconstrained signed integer, X.696 10.8: length + fewest two's-complement octets.
  void signed_integer(std::int64_t v);

  /// ENUMERATED, X.696 11: values 0..127 in one octet (the only ones 1609.2 uses).
  void enumerated(unsigned v) { u8(static_cast<std::uint8_t>(v & 0x7f)); }
  /// The tag of a CHOICE alternative, X.696 20: context-specific class, number below 63 in one
  /// octet. Extension alternatives are followed by an open type (open_type()).
  void choice_tag(unsigned index) { u8(static_cast<std::uint8_t>(0x80 | (index & 0x3f))); }

  /// SEQUENCE preamble, X.696 16.2: an extension bit when the type is extensible, one bit per
  /// OPTIONAL/DEFAULT root component (most significant first, @p flags in the low @p count
  /// bits, the first component's bit the highest), zero padding to whole octets.
  void preamble(bool extensible, bool extensions_present, std::uint32_t flags, unsigned count);

  /// SEQUENCE OF quantity, X.696 19.6: the count as an unsigned integer with a length.
  void quantity(std::size_t n) { unsigned_integer(n); }

  void octets(std::span<const std::uint8_t> b) { out_.insert(out_.end(), b.begin(), b.end()); }
  /// OCTET STRING of variable size: length + octets.
  void var_octets(std::span<const std::uint8_t> b) {
    length(b.size());
    octets(b);
  }

  /// Open type (X.696 8.6 + 10.1): the octets of a nested encoding preceded by their length.
  void open_type(std::span<const std::uint8_t> encoding) { var_octets(encoding); }

  /// Extension addition presence bitmap, X.696 16.4: a length, the number of unused bits, then
  /// @p count bits (@p flags low bits, first addition highest).
  void extension_bitmap(std::uint32_t flags, unsigned count);

  std::size_t size() const { return out_.size(); }

 private:
  void be(std::uint64_t v, unsigned n) {
    for (unsigned i = n; i-- > 0;)
      out_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  std::vector<std::uint8_t>& out_;
};

class CoerReader {
 public:
  explicit CoerReader(std::span<const std::uint8_t> in) : in_(in) {}

  std::uint8_t u8(const char* field) { return static_cast<std::uint8_t>(be(1, field)); }
  std::uint16_t u16(const char* field) { return static_cast<std::uint16_t>(be(2, field)); }
  std::uint32_t u32(const char* field) { return static_cast<std::uint32_t>(be(4, field)); }
  std::uint64_t u64(const char* field) { return be(8, field); }
  std::int32_t i32(const char* field) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(be(4, field)));
  }

  /// Length determinant; fails on a length beyond the remaining input (every length in 1609.2
  /// counts octets that follow) and on a non-canonical form.
  std::size_t length(const char* field);
  std::uint64_t unsigned_integer(const char* field);
  std::int64_t signed_integer(const char* field);
  /// ENUMERATED in one octet; values above @p max fail with kUnknownExtension (an extension
  /// value this codec cannot hold) or kValueOutOfRange for a long form.
  unsigned enumerated(unsigned max, const char* field);
  /// CHOICE tag: the alternative's index. A tag of another class or a long-form number fails.
  unsigned choice_tag(const char* field);
  /// Reads a preamble of @p count bits after the extension bit (when @p extensible): returns
  /// the flags in the low bits (first component highest); *extensions gets the extension bit.
  std::uint32_t preamble(bool extensible, bool* extensions, unsigned count, const char* field);
  std::size_t quantity(const char* field);

  /// @p n octets as a view into the input (empty on failure).
  std::span<const std::uint8_t> octets(std::size_t n, const char* field);
  std::span<const std::uint8_t> var_octets(const char* field) {
    return octets(length(field), field);
  }
  template <std::size_t N>
  void fixed(std::array<std::uint8_t, N>& out, const char* field) {
    auto b = octets(N, field);
    if (b.size() == N)
      std::copy(b.begin(), b.end(), out.begin());
  }

  /// The octets of an open type (length + contents).
  std::span<const std::uint8_t> open_type(const char* field) { return var_octets(field); }

  /// Reads an extension bitmap of any length; returns the presence bits of the first
  /// @p known additions (first highest) and sets *unknown_present when an addition beyond
  /// them is present. Use skip_open_types(n) to step over the unknown ones.
  std::uint32_t extension_bitmap(unsigned known, std::size_t* total_present, const char* field);

  /// Skips @p n open types.
  void skip_open_types(std::size_t n, const char* field) {
    for (std::size_t i = 0; i < n && ok(); ++i)
      open_type(field);
  }

  bool ok() const { return !failed_; }
  const CodecError& error() const { return error_; }
  std::size_t offset() const { return pos_; }
  std::size_t remaining() const { return in_.size() - pos_; }
  /// The input between @p from and the cursor (for hashing the octets of a component).
  std::span<const std::uint8_t> consumed_since(std::size_t from) const {
    return in_.subspan(from, pos_ - from);
  }

  void fail(Error code, const char* field, std::int64_t value = 0) {
    if (failed_)
      return;
    failed_ = true;
    error_ = CodecError{code, field, value, pos_ * 8};
  }
  /// The whole input was one value: fails with kTrailingData otherwise.
  void expect_end(const char* field) {
    if (ok() && pos_ != in_.size())
      fail(Error::kTrailingData, field, static_cast<std::int64_t>(in_.size() - pos_));
  }

 private:
  std::uint64_t be(unsigned n, const char* field) {
    if (failed_)
      return 0;
    if (remaining() < n) {
      fail(Error::kTruncated, field);
      return 0;
    }
    std::uint64_t v = 0;
    for (unsigned i = 0; i < n; ++i)
      v = (v << 8) | in_[pos_ + i];
    pos_ += n;
    return v;
  }

  std::span<const std::uint8_t> in_;
  std::size_t pos_ = 0;
  bool failed_ = false;
  CodecError error_{};
};

}  // namespace tb::its::asn1
