#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "its-station/messages/cam.hpp"
#include "its-station/messages/denm.hpp"
#include "its-station/messages/tests/bits.hpp"
#include "its-station/messages/tests/samples.hpp"

namespace tb::its::messages {
namespace {

using asn1::Error;
using testing::bits_of;
using testing::from_bits;
using testing::to_bits;
using testing::with_bits;
using Bytes = std::vector<std::uint8_t>;

Bytes must_encode(const Denm& d) {
  auto bytes = encode(d);
  EXPECT_TRUE(bytes) << asn1::to_string(bytes.error());
  return bytes ? *bytes : Bytes{};
}

void expect_round_trip(const Denm& d) {
  const Bytes bytes = must_encode(d);
  auto back = decode_denm(bytes);
  ASSERT_TRUE(back) << asn1::to_string(back.error());
  EXPECT_EQ(*back, d);
  EXPECT_EQ(must_encode(*back), bytes);
}

TEST(Denm, RoundTripOfEveryFieldAtItsBounds) {
  expect_round_trip(samples::denm_at_bounds(false));
  const Denm upper = samples::denm_at_bounds(true);
  expect_round_trip(upper);
  EXPECT_LE(must_encode(upper).size(), kDenmMaxEncodedSize);
}

TEST(Denm, ManagementOnlyAndEmptyTraceRoundTrip) {
  Denm d = samples::denm_collision_risk();
  d.denm.situation.reset();
  d.denm.location.reset();
  expect_round_trip(d);
  d = samples::denm_collision_risk();
  d.denm.location->traces[0].clear();  // one trace without points: SIZE(1..7) of SIZE(0..40)
  expect_round_trip(d);
}

TEST(Denm, DefaultValidityIsLeftOutAndRestored) {
  Denm d = samples::denm_collision_risk();
  d.denm.management.validityDuration = kDefaultValidity;
  const Bytes with_default = must_encode(d);
  const std::string bits = to_bits(with_default);
  EXPECT_EQ(bits[55], '0');             // validityDuration presence bit (golden table, bit 55)
  EXPECT_EQ(with_default.size(), 68u);  // 538 bits: the golden 555 less 17 of validityDuration
  auto back = decode_denm(with_default);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->denm.management.validityDuration, kDefaultValidity);
  // An encoder that sends the default explicitly (BASIC-PER allows it) decodes the same.
  std::string explicit_bits = bits.substr(0, 317);
  explicit_bits[55] = '1';
  explicit_bits += bits_of(600, 17) + bits.substr(317, 538 - 317);
  auto explicit_back = decode_denm(from_bits(explicit_bits));
  ASSERT_TRUE(explicit_back) << asn1::to_string(explicit_back.error());
  EXPECT_EQ(*explicit_back, d);
}

TEST(Denm, EncoderRejectsOutOfRangeAndEmptySequences) {
  struct Case {
    const char* field;
    void (*spoil)(Denm&);
    Error code;
  };
  const Case cases[] = {
      {"detectionTime", [](Denm& d) { d.denm.management.detectionTime = kTimestampItsMax + 1; },
       Error::kValueOutOfRange},
      {"referenceTime", [](Denm& d) { d.denm.management.referenceTime = ~TimestampIts{0}; },
       Error::kValueOutOfRange},
      {"validityDuration", [](Denm& d) { d.denm.management.validityDuration = 86401; },
       Error::kValueOutOfRange},
      {"transmissionInterval", [](Denm& d) { d.denm.management.transmissionInterval = 0; },
       Error::kValueOutOfRange},
      {"transmissionInterval", [](Denm& d) { d.denm.management.transmissionInterval = 10001; },
       Error::kValueOutOfRange},
      {"termination", [](Denm& d) { d.denm.management.termination = Termination{2}; },
       Error::kValueOutOfRange},
      {"relevanceDistance",
       [](Denm& d) { d.denm.management.relevanceDistance = RelevanceDistance{8}; },
       Error::kValueOutOfRange},
      {"informationQuality", [](Denm& d) { d.denm.situation->informationQuality = 8; },
       Error::kValueOutOfRange},
      {"roadType", [](Denm& d) { d.denm.location->roadType = RoadType{4}; },
       Error::kValueOutOfRange},
      {"traces", [](Denm& d) { d.denm.location->traces.clear(); }, Error::kSizeOutOfRange},
      {"eventHistory", [](Denm& d) { d.denm.situation->eventHistory.emplace(); },
       Error::kSizeOutOfRange},
      {"externalTemperature", [](Denm& d) { d.denm.alacarte.emplace().externalTemperature = 68; },
       Error::kValueOutOfRange},
      {"positioningSolution",
       [](Denm& d) { d.denm.alacarte.emplace().positioningSolution = PositioningSolutionType{6}; },
       Error::kValueOutOfRange},
      {"messageID", [](Denm& d) { d.header.messageID = kMessageIdCam; }, Error::kWrongMessageId},
  };
  for (const Case& c : cases) {
    Denm d = samples::denm_collision_risk();
    c.spoil(d);
    auto r = encode(d);
    ASSERT_FALSE(r) << c.field;
    EXPECT_EQ(r.error().code, c.code) << c.field;
    EXPECT_STREQ(r.error().field, c.field);
  }
}

TEST(Denm, ProtocolVersion1CauseCodesHaveNoExtensionBit) {
  Denm v1 = samples::as_version1(samples::denm_at_bounds(true));
  expect_round_trip(v1);
  Denm v2 = samples::denm_collision_risk();
  v1 = v2;
  v1.header.protocolVersion = kProtocolVersion1;
  const std::string b1 = to_bits(must_encode(v1));
  const std::string b2 = to_bits(must_encode(v2));
  // eventType starts at bit 362 (golden table): v2 has the extension bit there.
  EXPECT_EQ(b2.substr(362, 17), "0" + bits_of(97, 8) + bits_of(1, 8));
  EXPECT_EQ(b1.substr(362, 16), bits_of(97, 8) + bits_of(1, 8));
  EXPECT_EQ(b1.substr(378, 555 - 379), b2.substr(379, 555 - 379));
  auto back = decode_denm(must_encode(v1));
  ASSERT_TRUE(back);
  EXPECT_EQ(*back, v1);
}

TEST(Denm, DecoderRejectsEveryTruncation) {
  for (const Denm& sample : {samples::denm_collision_risk(), samples::denm_at_bounds(true)}) {
    const Bytes bytes = must_encode(sample);
    for (std::size_t n = 0; n < bytes.size(); ++n) {
      auto r = decode_denm(std::span<const std::uint8_t>(bytes).first(n));
      ASSERT_FALSE(r) << n;
      EXPECT_EQ(r.error().code, Error::kTruncated) << n << ": " << asn1::to_string(r.error());
    }
  }
}

TEST(Denm, DecoderRejectsCamsOtherVersionsAndBadValues) {
  auto cam = encode(samples::cam_hf());
  ASSERT_TRUE(cam);
  auto r = decode_denm(*cam);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, Error::kWrongMessageId);

  const Bytes golden = must_encode(samples::denm_collision_risk());
  auto v3 = decode_denm(with_bits(golden, 0, 8, 3));
  ASSERT_FALSE(v3);
  EXPECT_EQ(v3.error().code, Error::kUnsupportedVersion);

  struct Case {
    std::size_t bit;
    unsigned width;
    std::uint64_t raw;
    const char* field;
  };
  const Case cases[] = {
      {317, 17, 86401, "validityDuration"},
      {334, 14, 10000, "transmissionInterval"},  // raw 10000 is value 10001
      {404, 12, 3602, "headingValue"},
      {416, 7, 127, "headingConfidence"},  // raw 127 is value 128
      {469, 15, 25501, "deltaAltitude"},
  };
  for (const Case& c : cases) {
    auto bad = decode_denm(with_bits(golden, c.bit, c.width, c.raw));
    ASSERT_FALSE(bad) << c.field;
    EXPECT_EQ(bad.error().code, Error::kValueOutOfRange) << c.field;
    EXPECT_STREQ(bad.error().field, c.field);
    EXPECT_EQ(bad.error().bit_offset, c.bit);
  }
  // traces SIZE(1..7) in 3 bits: 7 is size 8.
  auto traces = decode_denm(with_bits(golden, 423, 3, 7));
  ASSERT_FALSE(traces);
  EXPECT_EQ(traces.error().code, Error::kValueOutOfRange);
  EXPECT_STREQ(traces.error().field, "traces");

  Bytes longer = golden;
  longer.push_back(0xFF);
  auto trailing = decode_denm(longer);
  ASSERT_FALSE(trailing);
  EXPECT_EQ(trailing.error().code, Error::kTrailingData);
}

Denm with_alacarte() {
  Denm d = samples::denm_collision_risk();
  d.denm.alacarte = samples::alacarte_full();
  return d;
}

TEST(Denm, EveryAlacarteMemberRoundTripsInBothVersions) {
  expect_round_trip(with_alacarte());
  // Each member alone, and the container empty.
  const AlacarteContainer full = samples::alacarte_full();
  for (int member = 0; member < 7; ++member) {
    Denm d = samples::denm_collision_risk();
    AlacarteContainer& a = d.denm.alacarte.emplace();
    if (member == 0)
      a.lanePosition = full.lanePosition;
    if (member == 1)
      a.impactReduction = full.impactReduction;
    if (member == 2)
      a.externalTemperature = full.externalTemperature;
    if (member == 3)
      a.roadWorks = full.roadWorks;
    if (member == 4)
      a.positioningSolution = full.positioningSolution;
    if (member == 5)
      a.stationaryVehicle = full.stationaryVehicle;
    expect_round_trip(d);
  }
  // The unavailable defaults of ImpactReductionContainer are valid values.
  Denm d = samples::denm_collision_risk();
  d.denm.alacarte.emplace().impactReduction.emplace();
  expect_round_trip(d);

  // protocolVersion 1: ClosedLanes {hardShoulderStatus, drivingLaneStatus (SIZE(1..14)), ...},
  // DangerousGoodsExtended without extension marker and with an IA5String phoneNumber,
  // CauseCode without extension marker.
  Denm v1 = with_alacarte();
  v1.header.protocolVersion = kProtocolVersion1;
  expect_round_trip(v1);
  // v1's DangerousGoodsExtended: no extension bit before the three presence bits, and the
  // phone number as an IA5String SIZE(1..24) (5-bit length, 7 bits a character).
  auto ia5 = [](const char* t) {
    std::string b;
    for (; *t != '\0'; ++t)
      b += bits_of(static_cast<unsigned char>(*t), 7);
    return b;
  };
  const std::string goods_v1 = "111" + bits_of(9, 5) + bits_of(1203, 14) + "010" + bits_of(2, 5) +
                               ia5("3YE") + bits_of(2, 5) + ia5("112") + bits_of(7, 8) +
                               bits_of(0xC3, 8);
  const std::string goods_v2 = "0" + goods_v1.substr(0, 3 + 5 + 14 + 3 + 5 + 21) + bits_of(2, 4) +
                               bits_of(2, 4) + bits_of(2, 4) + bits_of(3, 4) + bits_of(7, 8) +
                               bits_of(0xC3, 8);
  const std::string b1 = to_bits(must_encode(v1));
  const std::string b2 = to_bits(must_encode(with_alacarte()));
  EXPECT_NE(b1.find(goods_v1), std::string::npos);
  EXPECT_EQ(b1.find(goods_v2), std::string::npos);
  EXPECT_NE(b2.find(goods_v2), std::string::npos);
  // v1's outer hard shoulder and 14-bit driving-lane status.
  v1.denm.alacarte->roadWorks->closedLanes->drivingLaneStatus = DrivingLaneStatus{0x3FFF, 14};
  expect_round_trip(v1);
  Denm v1_bad = v1;
  v1_bad.denm.alacarte->roadWorks->closedLanes->innerhardShoulderStatus =
      HardShoulderStatus::closed;
  auto inner = encode(v1_bad);
  ASSERT_FALSE(inner);
  EXPECT_STREQ(inner.error().field, "innerhardShoulderStatus");
  // A version-1 phone number may hold any IA5 character and 24 of them.
  v1.denm.alacarte->stationaryVehicle->carryingDangerousGoods->phoneNumber =
      char_string<24>("+49 (89) 1234-5678 ext 9");
  expect_round_trip(v1);
  Denm v2 = with_alacarte();
  v2.denm.alacarte->stationaryVehicle->carryingDangerousGoods->phoneNumber =
      char_string<24>("+49 89");
  auto plus = encode(v2);
  ASSERT_FALSE(plus);
  EXPECT_STREQ(plus.error().field, "phoneNumber");
}

TEST(Denm, AlacarteEncoderRejectsValuesAndSizesOutsideTheConstraints) {
  struct Case {
    const char* field;
    void (*spoil)(AlacarteContainer&);
    Error code;
  };
  const Case cases[] = {
      {"heightLonCarrLeft", [](AlacarteContainer& a) { a.impactReduction->heightLonCarrLeft = 0; },
       Error::kValueOutOfRange},
      {"posCentMass", [](AlacarteContainer& a) { a.impactReduction->posCentMass = 64; },
       Error::kValueOutOfRange},
      {"vehicleMass", [](AlacarteContainer& a) { a.impactReduction->vehicleMass = 1025; },
       Error::kValueOutOfRange},
      {"positionOfOccupants",
       [](AlacarteContainer& a) { a.impactReduction->positionOfOccupants = 1u << 20; },
       Error::kValueOutOfRange},
      {"positionOfPillars", [](AlacarteContainer& a) { a.impactReduction->positionOfPillars = {}; },
       Error::kSizeOutOfRange},
      {"posPillar", [](AlacarteContainer& a) { a.impactReduction->positionOfPillars = {31}; },
       Error::kValueOutOfRange},
      {"restriction", [](AlacarteContainer& a) { a.roadWorks->restriction.emplace(); },
       Error::kSizeOutOfRange},
      {"recommendedPath", [](AlacarteContainer& a) { a.roadWorks->recommendedPath.emplace(); },
       Error::kSizeOutOfRange},
      {"referenceDenms", [](AlacarteContainer& a) { a.roadWorks->referenceDenms.emplace(); },
       Error::kSizeOutOfRange},
      {"speedLimit", [](AlacarteContainer& a) { a.roadWorks->speedLimit = 0; },
       Error::kValueOutOfRange},
      {"drivingLaneStatus",
       [](AlacarteContainer& a) {
         a.roadWorks->closedLanes->drivingLaneStatus = {0, 14};
       },
       Error::kValueOutOfRange},
      {"numberOfOccupants",
       [](AlacarteContainer& a) { a.stationaryVehicle->numberOfOccupants = 128; },
       Error::kValueOutOfRange},
      {"unNumber",
       [](AlacarteContainer& a) { a.stationaryVehicle->carryingDangerousGoods->unNumber = 10000; },
       Error::kValueOutOfRange},
      {"emergencyActionCode",
       [](AlacarteContainer& a) {
         a.stationaryVehicle->carryingDangerousGoods->emergencyActionCode.emplace();
       },
       Error::kSizeOutOfRange},
      {"emergencyActionCode",
       [](AlacarteContainer& a) {
         a.stationaryVehicle->carryingDangerousGoods->emergencyActionCode = char_string<24>("\xE9");
       },
       Error::kValueOutOfRange},
      {"phoneNumber",
       [](AlacarteContainer& a) {
         a.stationaryVehicle->carryingDangerousGoods->phoneNumber =
             char_string<24>("12345678901234567");  // 17 digits: SIZE(1..16)
       },
       Error::kSizeOutOfRange},
      {"companyName",
       [](AlacarteContainer& a) {
         a.stationaryVehicle->carryingDangerousGoods->companyName = {0xC3};  // cut sequence
       },
       Error::kValueOutOfRange},
      {"companyName",
       [](AlacarteContainer& a) {
         auto& c = a.stationaryVehicle->carryingDangerousGoods->companyName.emplace();
         for (int i = 0; i < 25; ++i)
           c.push_back('x');
       },
       Error::kSizeOutOfRange},
      {"vDS",
       [](AlacarteContainer& a) {
         a.stationaryVehicle->vehicleIdentification->vDS = char_string<6>("ZZZ1K");
       },
       Error::kSizeOutOfRange},
      {"energyStorageType",
       [](AlacarteContainer& a) { a.stationaryVehicle->energyStorageType = 128; },
       Error::kValueOutOfRange},
      {"dangerousGoodsType",
       [](AlacarteContainer& a) {
         a.stationaryVehicle->carryingDangerousGoods->dangerousGoodsType = 20;
       },
       Error::kValueOutOfRange},
  };
  for (const Case& c : cases) {
    Denm d = with_alacarte();
    c.spoil(*d.denm.alacarte);
    auto r = encode(d);
    ASSERT_FALSE(r) << c.field;
    EXPECT_EQ(r.error().code, c.code) << c.field << ": " << asn1::to_string(r.error());
    EXPECT_STREQ(r.error().field, c.field);
  }
}

// Offsets into with_alacarte()'s encoding, from the golden table in golden_test.cpp: the
// container starts at bit 555, positionOfPillars after its 7 head bits, lanePosition (4) and
// the four carrier fields (7 bits each).
constexpr std::size_t kAlacarte = 555;
constexpr std::size_t kPillarsExt = kAlacarte + 7 + 4 + 4 * 7;

TEST(Denm, AlacarteDecoderRejectsExtensionsBadCharactersAndEveryTruncation) {
  const Bytes bytes = must_encode(with_alacarte());
  const std::string bits = to_bits(bytes);
  // positionOfPillars SIZE(1..3, ...) with its extension bit set: a size this type cannot hold.
  ASSERT_EQ(bits.substr(kPillarsExt, 3), "001");
  auto pillars = decode_denm(with_bits(bytes, kPillarsExt, 1, 1));
  ASSERT_FALSE(pillars);
  EXPECT_EQ(pillars.error().code, Error::kUnknownExtension);
  EXPECT_STREQ(pillars.error().field, "positionOfPillars");

  // The StationaryVehicleContainer's head: six presence bits, lessThan2Minutes, stationaryCause.
  const std::string sv_head = "111111" + bits_of(1, 2) + "0" + bits_of(94, 8) + bits_of(2, 8);
  const std::size_t sv = bits.find(sv_head);
  ASSERT_NE(sv, std::string::npos);
  ASSERT_EQ(sv, bits.rfind(sv_head));
  // The phone number's first digit (index 2, '1') made 15: not in " 0123456789".
  // stationarySince 2, stationaryCause 17, DGE ext + 3 presence, type 5, unNumber 14, 3 flags,
  // emergencyActionCode 5 + 21: the phone number's length at sv + 6 + 2 + 17 + 4 + 5 + 14 + 3 + 26.
  const std::size_t phone = sv + 6 + 2 + 17 + 4 + 5 + 14 + 3 + 26;
  ASSERT_EQ(bits.substr(phone, 8), bits_of(2, 4) + bits_of(2, 4));
  auto digit = decode_denm(with_bits(bytes, phone + 4, 4, 15));
  ASSERT_FALSE(digit);
  EXPECT_EQ(digit.error().code, Error::kValueOutOfRange);
  EXPECT_STREQ(digit.error().field, "phoneNumber");
  // The company name's first octet (0xC3, a lead byte) made a continuation byte: not UTF-8.
  const std::size_t company = phone + 4 + 12;
  ASSERT_EQ(bits.substr(company, 16), bits_of(7, 8) + bits_of(0xC3, 8));
  auto utf8 = decode_denm(with_bits(bytes, company + 8, 8, 0x96));
  ASSERT_FALSE(utf8);
  EXPECT_EQ(utf8.error().code, Error::kValueOutOfRange);
  EXPECT_STREQ(utf8.error().field, "companyName");

  for (std::size_t n = 0; n < bytes.size(); ++n) {
    auto r = decode_denm(std::span<const std::uint8_t>(bytes).first(n));
    ASSERT_FALSE(r) << n;
    EXPECT_EQ(r.error().code, Error::kTruncated) << n << ": " << asn1::to_string(r.error());
  }
}

TEST(Denm, DecoderSkipsManagementExtensionAdditions) {
  std::string bits = to_bits(must_encode(samples::denm_collision_risk())).substr(0, 555);
  bits[51] = '1';  // management extension bit
  // After stationType (ends at bit 356): one addition, present, 3 octets.
  bits.insert(356, "0" + bits_of(0, 6) + "1" + bits_of(3, 8) + bits_of(0x123456, 24));
  auto r = decode_denm(from_bits(bits));
  ASSERT_TRUE(r) << asn1::to_string(r.error());
  EXPECT_EQ(*r, samples::denm_collision_risk());
}

TEST(Denm, RandomValidMessagesRoundTrip) {
  std::mt19937 rng(11);
  auto in = [&](std::int64_t lb, std::int64_t ub) {
    return std::uniform_int_distribution<std::int64_t>(lb, ub)(rng);
  };
  for (int i = 0; i < 500; ++i) {
    Denm d = samples::denm_collision_risk();
    ManagementContainer& m = d.denm.management;
    m.actionID = {static_cast<StationID>(in(0, 4294967295)),
                  static_cast<SequenceNumber>(in(0, 65535))};
    m.detectionTime = static_cast<TimestampIts>(in(0, 4398046511103));
    m.referenceTime = static_cast<TimestampIts>(in(0, 4398046511103));
    if (in(0, 1))
      m.termination = static_cast<Termination>(in(0, 1));
    else
      m.termination.reset();
    m.validityDuration = static_cast<ValidityDuration>(in(0, 86400));
    if (in(0, 1))
      m.transmissionInterval.reset();
    if (in(0, 1))
      d.denm.situation.reset();
    if (in(0, 1)) {
      d.denm.location->traces.clear();
      const auto traces = in(1, 7);
      for (std::int64_t t = 0; t < traces; ++t) {
        PathHistory& ph = d.denm.location->traces.emplace_back();
        const auto points = in(0, 40);
        for (std::int64_t k = 0; k < points; ++k)
          ph.push_back(
              PathPoint{{static_cast<DeltaLatitude>(in(-131071, 131072)),
                         static_cast<DeltaLongitude>(in(-131071, 131072)),
                         static_cast<DeltaAltitude>(in(-12700, 12800))},
                        in(0, 1) ? std::optional<PathDeltaTime>(in(1, 65535)) : std::nullopt});
      }
    }
    expect_round_trip(d);
    if (::testing::Test::HasFailure())
      break;
  }
}

}  // namespace
}  // namespace tb::its::messages
