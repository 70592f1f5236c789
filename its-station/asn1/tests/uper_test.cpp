#include "its-station/asn1/uper.hpp"

#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

namespace tb::its::asn1 {
namespace {

using Bytes = std::vector<std::uint8_t>;

template <typename F>
Bytes encode(F&& f, std::size_t capacity = 64) {
  Bytes out(capacity);
  UperWriter w(out);
  f(w);
  const std::size_t n = w.finish();
  EXPECT_TRUE(w.ok()) << to_string(w.error());
  out.resize(n);
  return out;
}

TEST(BitsForRange, MinimumBitsForTheRange) {
  EXPECT_EQ(bits_for_range(1), 0u);
  EXPECT_EQ(bits_for_range(2), 1u);
  EXPECT_EQ(bits_for_range(3), 2u);
  EXPECT_EQ(bits_for_range(4), 2u);
  EXPECT_EQ(bits_for_range(5), 3u);
  EXPECT_EQ(bits_for_range(256), 8u);
  EXPECT_EQ(bits_for_range(257), 9u);
  EXPECT_EQ((kConstrainedBits<0, 3601>), 12u);                  // HeadingValue
  EXPECT_EQ((kConstrainedBits<-900000000, 900000001>), 31u);    // Latitude
  EXPECT_EQ((kConstrainedBits<-1800000000, 1800000001>), 32u);  // Longitude
  EXPECT_EQ((kConstrainedBits<0, 4398046511103>), 42u);         // TimestampIts
  EXPECT_EQ((kConstrainedBits<-32766, 32767>), 16u);            // YawRateValue
  EXPECT_EQ((kConstrainedBits<0, 4294967295>), 32u);            // StationID
}

TEST(UperWriter, ConstrainedWholeNumberIsOffsetFromLowerBound) {
  // HeadingValue 900 (east) in 12 bits: 0011 1000 0100, padded with 4 zero bits.
  EXPECT_EQ(encode([](UperWriter& w) { w.put_constrained<0, 3601>(900, "h"); }),
            (Bytes{0x38, 0x40}));
  // -160 in (-160..161) is offset 0 in 9 bits; 161 is offset 321 = 1 0100 0001.
  EXPECT_EQ(encode([](UperWriter& w) {
              w.put_constrained<-160, 161>(-160, "a");
              w.put_constrained<-160, 161>(161, "a");
            }),
            (Bytes{0x00, 0x50, 0x40}));
  // A single-valued range takes no bits; a complete encoding is still one octet (X.691 11.1).
  EXPECT_EQ(encode([](UperWriter& w) { w.put_constrained<7, 7>(7, "x"); }), (Bytes{0x00}));
}

TEST(UperWriter, RejectsValuesOutsideTheConstraintNamingTheField) {
  std::array<std::uint8_t, 8> out{};
  UperWriter w(out);
  w.put_bool(true);
  w.put_constrained<0, 3601>(3602, "headingValue");
  w.put_bool(true);  // ignored after the failure
  EXPECT_FALSE(w.ok());
  EXPECT_EQ(w.error().code, Error::kValueOutOfRange);
  EXPECT_STREQ(w.error().field, "headingValue");
  EXPECT_EQ(w.error().value, 3602);
  EXPECT_EQ(w.error().bit_offset, 1u);
  EXPECT_EQ(w.finish(), 0u);
  EXPECT_EQ(to_string(w.error()), "value out of range: headingValue = 3602 (bit 1)");
}

TEST(UperWriter, LengthDeterminants) {
  EXPECT_EQ(encode([](UperWriter& w) { w.put_length(5, "l"); }), (Bytes{0x05}));
  EXPECT_EQ(encode([](UperWriter& w) { w.put_length(127, "l"); }), (Bytes{0x7F}));
  EXPECT_EQ(encode([](UperWriter& w) { w.put_length(200, "l"); }), (Bytes{0x80, 0xC8}));
  EXPECT_EQ(encode([](UperWriter& w) { w.put_length(16383, "l"); }), (Bytes{0xBF, 0xFF}));
  std::array<std::uint8_t, 8> out{};
  UperWriter w(out);
  w.put_length(16384, "big");
  EXPECT_EQ(w.error().code, Error::kUnsupported);
}

TEST(UperWriter, NormallySmallAndUnboundedIntegers) {
  // 5: 0 000101 -> 0000 1010.
  EXPECT_EQ(encode([](UperWriter& w) { w.put_normally_small(5); }), (Bytes{0x0A}));
  // 70: 1, length 00000001, 01000110 -> 1000 0000 1010 0011 0(000 0000).
  EXPECT_EQ(encode([](UperWriter& w) { w.put_normally_small(70); }), (Bytes{0x80, 0xA3, 0x00}));
  EXPECT_EQ(encode([](UperWriter& w) { w.put_unconstrained(-1); }), (Bytes{0x01, 0xFF}));
  EXPECT_EQ(encode([](UperWriter& w) { w.put_unconstrained(128); }), (Bytes{0x02, 0x00, 0x80}));
  EXPECT_EQ(encode([](UperWriter& w) { w.put_unconstrained(-129); }), (Bytes{0x02, 0xFF, 0x7F}));
  EXPECT_EQ(encode([](UperWriter& w) { w.put_semi_constrained(0, 0); }), (Bytes{0x01, 0x00}));
  EXPECT_EQ(encode([](UperWriter& w) { w.put_semi_constrained(300, 44); }),
            (Bytes{0x02, 0x01, 0x00}));
}

TEST(UperWriter, ExtensibleIntegerAndEnumerated) {
  // PathDeltaTime (1..65535, ...) = 1: extension bit 0, then 16 bits of 0.
  EXPECT_EQ(encode([](UperWriter& w) { w.put_constrained_ext<1, 65535>(1, "t"); }),
            (Bytes{0x00, 0x00, 0x00}));
  // Outside the root: 1, then unconstrained 70000 = length 3, 01 11 70.
  EXPECT_EQ(encode([](UperWriter& w) { w.put_constrained_ext<1, 65535>(70000, "t"); }),
            (Bytes{0x81, 0x80, 0x88, 0xB8, 0x00}));
  // CurvatureCalculationMode {3 root values, ...} = unavailable(2): 0 10.
  EXPECT_EQ(encode([](UperWriter& w) { w.put_enumerated(2, 3, true, "m"); }), (Bytes{0x40}));
  std::array<std::uint8_t, 4> out{};
  UperWriter w(out);
  w.put_enumerated(3, 3, true, "curvatureCalculationMode");
  EXPECT_EQ(w.error().code, Error::kValueOutOfRange);
}

TEST(UperWriter, FullBufferIsAnErrorNotAnOverrun) {
  std::array<std::uint8_t, 10> storage{};
  auto out = std::span<std::uint8_t>(storage).first(3);
  UperWriter w(out);
  w.put_bits(0xFFFFFF, 24);
  EXPECT_EQ(w.finish(), 3u);
  UperWriter w2(out);
  w2.put_bits(0xFFFFFFFF, 32);
  EXPECT_EQ(w2.finish(), 0u);
  EXPECT_EQ(w2.error().code, Error::kBufferTooSmall);
  UperWriter w3(out);
  for (int i = 0; i < 70; ++i)
    w3.put_bits(1, 1);  // crosses a whole 64-bit word with only 3 octets of room
  EXPECT_EQ(w3.error().code, Error::kBufferTooSmall);
  for (std::size_t i = 3; i < storage.size(); ++i)
    EXPECT_EQ(storage[i], 0) << i;
}

// A reference writer, one bit at a time, to check the word-at-a-time one against.
struct SlowWriter {
  Bytes bytes;
  std::size_t bits = 0;
  void put(std::uint64_t v, unsigned n) {
    for (unsigned i = n; i-- > 0;) {
      if (bits % 8 == 0)
        bytes.push_back(0);
      if ((v >> i) & 1)
        bytes.back() |= static_cast<std::uint8_t>(0x80 >> (bits % 8));
      ++bits;
    }
  }
};

TEST(UperWriterReader, RandomFieldsMatchBitByBitReferenceAndReadBack) {
  std::mt19937_64 rng(42);
  for (int round = 0; round < 200; ++round) {
    std::vector<std::pair<std::uint64_t, unsigned>> fields;
    SlowWriter ref;
    Bytes out(1200);
    UperWriter w(out);
    const int count = 1 + static_cast<int>(rng() % 120);
    for (int i = 0; i < count; ++i) {
      const unsigned n = static_cast<unsigned>(rng() % 65);
      const std::uint64_t v = n == 64 ? rng() : rng() & ((std::uint64_t{1} << n) - 1);
      fields.emplace_back(v, n);
      ref.put(v, n);
      w.put_bits(v, n);
    }
    const std::size_t size = w.finish();
    ASSERT_TRUE(w.ok());
    if (ref.bytes.empty())
      ref.bytes.push_back(0);
    out.resize(size);
    ASSERT_EQ(out, ref.bytes) << "round " << round;
    UperReader r(out);
    for (auto [v, n] : fields)
      ASSERT_EQ(r.get_bits(n, "f"), v) << "round " << round << " width " << n;
    EXPECT_TRUE(r.ok());
  }
}

TEST(UperReader, ReadsPastTheEndFailWithoutTouchingMemory) {
  const Bytes data{0xAB, 0xCD};
  UperReader r(std::span<const std::uint8_t>(data).first(2));
  EXPECT_EQ(r.get_bits(12, "a"), 0xABCu);
  EXPECT_EQ(r.get_bits(4, "b"), 0xDu);
  EXPECT_EQ(r.get_bits(1, "c"), 0u);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, Error::kTruncated);
  EXPECT_STREQ(r.error().field, "c");
  EXPECT_EQ(r.error().bit_offset, 16u);
  EXPECT_EQ(r.get_bits(8, "d"), 0u);  // sticky
  EXPECT_STREQ(r.error().field, "c");

  UperReader empty(std::span<const std::uint8_t>{});
  EXPECT_FALSE(empty.get_bool("x"));
  EXPECT_EQ(empty.error().code, Error::kTruncated);
}

TEST(UperReader, EveryWidthAtEveryOffsetNearTheEnd) {
  // Exercises the slow path (no 8-byte load) against the fast one on the same bits.
  Bytes data(11);
  for (std::size_t i = 0; i < data.size(); ++i)
    data[i] = static_cast<std::uint8_t>(0x5A ^ (i * 37));
  for (unsigned start = 0; start < 24; ++start) {
    for (unsigned n = 1; n <= 64; ++n) {
      UperReader a(data);
      a.skip_bits(start, "s");
      const std::uint64_t got = a.get_bits(n, "x");
      std::uint64_t want = 0;
      for (unsigned i = 0; i < n; ++i) {
        const std::size_t bit = start + i;
        want = (want << 1) | ((data[bit / 8] >> (7 - bit % 8)) & 1);
      }
      if (start + n <= data.size() * 8) {
        ASSERT_TRUE(a.ok());
        ASSERT_EQ(got, want) << start << " " << n;
      } else {
        ASSERT_FALSE(a.ok());
      }
    }
  }
}

TEST(UperReader, ConstrainedValueBeyondTheUpperBoundIsRejected) {
  const Bytes data{0xFF, 0xF0};  // 12 bits of 4095 for HeadingValue (0..3601)
  UperReader r(data);
  r.get_constrained<0, 3601>("headingValue");
  EXPECT_EQ(r.error().code, Error::kValueOutOfRange);
  EXPECT_EQ(r.error().value, 4095);
  EXPECT_EQ(r.error().bit_offset, 0u);
  EXPECT_STREQ(r.error().field, "headingValue");

  const Bytes ok{0xE1, 0x10};  // 3601 = 1110 0001 0001
  UperReader r2(ok);
  EXPECT_EQ((r2.get_constrained<0, 3601>("headingValue")), 3601);
  EXPECT_EQ((UperReader(ok).get_constrained(0, 3601, "h")), 3601);
}

TEST(UperReader, RoundTripOfEveryIntegerForm) {
  const std::int64_t values[] = {
      0, 1, -1, 63, 64, 127, 128, -128, -129, 65535, -65536, 4398046511103, INT64_MAX, INT64_MIN};
  for (std::int64_t v : values) {
    Bytes out(32);
    UperWriter w(out);
    w.put_unconstrained(v);
    if (v >= 0) {
      w.put_semi_constrained(static_cast<std::uint64_t>(v), 0);
      w.put_normally_small(static_cast<std::uint64_t>(v));
    }
    out.resize(w.finish());
    UperReader r(out);
    EXPECT_EQ(r.get_unconstrained("u"), v);
    if (v >= 0) {
      EXPECT_EQ(r.get_semi_constrained(0, "s"), static_cast<std::uint64_t>(v));
      EXPECT_EQ(r.get_normally_small("n"), static_cast<std::uint64_t>(v));
    }
    EXPECT_TRUE(r.ok()) << v << ": " << to_string(r.error());
  }
}

TEST(UperReader, UnboundedIntegerLongerThan64BitsIsRejected) {
  const Bytes data{0x09, 0, 0, 0, 0, 0, 0, 0, 0, 1};
  UperReader r(data);
  r.get_unconstrained("x");
  EXPECT_EQ(r.error().code, Error::kValueOutOfRange);
  EXPECT_EQ(r.error().value, 9);
  const Bytes frag{0xC1};  // a fragmented length (16K units)
  UperReader r2(frag);
  r2.get_length("len");
  EXPECT_EQ(r2.error().code, Error::kUnsupported);
}

TEST(UperReader, ExtensionValuesOfEnumerationsAndIntegersAreReported) {
  const Bytes enum_ext{0x80};  // extension bit 1, normally small 0
  UperReader r(enum_ext);
  r.get_enumerated(3, true, "curvatureCalculationMode");
  EXPECT_EQ(r.error().code, Error::kUnknownExtension);
  EXPECT_EQ(r.error().value, 0);

  const Bytes int_ext{0x81, 0x80, 0x88, 0xB8, 0x00};  // (1..65535, ...) = 70000
  UperReader r2(int_ext);
  r2.get_constrained_ext<1, 65535>("pathDeltaTime");
  EXPECT_EQ(r2.error().code, Error::kUnknownExtension);
  EXPECT_EQ(r2.error().value, 70000);

  const Bytes root{0x40};
  UperReader r3(root);
  EXPECT_EQ(r3.get_enumerated(3, true, "m"), 2u);
  EXPECT_TRUE(r3.ok());
  const Bytes bad_root{0xC0};  // 2 bits of 3 for a 3-valued root
  UperReader r4(bad_root);
  r4.get_enumerated(3, false, "driveDirection");
  EXPECT_EQ(r4.error().code, Error::kValueOutOfRange);
}

TEST(UperReader, SkipsPresentExtensionAdditionsOfASequence) {
  // Three additions, the first and third present, as open types of 2 and 0 octets, then a
  // 5-bit marker that belongs to what follows the sequence.
  Bytes out(16);
  UperWriter w(out);
  w.put_bool(false);
  w.put_bits(2, 6);      // normally small length: 3 additions
  w.put_bits(0b101, 3);  // presence bitmap
  w.put_length(2, "");
  w.put_bits(0xBEEF, 16);
  w.put_length(0, "");
  w.put_bits(0b10110, 5);
  out.resize(w.finish());
  UperReader r(out);
  r.skip_sequence_extensions("ext");
  EXPECT_EQ(r.get_bits(5, "marker"), 0b10110u);
  EXPECT_TRUE(r.ok());

  // The same with the last open type cut short.
  Bytes cut(out.begin(), out.begin() + 3);
  UperReader r2(cut);
  r2.skip_sequence_extensions("ext");
  EXPECT_EQ(r2.error().code, Error::kTruncated);
  EXPECT_STREQ(r2.error().field, "ext");
}

TEST(ErrorText, NamesEveryCode) {
  for (int c = 0; c <= static_cast<int>(Error::kTrailingData); ++c)
    EXPECT_NE(to_string(static_cast<Error>(c)), "unknown error");
}

}  // namespace
}  // namespace tb::its::asn1
