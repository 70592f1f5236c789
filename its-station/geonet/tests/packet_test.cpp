#include <gtest/gtest.h>

#include <vector>

#include "its-station/geonet/packet.hpp"

namespace tb::its::geonet {
namespace {

using namespace std::chrono_literals;
using Bytes = std::vector<std::uint8_t>;

// An SHB carrying a BTP-B header and 4 bytes of data, worked out by hand (EN 302 636-4-1 V1.4.1
// clause 9):
//   Basic header
//     11        version 1 (high nibble), NH 1 = common header
//     00        reserved
//     50        LT: multiplier 20 (0b010100) << 2 | base 0 (50 ms) = 1 s
//     01        RHL 1
//   Common header
//     20        NH 2 = BTP-B (high nibble), reserved
//     50        HT 5 (TSB), HST 0 (single hop)
//     02        TC: SCF 0, channel offload 0, TC ID 2
//     80        flags: bit 0 (MSB) mobile
//     00 08     PL 8 (BTP-B header 4 + data 4)
//     01        MHL 1
//     00        reserved
//   SHB extended header: source long position vector
//     14 00     GN_ADDR M 0, ST 5 (passenger car) << 10, reserved 0
//     02 00 00 00 00 01   MID
//     12 34 56 78         TST
//     1c b3 1b 60         latitude 48.15° = 481 500 000 × 1/10 µ°
//     ff 0b dc 00         longitude −1.6° = −16 000 000 (two's complement)
//     85 6d               PAI 1, speed 1389 × 0.01 m/s = 13.89 m/s
//     03 84               heading 900 × 0.1° = 90°
//     00 00 00 00         media-dependent data (DCC), unused
//   Payload
//     07 d1 00 00 de ad be ef   BTP-B port 2001, port info 0, data
const Bytes kShbGolden = {0x11, 0x00, 0x50, 0x01,                           // basic
                          0x20, 0x50, 0x02, 0x80, 0x00, 0x08, 0x01, 0x00,   // common
                          0x14, 0x00, 0x02, 0x00, 0x00, 0x00, 0x00, 0x01,   // GN_ADDR
                          0x12, 0x34, 0x56, 0x78, 0x1c, 0xb3, 0x1b, 0x60,   // TST, lat
                          0xff, 0x0b, 0xdc, 0x00, 0x85, 0x6d, 0x03, 0x84,   // long, PAI|S, H
                          0x00, 0x00, 0x00, 0x00,                           // media-dependent
                          0x07, 0xd1, 0x00, 0x00, 0xde, 0xad, 0xbe, 0xef};  // payload

LongPositionVector golden_pv() {
  LongPositionVector pv;
  pv.address = {false, StationType::kPassengerCar, {0x02, 0, 0, 0, 0, 0x01}};
  pv.timestamp = 0x12345678;
  pv.latitude = 481'500'000;
  pv.longitude = -16'000'000;
  pv.position_accurate = true;
  pv.speed = 1389;
  pv.heading = 900;
  return pv;
}

const Bytes kShbPayload = {0x07, 0xd1, 0x00, 0x00, 0xde, 0xad, 0xbe, 0xef};

TEST(GnPacket, EncodesTheHandWorkedShb) {
  BasicHeader basic{1, BasicNextHeader::kCommonHeader, Lifetime::from_duration(1s), 1};
  CommonHeader common{
      UpperProtocol::kBtpB, PacketType::kSingleHopBroadcast, {false, false, 2}, true, 0, 1};
  Bytes out(200);
  const std::size_t n = serialize(basic, common, ShbHeader{golden_pv(), 0}, kShbPayload, out);
  out.resize(n);
  EXPECT_EQ(out, kShbGolden);
}

TEST(GnPacket, DecodesTheHandWorkedShb) {
  auto p = parse_packet(kShbGolden);
  ASSERT_TRUE(p) << to_string(p.error());
  EXPECT_EQ(p->basic.version, 1);
  EXPECT_EQ(p->basic.lifetime.duration(), 1s);
  EXPECT_EQ(p->basic.remaining_hop_limit, 1);
  EXPECT_EQ(p->common.next_header, UpperProtocol::kBtpB);
  EXPECT_EQ(p->common.type, PacketType::kSingleHopBroadcast);
  EXPECT_EQ(p->common.traffic_class, (TrafficClass{false, false, 2}));
  EXPECT_TRUE(p->common.mobile);
  EXPECT_EQ(p->common.payload_length, 8);
  EXPECT_EQ(p->common.maximum_hop_limit, 1);
  EXPECT_EQ(source_position(p->extended), golden_pv());
  EXPECT_EQ(Bytes(p->payload.begin(), p->payload.end()), kShbPayload);
}

// A GeoBroadcast (ellipse) header by hand, after the basic and common headers:
//   01 02         SN 258
//   00 00         reserved
//   (24-byte LPV as above, but speed −0.5 m/s: PAI 0, S = −50 → 15-bit 0x7fce)
//   1c b3 1b 60   area centre latitude 48.15°
//   ff 0b dc 00   area centre longitude −1.6°
//   01 f4         distance a 500 m
//   00 c8         distance b 200 m
//   00 2d         angle 45°
//   00 00         reserved
// Basic header 11 00 f1 05: LT multiplier 60 << 2 | base 1 (1 s) = 60 s (the smallest base
// that holds 60 s: 1200 × 50 ms does not fit 6 bits), RHL 5.
// Common header 10 42 00 80 00 00 0a 00: NH 1 = BTP-A, HT 4 HST 2 (GBC ellipse), TC 0, mobile,
// PL 0, MHL 10.
const Bytes kGbcGolden = {
    0x11, 0x00, 0xf1, 0x05, 0x10, 0x42, 0x00, 0x80, 0x00, 0x00, 0x0a, 0x00,  // basic, common
    0x01, 0x02, 0x00, 0x00,                                                  // SN, reserved
    0x14, 0x00, 0x02, 0x00, 0x00, 0x00, 0x00, 0x01, 0x12, 0x34, 0x56, 0x78,  // GN_ADDR, TST
    0x1c, 0xb3, 0x1b, 0x60, 0xff, 0x0b, 0xdc, 0x00, 0x7f, 0xce, 0x03, 0x84,  // lat long S H
    0x1c, 0xb3, 0x1b, 0x60, 0xff, 0x0b, 0xdc, 0x00,                          // centre
    0x01, 0xf4, 0x00, 0xc8, 0x00, 0x2d, 0x00, 0x00};                         // a b angle res

TEST(GnPacket, GeoBroadcastEllipseMatchesHandWorkedBytesBothWays) {
  LongPositionVector pv = golden_pv();
  pv.position_accurate = false;
  pv.speed = -50;
  GeoArea area{AreaShape::kEllipse, 481'500'000, -16'000'000, 500, 200, 45};
  BasicHeader basic{1, BasicNextHeader::kCommonHeader, Lifetime::from_duration(60s), 5};
  CommonHeader common{UpperProtocol::kBtpA, PacketType::kGeoBroadcastEllipse, {}, true, 0, 10};
  Bytes out(200);
  out.resize(serialize(basic, common, GbcHeader{258, pv, area}, {}, out));
  EXPECT_EQ(out, kGbcGolden);

  auto p = parse_packet(kGbcGolden);
  ASSERT_TRUE(p) << to_string(p.error());
  EXPECT_EQ(p->common.type, PacketType::kGeoBroadcastEllipse);
  const auto& g = std::get<GbcHeader>(p->extended);
  EXPECT_EQ(g.sequence_number, 258);
  EXPECT_EQ(g.source_position, pv);
  EXPECT_EQ(g.source_position.speed, -50);
  EXPECT_EQ(g.area, area);
  EXPECT_EQ(p->basic.lifetime.duration(), 60s);
  EXPECT_TRUE(p->payload.empty());
}

TEST(GnPacket, TsbAndBeaconRoundTrip) {
  BasicHeader basic{1, BasicNextHeader::kCommonHeader, Lifetime::from_duration(5s), 3};
  CommonHeader common{UpperProtocol::kBtpB,
                      PacketType::kTopologicallyScopedBroadcast,
                      {true, true, 63},
                      false,
                      0,
                      4};
  const Bytes payload = {1, 2, 3};
  Bytes out(200);
  out.resize(serialize(basic, common, TsbHeader{65535, golden_pv()}, payload, out));
  ASSERT_EQ(out.size(), header_size(PacketType::kTopologicallyScopedBroadcast) + 3);
  EXPECT_EQ(out[5], 0x51);  // HT 5, HST 1
  EXPECT_EQ(out[6], 0xff);  // SCF, offload, TC ID 63
  auto p = parse_packet(out);
  ASSERT_TRUE(p);
  EXPECT_EQ(std::get<TsbHeader>(p->extended).sequence_number, 65535);
  EXPECT_EQ(p->common.traffic_class, (TrafficClass{true, true, 63}));
  EXPECT_FALSE(p->common.mobile);
  EXPECT_EQ(Bytes(p->payload.begin(), p->payload.end()), payload);

  Bytes beacon(100);
  common = CommonHeader{UpperProtocol::kAny, PacketType::kBeacon, {}, true, 0, 1};
  beacon.resize(serialize(basic, common, BeaconHeader{golden_pv()}, {}, beacon));
  ASSERT_EQ(beacon.size(), 36u);
  EXPECT_EQ(beacon[5], 0x10);
  auto b = parse_packet(beacon);
  ASSERT_TRUE(b);
  EXPECT_EQ(b->common.type, PacketType::kBeacon);
  EXPECT_EQ(source_position(b->extended), golden_pv());
}

TEST(GnPacket, SerializeFailsWhenTheBufferIsTooSmall) {
  Bytes out(kShbGolden.size() - 1);
  BasicHeader basic;
  CommonHeader common;
  EXPECT_EQ(serialize(basic, common, ShbHeader{golden_pv(), 0}, kShbPayload, out), 0u);
}

TEST(GnPacket, RejectsOtherVersions) {
  for (std::uint8_t version : {0, 2, 15}) {
    Bytes b = kShbGolden;
    b[0] = static_cast<std::uint8_t>((version << 4) | 1);
    auto p = parse_packet(b);
    ASSERT_FALSE(p);
    EXPECT_EQ(p.error(), ParseError::kUnsupportedVersion) << int{version};
  }
}

TEST(GnPacket, RejectsSecuredAndUnknownNextHeaders) {
  Bytes b = kShbGolden;
  b[0] = 0x12;
  EXPECT_EQ(parse_packet(b).error(), ParseError::kSecuredPacket);
  b[0] = 0x10;
  EXPECT_EQ(parse_packet(b).error(), ParseError::kUnknownBasicNextHeader);
  b[0] = 0x13;
  EXPECT_EQ(parse_packet(b).error(), ParseError::kUnknownBasicNextHeader);
}

TEST(GnPacket, EveryTruncationIsReportedWithTheHeaderItHit) {
  for (std::size_t n = 0; n < kShbGolden.size(); ++n) {
    auto p = parse_packet(std::span(kShbGolden).first(n));
    ASSERT_FALSE(p) << n;
    const ParseError want = n < 4    ? ParseError::kTruncatedBasicHeader
                            : n < 12 ? ParseError::kTruncatedCommonHeader
                            : n < 40 ? ParseError::kTruncatedExtendedHeader
                                     : ParseError::kPayloadLengthExceedsFrame;
    EXPECT_EQ(p.error(), want) << "length " << n << ": " << to_string(p.error());
  }
  for (std::size_t n = 0; n < kGbcGolden.size(); ++n)
    EXPECT_FALSE(parse_packet(std::span(kGbcGolden).first(n))) << n;
}

TEST(GnPacket, IgnoresLinkPaddingAfterThePayload) {
  Bytes b = kShbGolden;
  b.resize(b.size() + 10, 0);
  auto p = parse_packet(b);
  ASSERT_TRUE(p);
  EXPECT_EQ(Bytes(p->payload.begin(), p->payload.end()), kShbPayload);
}

TEST(GnPacket, HeaderTypesOutsideTheStandardAreUnknownAndUnimplementedOnesUnsupported) {
  Bytes b = kShbGolden;
  for (std::uint8_t ht_hst : {0x00, 0x11, 0x43, 0x52, 0x70, 0xf0}) {
    b[5] = ht_hst;
    EXPECT_EQ(parse_packet(b).error(), ParseError::kUnknownHeaderType) << int{ht_hst};
  }
  for (std::uint8_t ht_hst : {0x20, 0x30, 0x32, 0x60, 0x61}) {
    b[5] = ht_hst;
    EXPECT_EQ(parse_packet(b).error(), ParseError::kUnsupportedHeaderType) << int{ht_hst};
  }
}

TEST(GnLifetime, EncodesWithTheSmallestBaseThatFits) {
  EXPECT_EQ(Lifetime::from_duration(0s).encoded, 0);
  EXPECT_EQ(Lifetime::from_duration(50ms).encoded, (1 << 2) | 0);
  EXPECT_EQ(Lifetime::from_duration(1ms).duration(), 50ms);  // rounds up, never to 0
  EXPECT_EQ(Lifetime::from_duration(3150ms).encoded, (63 << 2) | 0);
  EXPECT_EQ(Lifetime::from_duration(3200ms).encoded, (4 << 2) | 1);  // 4 s
  EXPECT_EQ(Lifetime::from_duration(60s).duration(), 60s);
  EXPECT_EQ(Lifetime::from_duration(600s).encoded, (60 << 2) | 2);
  EXPECT_EQ(Lifetime::from_duration(6300s).encoded, (63 << 2) | 3);
  EXPECT_EQ(Lifetime::from_duration(100000s).duration(), 6300s);  // clamped to the maximum
}

}  // namespace
}  // namespace tb::its::geonet

namespace tb::its::geonet {
namespace {

TEST(GnPositionVector, ShortVectorIsAddressTimestampAndPosition) {
  // 9c 00 = M 1, ST 7 (light truck) << 10; MID; TST 1; lat −0.0000001°; long 180°.
  const Bytes golden = {0x9c, 0x00, 0x02, 0x00, 0x00, 0x00, 0x00, 0x2a, 0x00, 0x00,
                        0x00, 0x01, 0xff, 0xff, 0xff, 0xff, 0x6b, 0x49, 0xd2, 0x00};
  const ShortPositionVector spv{
      {true, StationType::kLightTruck, {0x02, 0, 0, 0, 0, 0x2a}}, 1, -1, 1'800'000'000};
  Bytes out(kShortPositionVectorSize);
  ByteWriter w{out};
  write_short_position_vector(w, spv);
  ASSERT_TRUE(w.ok());
  EXPECT_EQ(out, golden);
  ByteReader r{golden};
  EXPECT_EQ(read_short_position_vector(r), spv);
  EXPECT_TRUE(r.ok());
  ByteReader short_input{std::span(golden).first(19)};
  read_short_position_vector(short_input);
  EXPECT_FALSE(short_input.ok());
}

TEST(GnPositionVector, SpeedIsFifteenBitTwosComplementBesidePai) {
  for (const std::int16_t speed : {0, 1, -1, 16383, -16384}) {
    LongPositionVector pv;
    pv.speed = speed;
    pv.position_accurate = speed < 0;
    Bytes out(kLongPositionVectorSize);
    ByteWriter w{out};
    write_long_position_vector(w, pv);
    ByteReader r{out};
    const auto back = read_long_position_vector(r);
    EXPECT_EQ(back.speed, speed);
    EXPECT_EQ(back.position_accurate, speed < 0);
  }
}

}  // namespace
}  // namespace tb::its::geonet
