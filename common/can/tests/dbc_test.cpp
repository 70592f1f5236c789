#include <array>

#include <gtest/gtest.h>

#include "common/can/dbc.hpp"

namespace tb::can {
namespace {

Database parse_ok(std::string_view text) {
  auto db = Database::parse(text, "test.dbc");
  EXPECT_TRUE(db.has_value()) << (db ? "" : db.error().message());
  return db ? *db : Database{};
}

DbcError parse_error(std::string_view text) {
  auto db = Database::parse(text, "bad.dbc");
  EXPECT_FALSE(db.has_value());
  return db ? DbcError{} : db.error();
}

constexpr std::string_view kSmall = R"(VERSION ""

NS_ :
	CM_
	BA_
	SG_

BS_:
BU_: A B

BO_ 100 Intel: 8 A
 SG_ U16 : 0|16@1+ (0.5,-10) [-10|100] "m" B,C
 SG_ S12 : 16|12@1- (1,0) [0|0] "" B
 SG_ Flag : 28|1@1+ (1,0) [0|1] "" B

BO_ 2147484672 Moto: 4 A
 SG_ M10 : 5|10@0+ (1,0) [0|0] "" B
 SG_ MS16 : 23|16@0- (0.1,0) [-100|100] "deg" B

CM_ "A comment that spans
two lines; and has a ; inside";
CM_ SG_ 100 U16 "unit test";
BA_DEF_ BO_ "GenMsgCycleTime" INT 0 10000;
BA_DEF_DEF_ "GenMsgCycleTime" 50;
BA_ "GenMsgCycleTime" BO_ 100 20;
BA_ "OtherAttribute" BO_ 100 1;
VAL_ 100 Flag 0 "off" 1 "on" ;
)";

TEST(Dbc, ParsesMessagesSignalsAndAttributes) {
  const Database db = parse_ok(kSmall);
  ASSERT_EQ(db.messages.size(), 2u);
  const Message& m = db.messages[0];
  EXPECT_EQ(m.id, 100u);
  EXPECT_FALSE(m.extended);
  EXPECT_EQ(m.name, "Intel");
  EXPECT_EQ(m.dlc, 8u);
  EXPECT_EQ(m.transmitter, "A");
  ASSERT_EQ(m.signals.size(), 3u);
  const Signal& u = m.signals[0];
  EXPECT_EQ(u.start_bit, 0u);
  EXPECT_EQ(u.length, 16u);
  EXPECT_EQ(u.byte_order, ByteOrder::kIntel);
  EXPECT_FALSE(u.is_signed);
  EXPECT_DOUBLE_EQ(u.factor, 0.5);
  EXPECT_DOUBLE_EQ(u.offset, -10);
  EXPECT_DOUBLE_EQ(u.maximum, 100);
  EXPECT_EQ(u.unit, "m");
  EXPECT_EQ(u.receivers, (std::vector<std::string>{"B", "C"}));
  EXPECT_TRUE(m.signals[1].is_signed);
  EXPECT_EQ(m.cycle_time_ms, 20u);

  const Message& moto = db.messages[1];
  EXPECT_TRUE(moto.extended);
  EXPECT_EQ(moto.id, 1024u);  // 2147484672 = 0x80000400
  EXPECT_EQ(moto.signals[0].byte_order, ByteOrder::kMotorola);
  EXPECT_EQ(moto.cycle_time_ms, 50u);  // from BA_DEF_DEF_
  EXPECT_EQ(db.find_message(1024, true), &moto);
  EXPECT_EQ(db.find_message("Intel"), &m);
  EXPECT_EQ(db.find_message(1024, false), nullptr);
}

TEST(Dbc, IntelEncodingMatchesHandComputedBytes) {
  const Database db = parse_ok(kSmall);
  const Message& m = db.messages[0];
  std::array<std::uint8_t, 8> data{};
  // U16 = 45.5 m: raw (45.5 - (-10)) / 0.5 = 111 = 0x006F, little-endian in bytes 0-1.
  m.signals[0].encode(45.5, data);
  // S12 = -2: 12-bit two's complement 0xFFE in bits 16..27: byte 2 = 0xFE, byte 3 low = 0xF.
  m.signals[1].encode(-2, data);
  // Flag = 1 at bit 28: byte 3 bit 4.
  m.signals[2].encode(1, data);
  EXPECT_EQ(data, (std::array<std::uint8_t, 8>{0x6F, 0x00, 0xFE, 0x1F, 0, 0, 0, 0}));
  EXPECT_DOUBLE_EQ(m.signals[0].decode(data), 45.5);
  EXPECT_DOUBLE_EQ(m.signals[1].decode(data), -2);
  EXPECT_DOUBLE_EQ(m.signals[2].decode(data), 1);
}

TEST(Dbc, MotorolaEncodingMatchesHandComputedBytes) {
  const Database db = parse_ok(kSmall);
  const Message& m = db.messages[1];
  std::array<std::uint8_t, 4> data{};
  // M10 = 0x2AB (10 bits): MSB at byte 0 bit 5, so byte 0 bits 5..0 = 101010 and byte 1 bits
  // 7..4 = 1011: byte 0 = 0x2A, byte 1 = 0xB0.
  m.signals[0].encode(0x2AB, data);
  // MS16 = -12.3 deg: raw -123 = 0xFF85, MSB at byte 2 bit 7: byte 2 = 0xFF, byte 3 = 0x85.
  m.signals[1].encode(-12.3, data);
  EXPECT_EQ(data, (std::array<std::uint8_t, 4>{0x2A, 0xB0, 0xFF, 0x85}));
  EXPECT_DOUBLE_EQ(m.signals[0].decode(data), 0x2AB);
  EXPECT_NEAR(m.signals[1].decode(data), -12.3, 1e-9);
}

TEST(Dbc, EncodeRoundsAndClamps) {
  const Database db = parse_ok(kSmall);
  const Signal& u = db.messages[0].signals[0];    // [-10, 100], step 0.5
  const Signal& s12 = db.messages[0].signals[1];  // no range: limited by its 12 bits
  EXPECT_EQ(u.to_raw(45.74), 111);                // 55.74 / 0.5 = 111.48 → 111
  EXPECT_EQ(u.to_raw(45.76), 112);                // 111.52 → 112
  EXPECT_EQ(u.to_raw(1000), 220);                 // clamped to max 100 → (100 + 10) / 0.5
  EXPECT_EQ(u.to_raw(-50), 0);                    // clamped to min -10
  EXPECT_EQ(s12.to_raw(5000), 2047);
  EXPECT_EQ(s12.to_raw(-5000), -2048);
  EXPECT_EQ(s12.to_raw(std::numeric_limits<double>::quiet_NaN()), 0);
}

TEST(Dbc, EncodingLeavesOtherBitsAlone) {
  const Database db = parse_ok(kSmall);
  const Message& m = db.messages[1];
  std::array<std::uint8_t, 4> data{0xFF, 0xFF, 0xFF, 0xFF};
  m.signals[0].encode(0, data);
  // M10 covers byte 0 bits 5..0 and byte 1 bits 7..4 only.
  EXPECT_EQ(data, (std::array<std::uint8_t, 4>{0xC0, 0x0F, 0xFF, 0xFF}));
}

TEST(Dbc, ErrorsNameFileLineAndText) {
  DbcError e = parse_error(
      "BO_ 1 A: 8 X\n SG_ S : 0|8@1+ (1,0) [0|1] \"\" X\n SG_ T : 4|8@1+ (1,0) [0|1] \"\" X\n");
  EXPECT_EQ(e.code, DbcErrc::kSignalOverlap);
  EXPECT_EQ(e.line, 3);
  EXPECT_EQ(e.file, "bad.dbc");
  EXPECT_NE(e.message().find("bad.dbc:3: signals overlap"), std::string::npos) << e.message();
  EXPECT_NE(e.message().find("SG_ T : 4|8@1+"), std::string::npos) << e.message();

  e = parse_error("BO_ 1 A: 2 X\n SG_ S : 10|8@1+ (1,0) [0|1] \"\" X\n");
  EXPECT_EQ(e.code, DbcErrc::kSignalOutsideMessage);
  EXPECT_NE(e.detail.find("bit 16"), std::string::npos) << e.detail;

  e = parse_error("BO_ 1 A: 8 X\n SG_ S : 0|8@2+ (1,0) [0|1] \"\" X\n");
  EXPECT_EQ(e.code, DbcErrc::kSyntax);
  EXPECT_EQ(e.line, 2);

  e = parse_error("BO_ 1 A: 8 X\n SG_ S M : 0|8@1+ (1,0) [0|1] \"\" X\n");
  EXPECT_EQ(e.code, DbcErrc::kMultiplexingUnsupported);

  e = parse_error(" SG_ S : 0|8@1+ (1,0) [0|1] \"\" X\n");
  EXPECT_EQ(e.code, DbcErrc::kSignalBeforeMessage);
  EXPECT_EQ(e.line, 1);

  e = parse_error("BO_ 1 A: 8 X\nBO_ 1 B: 8 X\n");
  EXPECT_EQ(e.code, DbcErrc::kDuplicateMessage);
  EXPECT_EQ(e.line, 2);

  e = parse_error("BO_ 1 A: 8 X\n SG_ S : 0|8@1+ (0,0) [0|1] \"\" X\n");
  EXPECT_EQ(e.code, DbcErrc::kBadValue);

  e = parse_error("BO_ 2048 A: 8 X\n");
  EXPECT_EQ(e.code, DbcErrc::kBadValue);

  e = parse_error("BO_ 1 A: 8 X\nBA_ \"GenMsgCycleTime\" BO_ 2 10;\n");
  EXPECT_EQ(e.code, DbcErrc::kUnknownMessage);
  EXPECT_EQ(e.line, 2);

  e = parse_error("BO_ 1 A: 8 X\nCM_ \"never closed;\n");
  EXPECT_EQ(e.code, DbcErrc::kSyntax);
  EXPECT_EQ(e.line, 2);

  e = parse_error("BO_ 1 A: 8 X\nHELLO world\n");
  EXPECT_EQ(e.code, DbcErrc::kSyntax);
  EXPECT_NE(e.detail.find("HELLO"), std::string::npos);

  e = parse_error(
      "BO_ 1 A: 8 X\n SG_ S : 0|8@1+ (1,0) [0|1] \"\" X\n SG_ S : 8|8@1+ (1,0) [0|1] \"\" X\n");
  EXPECT_EQ(e.code, DbcErrc::kDuplicateSignal);
}

TEST(Dbc, LoadReportsMissingFile) {
  auto db = Database::load("/nonexistent/vehicle.dbc");
  ASSERT_FALSE(db.has_value());
  EXPECT_EQ(db.error().code, DbcErrc::kCannotOpen);
  EXPECT_NE(db.error().message().find("/nonexistent/vehicle.dbc"), std::string::npos);
}

TEST(Dbc, SkipsVectorIndependentSignals) {
  const Database db = parse_ok(
      "BO_ 3221225472 VECTOR__INDEPENDENT_SIG_MSG: 0 Vector__XXX\n"
      " SG_ Orphan : 0|8@1+ (1,0) [0|0] \"\" Vector__XXX\n"
      "BO_ 5 Real: 1 X\n SG_ S : 0|8@1+ (1,0) [0|0] \"\" Vector__XXX\n");
  ASSERT_EQ(db.messages.size(), 1u);
  EXPECT_EQ(db.messages[0].name, "Real");
}

TEST(Dbc, ShortFramesNeverReadOrWritePastTheirEnd) {
  const Database db = parse_ok(kSmall);
  const Signal& u16 = db.messages[0].signals[0];  // bytes 0-1
  const Signal& s12 = db.messages[0].signals[1];  // bits 16..27
  std::array<std::uint8_t, 1> one{0x6F};
  EXPECT_DOUBLE_EQ(u16.decode(one), 0x6F * 0.5 - 10);  // byte 1 missing: reads as 0
  EXPECT_EQ(s12.extract_raw(one), 0);
  u16.encode(45.5, std::span(one));  // only byte 0 fits
  EXPECT_EQ(one[0], 0x6F);
  std::array<std::uint8_t, 3> three{};
  s12.encode(-2, three);  // bits 16..23 fit, 24..27 do not
  EXPECT_EQ(three[2], 0xFE);
}

TEST(Dbc, SixtyFourBitSignalsRoundTrip) {
  const Database db = parse_ok("BO_ 1 A: 8 X\n SG_ S : 0|64@1- (1,0) [0|0] \"\" X\n");
  const Signal& s = db.messages[0].signals[0];
  std::array<std::uint8_t, 8> data{};
  s.insert_raw(-1234567890123LL, data);
  EXPECT_EQ(s.extract_raw(data), -1234567890123LL);
}

// Whole little-endian bytes (the vehicle frames' signals) are read without the bit loop: every
// start byte, width and signedness against the integer the bytes spell, two's complement.
TEST(Dbc, WholeByteIntelSignalsReadTheLittleEndianInteger) {
  const std::array<std::uint8_t, 8> data{0x81, 0x02, 0xF3, 0x44, 0x95, 0x06, 0xE7, 0xF8};
  for (unsigned start = 0; start < 64; start += 8) {
    for (unsigned length = 8; start + length <= 64; length += 8) {
      for (const bool is_signed : {false, true}) {
        Signal s;
        s.start_bit = start;
        s.length = length;
        s.is_signed = is_signed;
        std::uint64_t want = 0;
        for (unsigned b = 0; b < length / 8; ++b)
          want |= std::uint64_t{data[start / 8 + b]} << (8 * b);
        if (is_signed && length < 64 && (want >> (length - 1)) != 0)
          want -= std::uint64_t{1} << length;  // negative: value − 2^length
        EXPECT_EQ(s.extract_raw(data), static_cast<std::int64_t>(want))
            << "start " << start << " length " << length << " signed " << is_signed;
        // A frame one byte short: the missing top byte reads as zero (so no sign either), as
        // the bit loop reads it.
        const std::span<const std::uint8_t> cut(data.data(), start / 8 + length / 8 - 1);
        const std::uint64_t low = length == 8 ? 0 : want & ((std::uint64_t{1} << (length - 8)) - 1);
        EXPECT_EQ(s.extract_raw(cut), static_cast<std::int64_t>(low))
            << "cut frame, start " << start << " length " << length;
      }
    }
  }
}

}  // namespace
}  // namespace tb::can
