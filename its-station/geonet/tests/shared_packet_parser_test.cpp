#include <gtest/gtest.h>

#include <vector>

#include "its-station/geonet/shared_packet_parser.hpp"

namespace tb::its::geonet {
namespace {

using Bytes = std::vector<std::uint8_t>;

// The hand-worked SHB of packet_test.cpp (EN 302 636-4-1 clause 9): BTP-B 2001, 4 bytes of data.
const Bytes kShb = {0x11, 0x00, 0x50, 0x01, 0x20, 0x50, 0x02, 0x80, 0x00, 0x08, 0x01, 0x00,
                    0x14, 0x00, 0x02, 0x00, 0x00, 0x00, 0x00, 0x01, 0x12, 0x34, 0x56, 0x78,
                    0x1c, 0xb3, 0x1b, 0x60, 0xff, 0x0b, 0xdc, 0x00, 0x85, 0x6d, 0x03, 0x84,
                    0x00, 0x00, 0x00, 0x00, 0x07, 0xd1, 0x00, 0x00, 0xde, 0xad, 0xbe, 0xef};

void expect_same(const Expected<Packet, ParseError>& a, const Expected<Packet, ParseError>& b) {
  ASSERT_EQ(bool(a), bool(b));
  if (!a) {
    EXPECT_EQ(a.error(), b.error());
    return;
  }
  EXPECT_EQ(a->common.type, b->common.type);
  EXPECT_EQ(source_position(a->extended).timestamp, source_position(b->extended).timestamp);
  EXPECT_EQ(source_position(a->extended).latitude, source_position(b->extended).latitude);
  EXPECT_EQ(Bytes(a->payload.begin(), a->payload.end()),
            Bytes(b->payload.begin(), b->payload.end()));
}

TEST(SharedPacketParser, SameBytesParsedOnceAndThePayloadViewsTheCallersBytes) {
  SharedPacketParser parser;
  const Bytes first = kShb;
  auto a = parser.parse(first);
  ASSERT_TRUE(a);
  // A second station's copy of the frame (station-host hands each station its own view).
  const Bytes second = kShb;
  auto b = parser.parse(second);
  ASSERT_TRUE(b);
  EXPECT_EQ(parser.parsed(), 1u);
  EXPECT_EQ(parser.reused(), 1u);
  expect_same(b, parse_packet(second));
  EXPECT_EQ(b->payload.data(), second.data() + 40);  // not into the first caller's bytes
}

TEST(SharedPacketParser, GivesTheSourcesRowInItsSenderIndex) {
  SharedPacketParser parser;
  Bytes other = kShb;
  other[19] ^= 0x01;  // another source address: the last octet of the SO PV's MID
  Bytes truncated(kShb.begin(), kShb.begin() + 30);
  parser.parse(kShb);
  const auto row = parser.sender_row();
  ASSERT_NE(row, SenderIndex::kNoRow);
  EXPECT_EQ(parser.senders().key(row),
            source_position(parse_packet(kShb)->extended).address.mid_key());
  parser.parse(other);
  EXPECT_NE(parser.sender_row(), row);
  EXPECT_NE(parser.sender_row(), SenderIndex::kNoRow);
  parser.parse(kShb);
  EXPECT_EQ(parser.sender_row(), row);
  parser.parse(truncated);
  EXPECT_EQ(parser.sender_row(), SenderIndex::kNoRow);
}

TEST(SharedPacketParser, OtherBytesAndErrorsAreParsedAsParsePacketWould) {
  SharedPacketParser parser;
  Bytes later = kShb;
  later[21] ^= 0x01;  // another timestamp: another frame
  Bytes truncated(kShb.begin(), kShb.begin() + 30);
  Bytes bad_version = kShb;
  bad_version[0] = 0x21;
  for (const Bytes* b : std::vector<const Bytes*>{&kShb, &later, &later, &truncated, &truncated,
                                                  &bad_version, &kShb})
    expect_same(parser.parse(*b), parse_packet(*b));
  EXPECT_EQ(parser.parsed(), 5u);
  EXPECT_EQ(parser.reused(), 2u);
}

}  // namespace
}  // namespace tb::its::geonet
