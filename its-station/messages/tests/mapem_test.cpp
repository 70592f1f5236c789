// MAPEM (TS 103 301 v2.1.1, ISO TS 19091 MapData): a worked example whose bits were derived by
// hand from X.691, round trips at the bounds, and every kind of refusal.

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "its-station/messages/mapem.hpp"
#include "its-station/messages/spatem.hpp"
#include "its-station/messages/tests/bits.hpp"
#include "its-station/messages/tests/signal_samples.hpp"

namespace tb::its::messages {
namespace {

using asn1::Error;
using Bytes = std::vector<std::uint8_t>;
using testing::bits_of;
using testing::from_bits;
using testing::to_bits;
using testing::with_bits;

// clang-format off
// samples::mapem_one_lane(): 53 bytes, worked out as the SPATEM of spatem_test.cpp.
//  bit width component                      value                          bits
//    0   8  protocolVersion                 2                              00000010
//    8   8  messageID                       mapem (5)                      00000101
//   16  32  stationID                       1001                           00000000000000000000001111101001
//   48   1  MapData ext                                                    0
//   49   8  timeStamp? layerType? layerID? intersections? roadSegments? dataParameters? restrictionList? regional?
//                                                                          00010000
//   57   7  msgIssueRevision (0..127)       1                              0000001
//   64   5  intersections (SIZE(1..32))     1                              00000
//   69   1  IntersectionGeometry ext                                       0
//   70   5  name? laneWidth? speedLimits? preemptPriorityData? regional?   01000
//   75   1  id.region?                      absent                         0
//   76  16  id.id                           34                             0000000000100010
//   92   7  revision                        1                              0000001
//   99   1  Position3D ext                                                 0
//  100   2  elevation? regional?                                           00
//  102  31  lat (-900000000..900000001)     410255000                      1001110000110001110011110011000
//  133  32  long (-1800000000..1800000001)  289742000                      01111100100011101110111010110000
//  165  15  laneWidth (0..32767)            350 cm                         000000101011110
//  180   8  laneSet (SIZE(1..255))          1                              00000000
//  188   1  GenericLane ext                                                0
//  189   7  name? ingressApproach? egressApproach? maneuvers? connectsTo? overlays? regional?
//                                                                          0101100
//  196   8  laneID                          1                              00000001
//  204   4  ingressApproach (0..15)         1                              0001
//  208   1  LaneAttributes regional?        absent (no extension marker)   0
//  209   2  directionalUse (SIZE(2))        ingressPath (0)                10
//  211  10  sharedWith (SIZE(10))           none                           0000000000
//  221   1  LaneTypeAttributes ext                                         0
//  222   3  LaneTypeAttributes index        vehicle (0 of 8)               000
//  225   1  LaneAttributes-Vehicle size ext SIZE(8, ...) root              0
//  226   8  LaneAttributes-Vehicle          none                           00000000
//  234  12  maneuvers (SIZE(12))            straight (0), right (2)        101000000000
//  246   1  NodeListXY ext                                                 0
//  247   1  NodeListXY index                nodes (0 of 2)                 0
//  248   6  nodes (SIZE(2..63))             3                              000001
//  254   1  NodeXY ext                                                     0
//  255   1  attributes?                     present                        1
//  256   3  NodeOffsetPointXY index         node-XY3 (2 of 8)              010
//  259  12  x Offset-B12 (-2048..2047)      -175 cm                        011101010001
//  271  12  y                               -1200 cm                       001101010000
//  283   1  NodeAttributeSetXY ext                                         0
//  284   7  localNode? disabled? enabled? data? dWidth? dElevation? regional? 1000000
//  291   3  localNode (SIZE(1..8))          1                              000
//  294   1  NodeAttributeXY ext                                            0
//  295   4  NodeAttributeXY                 stopLine (1 of 12)             0001
//  299   1  NodeXY ext                                                     0
//  300   1  attributes?                     absent                         0
//  301   3  NodeOffsetPointXY index         node-XY2 (1)                   001
//  304  11  x Offset-B11 (-1024..1023)      0                              10000000000
//  315  11  y                               -1000 cm                       00000011000
//  326   1  NodeXY ext                                                     0
//  327   1  attributes?                     absent                         0
//  328   3  NodeOffsetPointXY index         node-XY1 (0)                   000
//  331  10  x Offset-B10 (-512..511)        0                              1000000000
//  341  10  y                               -500 cm                        0000001100
//  351   4  connectsTo (SIZE(1..16))        2                              0001
//  355   4  remoteIntersection? signalGroup? userClass? connectionID?      0100
//  359   1  connectingLane.maneuver?        present                        1
//  360   8  lane                            5                              00000101
//  368  12  maneuver                        straight (0)                   100000000000
//  380   8  signalGroup                     2                              00000010
//  388   4  remoteIntersection? signalGroup? userClass? connectionID?      0100
//  392   1  connectingLane.maneuver?        present                        1
//  393   8  lane                            7                              00000111
//  401  12  maneuver                        right (2)                      001000000000
//  413   8  signalGroup                     3                              00000011
//  421   3  padding                                                        000
const Bytes kMapemGolden = {
    0x02, 0x05, 0x00, 0x00, 0x03, 0xE9, 0x08, 0x01, 0x01, 0x00, 0x02, 0x20, 0x22, 0x70,
    0xC7, 0x3C, 0xC3, 0xE4, 0x77, 0x75, 0x80, 0x15, 0xE0, 0x02, 0xC0, 0x11, 0x40, 0x00,
    0x00, 0x28, 0x00, 0x05, 0x4E, 0xA2, 0x6A, 0x08, 0x00, 0x21, 0x80, 0x00, 0x60, 0x10,
    0x00, 0x18, 0x29, 0x05, 0x80, 0x00, 0x24, 0x83, 0x90, 0x00, 0x18,
};
// clang-format on
constexpr std::size_t kGoldenBits = 421;

Bytes must_encode(const Mapem& m) {
  auto bytes = encode(m);
  EXPECT_TRUE(bytes) << asn1::to_string(bytes.error());
  return bytes ? *bytes : Bytes{};
}

std::unique_ptr<Mapem> must_decode(const Bytes& bytes) {
  auto m = std::make_unique<Mapem>();
  auto n = decode(bytes, *m);
  EXPECT_TRUE(n) << asn1::to_string(n.error());
  return m;
}

CodecError decode_error(const Bytes& bytes) {
  auto m = std::make_unique<Mapem>();
  auto n = decode(bytes, *m);
  EXPECT_FALSE(n);
  return n ? CodecError{} : n.error();
}

CodecError encode_error(const Mapem& m) {
  auto bytes = encode(m);
  EXPECT_FALSE(bytes);
  return bytes ? CodecError{} : bytes.error();
}

std::string golden_bits() {
  return to_bits(kMapemGolden).substr(0, kGoldenBits);
}

TEST(Mapem, OneLaneWithTwoConnectionsEncodesToTheWorkedOutBytes) {
  const auto sample = samples::mapem_one_lane();
  EXPECT_EQ(must_encode(*sample), kMapemGolden);
  EXPECT_EQ(*must_decode(kMapemGolden), *sample);
}

TEST(Mapem, EncodesIntoTheCallersBufferAndSaysWhenItIsTooSmall) {
  const auto sample = samples::mapem_one_lane();
  Bytes buf(kMapemGolden.size());
  auto n = encode(*sample, buf);
  ASSERT_TRUE(n) << asn1::to_string(n.error());
  EXPECT_EQ(buf, kMapemGolden);
  Bytes small(kMapemGolden.size() - 1);
  auto r = encode(*sample, small);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, Error::kBufferTooSmall);
}

TEST(Mapem, EveryOptionalAtBothEndsOfItsRangeRoundTripsBitForBit) {
  for (bool upper : {false, true}) {
    const auto sample = samples::mapem_at_bounds(upper);
    const Bytes bytes = must_encode(*sample);
    ASSERT_FALSE(bytes.empty());
    EXPECT_LE(bytes.size(), kMapemMaxEncodedSize);
    const auto back = must_decode(bytes);
    EXPECT_TRUE(*back == *sample) << upper;
    EXPECT_EQ(must_encode(*back), bytes) << upper;
  }
}

TEST(Mapem, TheTypicalJunctionRoundTrips) {
  const auto sample = samples::mapem_typical();
  const Bytes bytes = must_encode(*sample);
  EXPECT_EQ(*must_decode(bytes), *sample);
}

TEST(Mapem, NodeXyPicksTheSmallestAlternativeThatHoldsTheOffset) {
  using C = NodeOffsetPointXY::Choice;
  // Offset-B10 is -512..511 cm, B11 -1024..1023, ..., B16 -32768..32767.
  EXPECT_EQ(node_xy(511, -512).choice, C::node_XY1);
  EXPECT_EQ(node_xy(512, 0).choice, C::node_XY2);
  EXPECT_EQ(node_xy(0, -1025).choice, C::node_XY3);
  EXPECT_EQ(node_xy(2048, 0).choice, C::node_XY4);
  EXPECT_EQ(node_xy(-4097, 0).choice, C::node_XY5);
  EXPECT_EQ(node_xy(8192, 8191).choice, C::node_XY6);
  EXPECT_EQ(node_xy(32767, -32768).choice, C::node_XY6);
  // Beyond 327.67 m there is no XY alternative: the encoder says so.
  auto m = samples::mapem_one_lane();
  std::get<NodeSetXY>((*m->map.intersections)[0].laneSet[0].nodeList)[1].delta = node_xy(32768, 0);
  const CodecError e = encode_error(*m);
  EXPECT_EQ(e.code, Error::kValueOutOfRange);
  EXPECT_STREQ(e.field, "x");
}

GenericLane& lane0(Mapem& m) {
  return (*m.map.intersections)[0].laneSet[0];
}
NodeXY& node0(Mapem& m) {
  return std::get<NodeSetXY>(lane0(m).nodeList)[0];
}

TEST(Mapem, EncoderRejectsEveryFieldOutsideItsConstraintNamingIt) {
  struct Case {
    const char* field;
    Error code;
    void (*mutate)(Mapem&);
  };
  using C = NodeOffsetPointXY::Choice;
  const Case cases[] = {
      {"timeStamp", Error::kValueOutOfRange, [](Mapem& m) { m.map.timeStamp = 527041; }},
      {"msgIssueRevision", Error::kValueOutOfRange, [](Mapem& m) { m.map.msgIssueRevision = 128; }},
      {"layerType", Error::kValueOutOfRange,
       [](Mapem& m) { m.map.layerType = static_cast<LayerType>(8); }},
      {"layerID", Error::kValueOutOfRange, [](Mapem& m) { m.map.layerID = 101; }},
      {"intersections", Error::kSizeOutOfRange, [](Mapem& m) { m.map.intersections->clear(); }},
      {"name", Error::kSizeOutOfRange, [](Mapem& m) { (*m.map.intersections)[0].name.emplace(); }},
      {"revision", Error::kValueOutOfRange,
       [](Mapem& m) { (*m.map.intersections)[0].revision = 200; }},
      {"lat", Error::kValueOutOfRange,
       [](Mapem& m) { (*m.map.intersections)[0].refPoint.lat = 900000002; }},
      {"long", Error::kValueOutOfRange,
       [](Mapem& m) { (*m.map.intersections)[0].refPoint.long_ = -1800000001; }},
      {"elevation", Error::kValueOutOfRange,
       [](Mapem& m) { (*m.map.intersections)[0].refPoint.elevation = 61440; }},
      {"laneWidth", Error::kValueOutOfRange,
       [](Mapem& m) { (*m.map.intersections)[0].laneWidth = 32768; }},
      {"speedLimits", Error::kSizeOutOfRange,
       [](Mapem& m) { (*m.map.intersections)[0].speedLimits.emplace(); }},
      {"speed", Error::kValueOutOfRange,
       [](Mapem& m) {
         (*m.map.intersections)[0].speedLimits.emplace().push_back({SpeedLimitType::unknown, 8192});
       }},
      {"type", Error::kValueOutOfRange,
       [](Mapem& m) {
         (*m.map.intersections)[0].speedLimits.emplace().push_back(
             {static_cast<SpeedLimitType>(13), 0});
       }},
      {"laneSet", Error::kSizeOutOfRange,
       [](Mapem& m) { (*m.map.intersections)[0].laneSet.clear(); }},
      {"ingressApproach", Error::kValueOutOfRange, [](Mapem& m) { lane0(m).ingressApproach = 16; }},
      {"egressApproach", Error::kValueOutOfRange, [](Mapem& m) { lane0(m).egressApproach = 16; }},
      {"directionalUse", Error::kValueOutOfRange,
       [](Mapem& m) { lane0(m).laneAttributes.directionalUse = 4; }},
      {"sharedWith", Error::kValueOutOfRange,
       [](Mapem& m) { lane0(m).laneAttributes.sharedWith = 0x400; }},
      {"laneType", Error::kValueOutOfRange,
       [](Mapem& m) { lane0(m).laneAttributes.laneType.bits = 0x100; }},  // vehicle: 8 bits
      {"laneType", Error::kValueOutOfRange,
       [](Mapem& m) {
         lane0(m).laneAttributes.laneType.choice = static_cast<LaneTypeAttributes::Choice>(8);
       }},
      {"maneuvers", Error::kValueOutOfRange, [](Mapem& m) { lane0(m).maneuvers = 0x1000; }},
      {"nodes", Error::kSizeOutOfRange,
       [](Mapem& m) { std::get<NodeSetXY>(lane0(m).nodeList).resize_down(1); }},
      {"x", Error::kValueOutOfRange,
       [](Mapem& m) {
         node0(m).delta = {C::node_XY1, 512, 0};
       }},
      {"y", Error::kValueOutOfRange,
       [](Mapem& m) {
         node0(m).delta = {C::node_XY5, 0, -8193};
       }},
      {"lat", Error::kValueOutOfRange,
       [](Mapem& m) {
         node0(m).delta = {C::node_LatLon, 0, 900000002};
       }},
      {"delta", Error::kValueOutOfRange,
       [](Mapem& m) { node0(m).delta.choice = static_cast<C>(7); }},
      {"localNode", Error::kSizeOutOfRange,
       [](Mapem& m) { node0(m).attributes->localNode->clear(); }},
      {"localNode", Error::kValueOutOfRange,
       [](Mapem& m) { (*node0(m).attributes->localNode)[0] = static_cast<NodeAttributeXY>(12); }},
      {"enabled", Error::kValueOutOfRange,
       [](Mapem& m) { node0(m).attributes->enabled.emplace().push_back(38); }},
      {"disabled", Error::kSizeOutOfRange,
       [](Mapem& m) { node0(m).attributes->disabled.emplace(); }},
      {"dWidth", Error::kValueOutOfRange, [](Mapem& m) { node0(m).attributes->dWidth = 512; }},
      {"dElevation", Error::kValueOutOfRange,
       [](Mapem& m) { node0(m).attributes->dElevation = -513; }},
      {"offsetXaxis", Error::kValueOutOfRange,
       [](Mapem& m) {
         lane0(m).nodeList = ComputedLane{1, {false, 2048}, {}, {}, {}, {}};
       }},
      {"offsetYaxis", Error::kValueOutOfRange,
       [](Mapem& m) {
         lane0(m).nodeList = ComputedLane{1, {}, {true, -32768}, {}, {}, {}};
       }},
      {"rotateXY", Error::kValueOutOfRange,
       [](Mapem& m) { lane0(m).nodeList = ComputedLane{1, {}, {}, 28801, {}, {}}; }},
      {"scaleYaxis", Error::kValueOutOfRange,
       [](Mapem& m) { lane0(m).nodeList = ComputedLane{1, {}, {}, {}, {}, 2048}; }},
      {"connectsTo", Error::kSizeOutOfRange, [](Mapem& m) { lane0(m).connectsTo->clear(); }},
      {"maneuver", Error::kValueOutOfRange,
       [](Mapem& m) { (*lane0(m).connectsTo)[0].connectingLane.maneuver = 0x1000; }},
      {"overlays", Error::kSizeOutOfRange, [](Mapem& m) { lane0(m).overlays.emplace(); }},
      {"processAgency", Error::kSizeOutOfRange,
       [](Mapem& m) { m.map.dataParameters.emplace().processAgency.emplace(); }},
      {"geoidUsed", Error::kValueOutOfRange,
       [](Mapem& m) { m.map.dataParameters.emplace().geoidUsed = char_string<255>("\xE9"); }},
      {"restrictionList", Error::kSizeOutOfRange,
       [](Mapem& m) { m.map.restrictionList.emplace(); }},
      {"users", Error::kSizeOutOfRange,
       [](Mapem& m) { m.map.restrictionList.emplace().emplace_back(); }},
      {"basicType", Error::kValueOutOfRange,
       [](Mapem& m) { m.map.restrictionList.emplace().emplace_back().users.push_back(14); }},
  };
  for (const Case& c : cases) {
    auto m = samples::mapem_one_lane();
    c.mutate(*m);
    const CodecError e = encode_error(*m);
    EXPECT_EQ(e.code, c.code) << c.field << ": " << asn1::to_string(e);
    EXPECT_STREQ(e.field, c.field) << asn1::to_string(e);
  }
}

TEST(Mapem, EncoderChecksMessageIdAndVersion) {
  auto m = samples::mapem_one_lane();
  m->header.messageID = kMessageIdSpatem;
  EXPECT_EQ(encode_error(*m).code, Error::kWrongMessageId);
  m->header.messageID = kMessageIdMapem;
  m->header.protocolVersion = 1;
  EXPECT_EQ(encode_error(*m).code, Error::kUnsupportedVersion);
}

TEST(Mapem, DecoderRejectsEveryTruncation) {
  for (const Bytes& bytes : {kMapemGolden, must_encode(*samples::mapem_at_bounds(false)),
                             must_encode(*samples::mapem_typical())}) {
    for (std::size_t n = 0; n < bytes.size(); ++n) {
      const CodecError e = decode_error(Bytes(bytes.begin(), bytes.begin() + n));
      EXPECT_EQ(e.code, Error::kTruncated) << n << ": " << asn1::to_string(e);
    }
  }
}

TEST(Mapem, DecoderNeverMisreadsAMessageCutAtAnyBit) {
  auto m = std::make_unique<Mapem>();
  for (const Bytes& whole : {kMapemGolden, must_encode(*samples::mapem_at_bounds(false)),
                             must_encode(*samples::mapem_typical())}) {
    const std::string bits = to_bits(whole);
    for (std::size_t n = 0; n < bits.size(); ++n) {
      const Bytes cut = from_bits(bits.substr(0, n));
      auto r = decode(cut, *m);
      if (cut.size() < whole.size()) {
        ASSERT_FALSE(r) << n;
        EXPECT_EQ(r.error().code, Error::kTruncated) << n << ": " << asn1::to_string(r.error());
      } else if (r) {
        EXPECT_EQ(must_encode(*m), cut) << n;
      }
    }
  }
}

TEST(Mapem, DecoderRejectsTrailingOctets) {
  Bytes bytes = kMapemGolden;
  bytes.push_back(0);
  EXPECT_EQ(decode_error(bytes).code, Error::kTrailingData);
}

TEST(Mapem, DecoderRejectsOtherMessagesAndVersions) {
  auto spatem = encode(*samples::spatem_two_groups());
  ASSERT_TRUE(spatem);
  const CodecError e = decode_error(*spatem);
  EXPECT_EQ(e.code, Error::kWrongMessageId);
  EXPECT_EQ(e.value, kMessageIdSpatem);
  for (unsigned v : {1u, 3u, 255u})
    EXPECT_EQ(decode_error(with_bits(kMapemGolden, 0, 8, v)).code, Error::kUnsupportedVersion);
}

TEST(Mapem, DecoderRejectsValuesOutsideTheirConstraintAndSizesAboveTheHeldBound) {
  struct Case {
    std::size_t bit;
    unsigned width;
    std::uint64_t value;
    Error code;
    const char* field;
  };
  const Case cases[] = {
      {102, 31, 0x7FFFFFFF, Error::kValueOutOfRange, "lat"},
      {133, 32, 0xFFFFFFFF, Error::kValueOutOfRange, "long"},
      {64, 5, kIntersectionGeometriesMax, Error::kSizeOutOfRange, "intersections"},
      {180, 8, kLanesMax, Error::kSizeOutOfRange, "laneSet"},
      {295, 4, 12, Error::kValueOutOfRange, "localNode"},  // NodeAttributeXY has 12 roots
      {221, 1, 1, Error::kUnknownExtension, "laneType"},   // a LaneTypeAttributes extension
      {225, 1, 1, Error::kUnknownExtension, "laneType"},   // LaneAttributes-Vehicle > 8 bits
      {246, 1, 1, Error::kUnknownExtension, "nodeList"},   // a NodeListXY extension
      {256, 3, 7, Error::kUnsupported, "delta regional"},
      {287, 1, 1, Error::kUnsupported, "data"},
      {53, 1, 1, Error::kUnsupported, "roadSegments"},
  };
  for (const Case& c : cases) {
    const CodecError e = decode_error(with_bits(kMapemGolden, c.bit, c.width, c.value));
    EXPECT_EQ(e.code, c.code) << c.field << ": " << asn1::to_string(e);
    EXPECT_STREQ(e.field, c.field) << asn1::to_string(e);
  }
}

TEST(Mapem, DecoderRefusesARegionalRestrictionUserType) {
  auto m = samples::mapem_one_lane();
  m->map.restrictionList.emplace().push_back({9, {3}});
  std::string bits = to_bits(must_encode(*m));
  // After the golden part: the list's size (8 bits), id (8), users' size (4), the CHOICE's
  // extension bit, then its index: 1 is regional.
  ASSERT_EQ(bits[kGoldenBits + 21], '0');
  bits[kGoldenBits + 21] = '1';
  const CodecError e = decode_error(from_bits(bits));
  EXPECT_EQ(e.code, Error::kUnsupported);
  EXPECT_STREQ(e.field, "users regional");
}

TEST(Mapem, DecoderSkipsRegionalExtensionsPreemptZonesAndLaterVersionsAdditions) {
  std::string bits = golden_bits();
  const std::string open_type = bits_of(2, 8) + bits_of(0xBEEF, 16);
  // Appended at the end first, so that the offsets before stay those of the table.
  // preemptPriorityData: presence bit, then after laneSet SIZE(1..32) = 1 and a
  // SignalControlZone {ext 0, zone RegionalExtension {regionId, open type}}.
  bits.replace(73, 1, "1");
  bits += bits_of(0, 5) + "0" + bits_of(3, 8) + open_type;
  // An extension addition of MapData: extension bit, count 1, bitmap, open type.
  bits.replace(48, 1, "1");
  bits += "0" + bits_of(0, 6) + "1" + bits_of(1, 8) + bits_of(0x5A, 8);
  // A regional extension of the reference point (Position3D-addGrpC): after its longitude.
  bits.replace(101, 1, "1");
  bits.insert(165, "00" + bits_of(3, 8) + open_type);
  const auto back = must_decode(from_bits(bits));
  EXPECT_EQ(*back, *samples::mapem_one_lane());
  EXPECT_EQ(must_encode(*back), kMapemGolden);
}

TEST(Mapem, DecodingIntoAUsedObjectClearsWhatTheNewMessageLacks) {
  auto m = samples::mapem_at_bounds(true);
  ASSERT_TRUE(decode(kMapemGolden, *m));
  EXPECT_EQ(*m, *samples::mapem_one_lane());
}

TEST(Mapem, RandomValidMessagesRoundTrip) {
  std::mt19937 rng(35);
  auto pick = [&](std::int64_t lo, std::int64_t hi) {
    return std::uniform_int_distribution<std::int64_t>(lo, hi)(rng);
  };
  auto maybe = [&] { return pick(0, 1) == 1; };
  auto m = std::make_unique<Mapem>();
  for (int round = 0; round < 100; ++round) {
    *m = Mapem{};
    m->header.stationID = static_cast<StationID>(pick(0, 0xFFFFFFFF));
    m->map.msgIssueRevision = static_cast<MsgCount>(pick(0, 127));
    if (maybe())
      m->map.layerType = static_cast<LayerType>(pick(0, 7));
    IntersectionGeometry& g = m->map.intersections.emplace().emplace_back();
    g.id.id = static_cast<IntersectionID>(pick(0, 65535));
    g.refPoint = {static_cast<Latitude>(pick(-900000000, 900000001)),
                  static_cast<Longitude>(pick(-1800000000, 1800000001)), std::nullopt};
    if (maybe())
      g.refPoint.elevation = static_cast<Elevation>(pick(-4096, 61439));
    const auto lanes = pick(1, 12);
    for (std::int64_t li = 0; li < lanes; ++li) {
      GenericLane& l = g.laneSet.emplace_back();
      l.laneID = static_cast<LaneID>(pick(0, 255));
      l.laneAttributes.directionalUse = static_cast<LaneDirection>(pick(0, 3));
      l.laneAttributes.laneType.choice = static_cast<LaneTypeAttributes::Choice>(pick(0, 7));
      l.laneAttributes.laneType.bits = static_cast<std::uint16_t>(
          l.laneAttributes.laneType.choice == LaneTypeAttributes::Choice::vehicle ? pick(0, 255)
                                                                                  : pick(0, 65535));
      NodeSetXY& nodes = l.nodeList.emplace<NodeSetXY>();
      const auto n = pick(2, 8);
      for (std::int64_t k = 0; k < n; ++k) {
        NodeXY& node = nodes.emplace_back();
        node.delta = node_xy(static_cast<std::int32_t>(pick(-32768, 32767)),
                             static_cast<std::int32_t>(pick(-600, 600)));
        if (maybe())
          node.attributes.emplace().dWidth = static_cast<std::int16_t>(pick(-512, 511));
      }
      if (maybe()) {
        Connection& c = l.connectsTo.emplace().emplace_back();
        c.connectingLane.lane = static_cast<LaneID>(pick(0, 255));
        if (maybe())
          c.signalGroup = static_cast<SignalGroupID>(pick(0, 255));
        if (maybe())
          c.remoteIntersection = IntersectionReferenceID{std::nullopt, 7};
      }
    }
    const Bytes bytes = must_encode(*m);
    const auto back = must_decode(bytes);
    ASSERT_TRUE(*back == *m) << round;
    ASSERT_EQ(must_encode(*back), bytes) << round;
  }
}

}  // namespace
}  // namespace tb::its::messages
