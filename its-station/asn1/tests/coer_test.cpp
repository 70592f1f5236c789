#include "its-station/asn1/coer.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace tb::its::asn1 {
namespace {

using Bytes = std::vector<std::uint8_t>;

template <typename F>
Bytes encode(F&& f) {
  Bytes out;
  CoerWriter w(out);
  f(w);
  return out;
}

TEST(CoerWriter, LengthShortAndLongForm) {
  // X.696 8.6: 127 in one octet; 128 as 0x81 0x80; 300 as 0x82 0x01 0x2c.
  EXPECT_EQ(encode([](CoerWriter& w) { w.length(127); }), (Bytes{0x7f}));
  EXPECT_EQ(encode([](CoerWriter& w) { w.length(128); }), (Bytes{0x81, 0x80}));
  EXPECT_EQ(encode([](CoerWriter& w) { w.length(300); }), (Bytes{0x82, 0x01, 0x2c}));
}

TEST(CoerWriter, SemiConstrainedIntegersInFewestOctets) {
  // Psid 36 (CA basic service) = 01 24; psid 0x8007 = 02 80 07; 0 = 01 00.
  EXPECT_EQ(encode([](CoerWriter& w) { w.unsigned_integer(36); }), (Bytes{0x01, 0x24}));
  EXPECT_EQ(encode([](CoerWriter& w) { w.unsigned_integer(0x8007); }), (Bytes{0x02, 0x80, 0x07}));
  EXPECT_EQ(encode([](CoerWriter& w) { w.unsigned_integer(0); }), (Bytes{0x01, 0x00}));
  // Signed: 1 = 01 01, -1 = 01 ff, 128 = 02 00 80, -129 = 02 ff 7f.
  EXPECT_EQ(encode([](CoerWriter& w) { w.signed_integer(1); }), (Bytes{0x01, 0x01}));
  EXPECT_EQ(encode([](CoerWriter& w) { w.signed_integer(-1); }), (Bytes{0x01, 0xff}));
  EXPECT_EQ(encode([](CoerWriter& w) { w.signed_integer(128); }), (Bytes{0x02, 0x00, 0x80}));
  EXPECT_EQ(encode([](CoerWriter& w) { w.signed_integer(-129); }), (Bytes{0x02, 0xff, 0x7f}));
}

TEST(CoerWriter, PreambleChoiceAndBitmap) {
  // HeaderInfo: extensible, 6 optional components, only generationTime (the 1st): 0100 0000.
  EXPECT_EQ(encode([](CoerWriter& w) { w.preamble(true, false, 0b100000, 6); }), (Bytes{0x40}));
  // Extension bit set, no optional present: 1000 0000.
  EXPECT_EQ(encode([](CoerWriter& w) { w.preamble(true, true, 0, 6); }), (Bytes{0x80}));
  // ToBeSignedCertificate: extensible, 7 optionals, appPermissions (3rd) = 0 0010 0000 + pad.
  EXPECT_EQ(encode([](CoerWriter& w) { w.preamble(true, false, 0b0010000, 7); }), (Bytes{0x10}));
  // 9 bits over two octets: the padding is at the end.
  EXPECT_EQ(encode([](CoerWriter& w) { w.preamble(false, false, 0x1ff, 9); }), (Bytes{0xff, 0x80}));
  EXPECT_EQ(encode([](CoerWriter& w) { w.choice_tag(2); }), (Bytes{0x82}));
  // Two known additions, only the second present: length 2, 6 unused bits, 01.
  EXPECT_EQ(encode([](CoerWriter& w) { w.extension_bitmap(0b01, 2); }), (Bytes{0x02, 0x06, 0x40}));
}

TEST(CoerReader, RoundTripsWhatTheWriterWrites) {
  Bytes b = encode([](CoerWriter& w) {
    w.u8(3);
    w.u16(0xbeef);
    w.u32(0xdeadbeef);
    w.u64(722539108207911ull);
    w.i32(-900000000);
    w.unsigned_integer(0x123456789aull);
    w.signed_integer(-70000);
    w.enumerated(1);
    w.choice_tag(5);
    w.preamble(true, true, 0b101, 3);
    w.quantity(2);
    w.var_octets(Bytes(200, 0xaa));
    w.extension_bitmap(0b10, 2);
  });
  CoerReader r(b);
  EXPECT_EQ(r.u8("a"), 3);
  EXPECT_EQ(r.u16("b"), 0xbeef);
  EXPECT_EQ(r.u32("c"), 0xdeadbeefu);
  EXPECT_EQ(r.u64("d"), 722539108207911ull);
  EXPECT_EQ(r.i32("e"), -900000000);
  EXPECT_EQ(r.unsigned_integer("f"), 0x123456789aull);
  EXPECT_EQ(r.signed_integer("g"), -70000);
  EXPECT_EQ(r.enumerated(1, "h"), 1u);
  EXPECT_EQ(r.choice_tag("i"), 5u);
  bool ext = false;
  EXPECT_EQ(r.preamble(true, &ext, 3, "j"), 0b101u);
  EXPECT_TRUE(ext);
  EXPECT_EQ(r.quantity("k"), 2u);
  EXPECT_EQ(r.var_octets("l").size(), 200u);
  std::size_t present = 0;
  EXPECT_EQ(r.extension_bitmap(2, &present, "m"), 0b10u);
  EXPECT_EQ(present, 1u);
  r.expect_end("end");
  EXPECT_TRUE(r.ok()) << to_string(r.error());
}

TEST(CoerReader, RejectsNonCanonicalAndTruncatedInputNamingTheField) {
  {
    const Bytes b{0x81, 0x05, 0, 0, 0, 0, 0};  // long form for a length below 128
    CoerReader r(b);
    r.length("len");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, Error::kValueOutOfRange);
    EXPECT_STREQ(r.error().field, "len");
  }
  {
    const Bytes b{0x02, 0x00, 0x24};  // psid with a leading zero octet
    CoerReader r(b);
    r.unsigned_integer("psid");
    EXPECT_FALSE(r.ok());
  }
  {
    const Bytes b{0x05, 1, 2};  // a length past the end
    CoerReader r(b);
    r.var_octets("unsecuredData");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, Error::kTruncated);
    EXPECT_EQ(to_string(r.error()), "input truncated: unsecuredData = 5 (bit 8)");
  }
  {
    const Bytes b{0x41};  // a padding bit set
    CoerReader r(b);
    r.preamble(true, nullptr, 6, "HeaderInfo");
    EXPECT_FALSE(r.ok());
  }
  {
    const Bytes b{0x05};  // enumerated beyond the root values
    CoerReader r(b);
    r.enumerated(1, "hashId");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, Error::kUnknownExtension);
  }
  {
    const Bytes b{0x45};  // universal-class tag where a CHOICE tag is expected
    CoerReader r(b);
    r.choice_tag("signer");
    EXPECT_FALSE(r.ok());
  }
  {
    const Bytes b{0x01, 0x02, 0x03};  // sticky: after a failure every read returns zero
    CoerReader r(b);
    r.u32("x");
    EXPECT_EQ(r.u8("y"), 0);
    EXPECT_STREQ(r.error().field, "x");
  }
}

}  // namespace
}  // namespace tb::its::asn1
