#include <gtest/gtest.h>

#include <array>
#include <functional>
#include <random>
#include <string>
#include <type_traits>
#include <variant>
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

Bytes must_encode(const Cam& cam) {
  auto bytes = encode(cam);
  EXPECT_TRUE(bytes) << asn1::to_string(bytes.error());
  return bytes ? *bytes : Bytes{};
}

void expect_round_trip(const Cam& cam) {
  const Bytes bytes = must_encode(cam);
  auto back = decode_cam(bytes);
  ASSERT_TRUE(back) << asn1::to_string(back.error());
  EXPECT_EQ(*back, cam);
  EXPECT_EQ(must_encode(*back), bytes);
}

TEST(Cam, RoundTripOfEveryFieldAtItsLowerBound) {
  Cam cam = samples::cam_at_bounds(false);
  expect_round_trip(cam);
  cam.cam.camParameters.lowFrequencyContainer->pathHistory.push_back(
      PathPoint{{-131071, -131071, -12700}, 1});
  expect_round_trip(cam);
}

TEST(Cam, RoundTripOfEveryFieldAtItsUpperBound) {
  const Cam cam = samples::cam_at_bounds(true);
  expect_round_trip(cam);
  EXPECT_EQ(cam.cam.camParameters.lowFrequencyContainer->pathHistory.size(), kPathHistoryMaxPoints);
  EXPECT_LE(must_encode(cam).size(), kCamMaxEncodedSize);
}

TEST(Cam, TheLargestCamFitsTheAdvertisedBuffer) {
  // Every optional component, 40 path points, and the longest special-vehicle container (20
  // octets of ptActivationData).
  Cam cam = samples::cam_at_bounds(true);
  PtActivation pt{255, {}};
  for (int i = 0; i < 20; ++i)
    pt.ptActivationData.push_back(0xFF);
  cam.cam.camParameters.specialVehicleContainer = PublicTransportContainer{true, pt};
  std::array<std::uint8_t, kCamMaxEncodedSize> buf{};
  auto n = encode(cam, buf);
  ASSERT_TRUE(n) << asn1::to_string(n.error());
  EXPECT_LE(*n, kCamMaxEncodedSize);
  Cam back;
  ASSERT_TRUE(decode(std::span<const std::uint8_t>(buf).first(*n), back));
  EXPECT_EQ(back, cam);
}

TEST(Cam, NamedBitsKeepTheirPositions) {
  // exteriorLights bit 7 (parkingLightsOn) is the last of the eight bits on the wire.
  Cam cam = samples::cam_with_path(0);
  cam.cam.camParameters.lowFrequencyContainer->exteriorLights = exterior_lights::kParkingLightsOn;
  const std::string bits = to_bits(must_encode(cam));
  EXPECT_EQ(bits.substr(322 + 1 + 4, 8), "00000001");
  cam.cam.camParameters.lowFrequencyContainer->exteriorLights =
      exterior_lights::kLowBeamHeadlightsOn;
  EXPECT_EQ(to_bits(must_encode(cam)).substr(322 + 1 + 4, 8), "10000000");
}

struct OutOfRange {
  const char* field;
  std::function<void(Cam&)> spoil;
};

TEST(Cam, EncoderRejectsEveryFieldOutsideItsConstraintNamingIt) {
  auto hf = [](Cam& c) -> BasicVehicleContainerHighFrequency& {
    return (*vehicle_hf(c.cam.camParameters));
  };
  auto pos = [](Cam& c) -> ReferencePosition& {
    return c.cam.camParameters.basicContainer.referencePosition;
  };
  const std::vector<OutOfRange> cases = {
      {"latitude", [&](Cam& c) { pos(c).latitude = 900000002; }},
      {"latitude", [&](Cam& c) { pos(c).latitude = -900000001; }},
      {"longitude", [&](Cam& c) { pos(c).longitude = 1800000002; }},
      {"semiMajorConfidence",
       [&](Cam& c) { pos(c).positionConfidenceEllipse.semiMajorConfidence = 4096; }},
      {"semiMajorOrientation",
       [&](Cam& c) { pos(c).positionConfidenceEllipse.semiMajorOrientation = 3602; }},
      {"altitudeValue", [&](Cam& c) { pos(c).altitude.altitudeValue = 800002; }},
      {"altitudeValue", [&](Cam& c) { pos(c).altitude.altitudeValue = -100001; }},
      {"altitudeConfidence",
       [&](Cam& c) { pos(c).altitude.altitudeConfidence = AltitudeConfidence{16}; }},
      {"headingValue", [&](Cam& c) { hf(c).heading.headingValue = 3602; }},
      {"headingConfidence", [&](Cam& c) { hf(c).heading.headingConfidence = 0; }},
      {"headingConfidence", [&](Cam& c) { hf(c).heading.headingConfidence = 128; }},
      {"speedValue", [&](Cam& c) { hf(c).speed.speedValue = 16384; }},
      {"speedConfidence", [&](Cam& c) { hf(c).speed.speedConfidence = 0; }},
      {"driveDirection", [&](Cam& c) { hf(c).driveDirection = DriveDirection{3}; }},
      {"vehicleLengthValue", [&](Cam& c) { hf(c).vehicleLength.vehicleLengthValue = 0; }},
      {"vehicleLengthConfidenceIndication",
       [&](Cam& c) {
         hf(c).vehicleLength.vehicleLengthConfidenceIndication =
             VehicleLengthConfidenceIndication{5};
       }},
      {"vehicleWidth", [&](Cam& c) { hf(c).vehicleWidth = 63; }},
      {"longitudinalAccelerationValue",
       [&](Cam& c) { hf(c).longitudinalAcceleration.longitudinalAccelerationValue = -161; }},
      {"longitudinalAccelerationConfidence",
       [&](Cam& c) { hf(c).longitudinalAcceleration.longitudinalAccelerationConfidence = 103; }},
      {"curvatureValue", [&](Cam& c) { hf(c).curvature.curvatureValue = -1024; }},
      {"curvatureConfidence",
       [&](Cam& c) { hf(c).curvature.curvatureConfidence = CurvatureConfidence{8}; }},
      {"curvatureCalculationMode",
       [&](Cam& c) { hf(c).curvatureCalculationMode = CurvatureCalculationMode{3}; }},
      {"yawRateValue", [&](Cam& c) { hf(c).yawRate.yawRateValue = -32767; }},
      {"yawRateConfidence",
       [&](Cam& c) { hf(c).yawRate.yawRateConfidence = YawRateConfidence{9}; }},
      {"accelerationControl", [&](Cam& c) { hf(c).accelerationControl = 0x80; }},
      {"lanePosition", [&](Cam& c) { hf(c).lanePosition = 15; }},
      {"lanePosition", [&](Cam& c) { hf(c).lanePosition = -2; }},
      {"steeringWheelAngleValue",
       [&](Cam& c) {
         hf(c).steeringWheelAngle = SteeringWheelAngle{513, 1};
       }},
      {"steeringWheelAngleConfidence",
       [&](Cam& c) {
         hf(c).steeringWheelAngle = SteeringWheelAngle{0, 0};
       }},
      {"lateralAccelerationValue",
       [&](Cam& c) {
         hf(c).lateralAcceleration = LateralAcceleration{162, 0};
       }},
      {"verticalAccelerationConfidence",
       [&](Cam& c) {
         hf(c).verticalAcceleration = VerticalAcceleration{0, 103};
       }},
      {"performanceClass", [&](Cam& c) { hf(c).performanceClass = 8; }},
      {"cenDsrcTollingZoneID",
       [&](Cam& c) {
         hf(c).cenDsrcTollingZone = CenDsrcTollingZone{0, 0, 134217728};
       }},
      {"protectedZoneLatitude",
       [&](Cam& c) {
         hf(c).cenDsrcTollingZone = CenDsrcTollingZone{900000002, 0, {}};
       }},
      {"vehicleRole",
       [&](Cam& c) {
         c.cam.camParameters.lowFrequencyContainer.emplace().vehicleRole = VehicleRole{16};
       }},
      {"deltaLatitude",
       [&](Cam& c) {
         c.cam.camParameters.lowFrequencyContainer.emplace().pathHistory.push_back(
             PathPoint{{131073, 0, 0}, {}});
       }},
      {"deltaLongitude",
       [&](Cam& c) {
         c.cam.camParameters.lowFrequencyContainer.emplace().pathHistory.push_back(
             PathPoint{{0, -131072, 0}, {}});
       }},
      {"deltaAltitude",
       [&](Cam& c) {
         c.cam.camParameters.lowFrequencyContainer.emplace().pathHistory.push_back(
             PathPoint{{0, 0, 12801}, {}});
       }},
      {"pathDeltaTime",
       [&](Cam& c) {
         c.cam.camParameters.lowFrequencyContainer.emplace().pathHistory.push_back(
             PathPoint{{0, 0, 0}, 0});
       }},
  };
  for (const OutOfRange& c : cases) {
    Cam cam = samples::cam_hf();
    c.spoil(cam);
    auto r = encode(cam);
    ASSERT_FALSE(r) << c.field;
    EXPECT_EQ(r.error().code, Error::kValueOutOfRange) << c.field;
    EXPECT_STREQ(r.error().field, c.field);
  }
}

TEST(Cam, EncoderChecksMessageIdAndBufferSize) {
  Cam cam = samples::cam_hf();
  cam.header.messageID = kMessageIdDenm;
  auto wrong = encode(cam);
  ASSERT_FALSE(wrong);
  EXPECT_EQ(wrong.error().code, Error::kWrongMessageId);

  const Bytes golden = must_encode(samples::cam_lf());
  std::vector<std::uint8_t> buf(golden.size());
  for (std::size_t size = 0; size < golden.size(); ++size) {
    auto r = encode(samples::cam_lf(), std::span<std::uint8_t>(buf).first(size));
    ASSERT_FALSE(r) << size;
    EXPECT_EQ(r.error().code, Error::kBufferTooSmall) << size;
  }
  auto exact = encode(samples::cam_lf(), buf);
  ASSERT_TRUE(exact);
  EXPECT_EQ(*exact, golden.size());
  EXPECT_EQ(buf, golden);
}

TEST(Cam, DecoderRejectsEveryTruncation) {
  for (const Cam& sample : {samples::cam_hf(), samples::cam_lf(), samples::cam_with_path(40)}) {
    const Bytes bytes = must_encode(sample);
    for (std::size_t n = 0; n < bytes.size(); ++n) {
      auto r = decode_cam(std::span<const std::uint8_t>(bytes).first(n));
      ASSERT_FALSE(r) << n;
      EXPECT_EQ(r.error().code, Error::kTruncated) << n << ": " << asn1::to_string(r.error());
    }
  }
}

TEST(Cam, DecoderRejectsTrailingOctets) {
  Bytes bytes = must_encode(samples::cam_hf());
  bytes.push_back(0);
  auto r = decode_cam(bytes);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, Error::kTrailingData);
  EXPECT_EQ(r.error().value, 1);
}

TEST(Cam, DecoderRejectsOtherMessagesAndVersions) {
  auto denm = encode(samples::denm_collision_risk());
  ASSERT_TRUE(denm);
  auto r = decode_cam(*denm);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().code, Error::kWrongMessageId);
  EXPECT_EQ(r.error().value, 1);
  EXPECT_EQ(asn1::to_string(r.error()), "wrong messageID: messageID = 1 (bit 8)");

  const Bytes cam = must_encode(samples::cam_hf());
  for (std::uint64_t version : {0, 3, 255}) {
    auto v = decode_cam(with_bits(cam, 0, 8, version));
    ASSERT_FALSE(v);
    EXPECT_EQ(v.error().code, Error::kUnsupportedVersion);
    EXPECT_EQ(v.error().value, static_cast<std::int64_t>(version));
  }
}

TEST(Cam, ProtocolVersion1UsesTheVersion1Dictionary) {
  // CDD version 1: CurvatureValue (-30000..30001) in 16 bits instead of (-1023..1023) in 11,
  // and no extension bit in CenDsrcTollingZone.
  Cam v2 = samples::cam_hf();
  (*vehicle_hf(v2.cam.camParameters)).cenDsrcTollingZone =
      CenDsrcTollingZone{410255000, 289742000, 77};
  Cam v1 = v2;
  v1.header.protocolVersion = kProtocolVersion1;
  (*vehicle_hf(v1.cam.camParameters)).curvature.curvatureValue = kCurvatureValueUnavailableV1;
  expect_round_trip(v1);
  const std::string b1 = to_bits(must_encode(v1));
  const std::string b2 = to_bits(must_encode(v2));
  EXPECT_EQ(b1.substr(285, 16), bits_of(30001 + 30000, 16));
  EXPECT_EQ(b2.substr(285, 11), bits_of(1023, 11));
  // Everything after the curvature is shifted by 5 bits; the tolling zone lacks its first bit.
  EXPECT_EQ(b1.substr(301, 21), b2.substr(296, 21));
  EXPECT_EQ(b1.substr(327, 1 + 31 + 32 + 27), b2.substr(322 + 1, 1 + 31 + 32 + 27));

  (*vehicle_hf(v1.cam.camParameters)).curvature.curvatureValue = -30000;
  expect_round_trip(v1);
  (*vehicle_hf(v1.cam.camParameters)).curvature.curvatureValue = -30001;
  auto bad = encode(v1);
  ASSERT_FALSE(bad);
  EXPECT_STREQ(bad.error().field, "curvatureValue");
  v2.header.protocolVersion = 3;
  auto v3 = encode(v2);
  ASSERT_FALSE(v3);
  EXPECT_EQ(v3.error().code, Error::kUnsupportedVersion);
}

TEST(Cam, EverySpecialVehicleContainerRoundTrips) {
  const auto cams = samples::cams_special_vehicle();
  ASSERT_EQ(cams.size(), 7u);
  for (std::size_t i = 0; i < cams.size(); ++i) {
    SCOPED_TRACE(i);
    expect_round_trip(cams[i]);
    // The presence bit, then after the HF container the CHOICE: extension bit 0, index.
    const std::string bits = to_bits(must_encode(cams[i]));
    EXPECT_EQ(bits[66], '1');
    EXPECT_EQ(bits.substr(322, 4), "0" + bits_of(i, 3));
    // With the optional components left out.
    Cam bare = cams[i];
    std::visit(
        [](auto& c) {
          using C = std::decay_t<decltype(c)>;
          if constexpr (std::is_same_v<C, PublicTransportContainer>)
            c.ptActivation.reset();
          if constexpr (std::is_same_v<C, RoadWorksContainerBasic>) {
            c.roadworksSubCauseCode.reset();
            c.closedLanes.reset();
          }
          if constexpr (std::is_same_v<C, EmergencyContainer>) {
            c.incidentIndication.reset();
            c.emergencyPriority.reset();
          }
          if constexpr (std::is_same_v<C, SafetyCarContainer>) {
            c.incidentIndication.reset();
            c.trafficRule.reset();
            c.speedLimit.reset();
          }
        },
        *bare.cam.camParameters.specialVehicleContainer);
    expect_round_trip(bare);
  }
  // EmergencyContainer by hand: bitmap 11, lightBarSirenInUse 11, CauseCode 0 01011111
  // 00000001, emergencyPriority bits (requestForRightOfWay) 10.
  EXPECT_EQ(to_bits(must_encode(cams[5])).substr(326, 2 + 2 + 17 + 2),
            "11"
            "11"
            "0" +
                bits_of(95, 8) + bits_of(1, 8) + "10");
}

TEST(Cam, SpecialVehicleContainerRangesAndChoices) {
  struct Case {
    const char* field;
    SpecialVehicleContainer c;
  };
  const Case cases[] = {
      {"dangerousGoodsBasic", DangerousGoodsContainer{20}},
      {"speedLimit", SafetyCarContainer{0, {}, {}, 0}},
      {"ptActivationData", PublicTransportContainer{false, PtActivation{0, {}}}},
      {"lightBarSirenInUse", RescueContainer{4}},
      {"specialTransportType", SpecialTransportContainer{16, 0}},
      {"emergencyPriority", EmergencyContainer{0, {}, 4}},
      {"drivingLaneStatus",
       RoadWorksContainerBasic{{}, 0, ClosedLanes{{}, {}, DrivingLaneStatus{0, 14}}}},
      {"drivingLaneStatus",
       RoadWorksContainerBasic{{}, 0, ClosedLanes{{}, {}, DrivingLaneStatus{0b1000, 3}}}},
      {"trafficRule", SafetyCarContainer{0, {}, TrafficRule{4}, {}}},
  };
  for (const Case& c : cases) {
    Cam cam = samples::cam_hf();
    cam.cam.camParameters.specialVehicleContainer = c.c;
    auto r = encode(cam);
    ASSERT_FALSE(r) << c.field;
    EXPECT_EQ(r.error().code, Error::kValueOutOfRange) << c.field;
    EXPECT_STREQ(r.error().field, c.field);
  }
  const Bytes rescue = must_encode(samples::cams_special_vehicle()[4]);
  auto index7 = decode_cam(with_bits(rescue, 323, 3, 7));
  ASSERT_FALSE(index7);
  EXPECT_EQ(index7.error().code, Error::kValueOutOfRange);
  EXPECT_STREQ(index7.error().field, "specialVehicleContainer");
  auto ext = decode_cam(with_bits(rescue, 322, 1, 1));
  ASSERT_FALSE(ext);
  EXPECT_EQ(ext.error().code, Error::kUnknownExtension);
  // CDD version 1's ClosedLanes: {hardShoulderStatus OPTIONAL, drivingLaneStatus (SIZE(1..14)),
  // ...}, held as the outer hard shoulder and a driving-lane status that must be present.
  Cam v1 = samples::cams_special_vehicle()[3];
  v1.header.protocolVersion = kProtocolVersion1;
  auto inner = encode(v1);  // the sample has an inner hard shoulder, which v1 cannot carry
  ASSERT_FALSE(inner);
  EXPECT_EQ(inner.error().code, Error::kValueOutOfRange);
  EXPECT_STREQ(inner.error().field, "innerhardShoulderStatus");
  auto& rw = std::get<RoadWorksContainerBasic>(*v1.cam.camParameters.specialVehicleContainer);
  rw.closedLanes = ClosedLanes{std::nullopt, HardShoulderStatus::closed,
                               DrivingLaneStatus{0b10000000000001, 14}};
  expect_round_trip(v1);
  // v1 HF ends at bit 327 (curvature 5 bits wider); CHOICE 4 bits; sub cause? lanes? 2 bits;
  // roadworksSubCauseCode 8; lightBarSirenInUse 2: closedLanes starts at 343.
  const std::string bits = to_bits(must_encode(v1));
  EXPECT_EQ(bits.substr(343, 1 + 1 + 2 + 4 + 14),
            std::string("0") + "1" + "01" + bits_of(14 - 1, 4) + "10000000000001");
  rw.closedLanes->drivingLaneStatus.reset();
  auto no_lanes = encode(v1);
  ASSERT_FALSE(no_lanes);
  EXPECT_STREQ(no_lanes.error().field, "drivingLaneStatus");
}

TEST(Cam, DecoderRejectsValuesOutsideTheirConstraint) {
  const Bytes hf = must_encode(samples::cam_hf());  // offsets from the golden table
  struct Case {
    std::size_t bit;
    unsigned width;
    std::uint64_t raw;
    const char* field;
    std::int64_t value;
  };
  const Case cases[] = {
      {76, 31, 0x7FFFFFFF, "latitude", 2147483647 - 900000000},
      {107, 32, 0xFFFFFFFF, "longitude", 4294967295LL - 1800000000},
      {163, 12, 3602, "semiMajorOrientation", 3602},
      {175, 20, 900002, "altitudeValue", 800002},
      {208, 12, 4095, "headingValue", 4095},
      {220, 7, 127, "headingConfidence", 128},
      {248, 2, 3, "driveDirection", 3},
      {250, 10, 1023, "vehicleLengthValue", 1024},
      {260, 3, 5, "vehicleLengthConfidenceIndication", 5},
      {263, 6, 62, "vehicleWidth", 63},
      {269, 9, 322, "longitudinalAccelerationValue", 162},
      {278, 7, 103, "longitudinalAccelerationConfidence", 103},
      {285, 11, 2047, "curvatureValue", 1024},
      {300, 2, 3, "curvatureCalculationMode", 3},
      {302, 16, 65534, "yawRateValue", 32768},
      {318, 4, 9, "yawRateConfidence", 9},
  };
  for (const Case& c : cases) {
    auto r = decode_cam(with_bits(hf, c.bit, c.width, c.raw));
    ASSERT_FALSE(r) << c.field;
    EXPECT_EQ(r.error().code, Error::kValueOutOfRange) << c.field;
    EXPECT_STREQ(r.error().field, c.field);
    EXPECT_EQ(r.error().value, c.value) << c.field;
    EXPECT_EQ(r.error().bit_offset, c.bit) << c.field;
  }
  // pathHistory SIZE(0..40): 41 in its 6 bits.
  auto big = decode_cam(with_bits(must_encode(samples::cam_lf()), 375, 6, 41));
  ASSERT_FALSE(big);
  EXPECT_EQ(big.error().code, Error::kSizeOutOfRange);
  EXPECT_STREQ(big.error().field, "pathHistory");
}

TEST(Cam, RoadSideUnitContainerRoundTripsInBothVersionsAndChecksItsRanges) {
  expect_round_trip(samples::cam_rsu());
  Cam none = samples::cam_rsu();
  std::get<RSUContainerHighFrequency>(none.cam.camParameters.highFrequencyContainer)
      .protectedCommunicationZonesRSU.reset();
  expect_round_trip(none);
  EXPECT_EQ(vehicle_hf(none.cam.camParameters), nullptr);
  // Sixteen zones, every field at its upper bound, with the low-frequency and special-vehicle
  // containers: still within kCamMaxEncodedSize.
  Cam big = samples::cam_at_bounds(true);
  big.cam.camParameters.specialVehicleContainer = PublicTransportContainer{
      true,
      PtActivation{255, {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20}}};
  RSUContainerHighFrequency rsu;
  for (int i = 0; i < 16; ++i)
    rsu.protectedCommunicationZonesRSU.emplace().push_back(
        ProtectedCommunicationZone{ProtectedZoneType::temporaryCenDsrcTolling, kTimestampItsMax,
                                   900000001, 1800000001, 255, 134217727});
  big.cam.camParameters.highFrequencyContainer = rsu;
  expect_round_trip(big);
  EXPECT_LE(must_encode(big).size(), kCamMaxEncodedSize);

  // Version 1: no extension marker in ProtectedCommunicationZone, no temporary zones.
  Cam v1 = samples::cam_rsu();
  v1.header.protocolVersion = kProtocolVersion1;
  auto temporary = encode(v1);
  ASSERT_FALSE(temporary);
  EXPECT_STREQ(temporary.error().field, "protectedZoneType");
  auto& zones = *std::get<RSUContainerHighFrequency>(v1.cam.camParameters.highFrequencyContainer)
                     .protectedCommunicationZonesRSU;
  zones[1].protectedZoneType = ProtectedZoneType::permanentCenDsrcTolling;
  expect_round_trip(v1);
  // Zone 1 starts at bit 207 (golden table of cam_hf, then 2 + 2 + 4 bits): v1 has no ext bit,
  // so the three presence bits and the type's extension bit come first.
  EXPECT_EQ(to_bits(must_encode(v1)).substr(207, 4), "1110");

  struct Case {
    const char* field;
    void (*spoil)(ProtectedCommunicationZone&);
  };
  const Case cases[] = {
      {"protectedZoneRadius", [](ProtectedCommunicationZone& z) { z.protectedZoneRadius = 0; }},
      {"protectedZoneID", [](ProtectedCommunicationZone& z) { z.protectedZoneID = 134217728; }},
      {"expiryTime", [](ProtectedCommunicationZone& z) { z.expiryTime = kTimestampItsMax + 1; }},
      {"protectedZoneLatitude",
       [](ProtectedCommunicationZone& z) { z.protectedZoneLatitude = 900000002; }},
      {"protectedZoneType",
       [](ProtectedCommunicationZone& z) { z.protectedZoneType = ProtectedZoneType{2}; }},
  };
  for (const Case& c : cases) {
    Cam cam = samples::cam_rsu();
    c.spoil((*std::get<RSUContainerHighFrequency>(cam.cam.camParameters.highFrequencyContainer)
                  .protectedCommunicationZonesRSU)[0]);
    auto r = encode(cam);
    ASSERT_FALSE(r) << c.field;
    EXPECT_EQ(r.error().code, Error::kValueOutOfRange) << c.field;
    EXPECT_STREQ(r.error().field, c.field);
  }
  Cam empty = samples::cam_rsu();
  std::get<RSUContainerHighFrequency>(empty.cam.camParameters.highFrequencyContainer)
      .protectedCommunicationZonesRSU.emplace();
  auto e = encode(empty);
  ASSERT_FALSE(e);
  EXPECT_EQ(e.error().code, Error::kSizeOutOfRange);

  // Decoding: a ProtectedZoneType extension beyond the one known, a radius extension, and
  // every truncation.
  const Bytes golden = must_encode(samples::cam_rsu());
  const std::string bits = to_bits(golden);
  // Zone 2's type: after zone 1 (1 + 3 + 1 + 42 + 31 + 32 + 9 + 27 = 146 bits from 207), ext 0
  // and three presence bits: bit 357 is the type's extension bit, 358.. its index.
  ASSERT_EQ(bits.substr(357, 8), "10000000");
  auto other = decode_cam(with_bits(golden, 358, 7, 1));
  ASSERT_FALSE(other);
  EXPECT_EQ(other.error().code, Error::kUnknownExtension);
  EXPECT_STREQ(other.error().field, "protectedZoneType");
  // Zone 1's radius extension bit: 207 + 1 + 3 + 1 + 42 + 31 + 32 = 317.
  auto radius = decode_cam(with_bits(golden, 317, 1, 1));
  ASSERT_FALSE(radius);
  EXPECT_STREQ(radius.error().field, "protectedZoneRadius");
  for (std::size_t n = 0; n < golden.size(); ++n) {
    auto r = decode_cam(std::span<const std::uint8_t>(golden).first(n));
    ASSERT_FALSE(r) << n;
    EXPECT_EQ(r.error().code, Error::kTruncated) << n;
  }
}

TEST(Cam, DecoderRejectsExtensionsItCannotHold) {
  const Bytes hf = must_encode(samples::cam_hf());
  auto hf_ext = decode_cam(with_bits(hf, 199, 1, 1));
  ASSERT_FALSE(hf_ext);
  EXPECT_EQ(hf_ext.error().code, Error::kUnknownExtension);
  EXPECT_STREQ(hf_ext.error().field, "highFrequencyContainer");

  auto mode = decode_cam(with_bits(hf, 299, 1, 1));
  ASSERT_FALSE(mode);
  EXPECT_EQ(mode.error().code, Error::kUnknownExtension);
  EXPECT_STREQ(mode.error().field, "curvatureCalculationMode");

  // pathDeltaTime (1..65535, ...) with its extension bit set.
  auto delta = decode_cam(with_bits(must_encode(samples::cam_lf()), 433, 1, 1));
  ASSERT_FALSE(delta);
  EXPECT_STREQ(delta.error().field, "pathDeltaTime");
}

TEST(Cam, DecoderSkipsExtensionAdditionsOfExtensibleSequences) {
  // A CAM of a later version: camParameters with its extension bit set and one addition (an
  // open type of two octets) after the root components, and a basicContainer with two
  // additions of which the second is present.
  std::string bits = to_bits(must_encode(samples::cam_hf())).substr(0, 322);
  bits[64] = '1';
  bits[67] = '1';
  const std::string basic_ext = "0" + bits_of(1, 6) + "01" + bits_of(1, 8) + bits_of(0xA5, 8);
  bits.insert(199, basic_ext);
  bits += "0" + bits_of(0, 6) + "1" + bits_of(2, 8) + bits_of(0xBEEF, 16);
  auto r = decode_cam(from_bits(bits));
  ASSERT_TRUE(r) << asn1::to_string(r.error());
  EXPECT_EQ(*r, samples::cam_hf());

  // The same with the open type claiming more octets than are left.
  std::string cut = bits;
  cut.replace(cut.size() - 24, 8, bits_of(9, 8));
  auto bad = decode_cam(from_bits(cut));
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().code, Error::kTruncated);
  EXPECT_STREQ(bad.error().field, "camParameters");
}

TEST(Cam, DecodingIntoAUsedObjectClearsWhatTheNewMessageLacks) {
  Cam cam;
  ASSERT_TRUE(decode(must_encode(samples::cam_lf()), cam));
  ASSERT_TRUE(decode(must_encode(samples::cam_hf()), cam));
  EXPECT_EQ(cam, samples::cam_hf());
}

TEST(Cam, RandomValidMessagesRoundTrip) {
  std::mt19937 rng(7);
  auto in = [&](std::int64_t lb, std::int64_t ub) {
    return std::uniform_int_distribution<std::int64_t>(lb, ub)(rng);
  };
  for (int i = 0; i < 2000; ++i) {
    Cam cam;
    cam.header.stationID = static_cast<StationID>(in(0, 4294967295));
    cam.cam.generationDeltaTime = static_cast<GenerationDeltaTime>(in(0, 65535));
    auto& p = cam.cam.camParameters;
    p.basicContainer.stationType = static_cast<StationType>(in(0, 255));
    auto& rp = p.basicContainer.referencePosition;
    rp.latitude = static_cast<Latitude>(in(-900000000, 900000001));
    rp.longitude = static_cast<Longitude>(in(-1800000000, 1800000001));
    rp.positionConfidenceEllipse = {static_cast<SemiAxisLength>(in(0, 4095)),
                                    static_cast<SemiAxisLength>(in(0, 4095)),
                                    static_cast<HeadingValue>(in(0, 3601))};
    rp.altitude = {static_cast<AltitudeValue>(in(-100000, 800001)),
                   static_cast<AltitudeConfidence>(in(0, 15))};
    auto& hf = *vehicle_hf(p);
    hf.heading = {static_cast<HeadingValue>(in(0, 3601)),
                  static_cast<HeadingConfidence>(in(1, 127))};
    hf.speed = {static_cast<SpeedValue>(in(0, 16383)), static_cast<SpeedConfidence>(in(1, 127))};
    hf.driveDirection = static_cast<DriveDirection>(in(0, 2));
    hf.vehicleLength = {static_cast<VehicleLengthValue>(in(1, 1023)),
                        static_cast<VehicleLengthConfidenceIndication>(in(0, 4))};
    hf.vehicleWidth = static_cast<VehicleWidth>(in(1, 62));
    hf.longitudinalAcceleration = {static_cast<AccelerationValue>(in(-160, 161)),
                                   static_cast<AccelerationConfidence>(in(0, 102))};
    hf.curvature = {static_cast<CurvatureValue>(in(-1023, 1023)),
                    static_cast<CurvatureConfidence>(in(0, 7))};
    hf.curvatureCalculationMode = static_cast<CurvatureCalculationMode>(in(0, 2));
    hf.yawRate = {static_cast<YawRateValue>(in(-32766, 32767)),
                  static_cast<YawRateConfidence>(in(0, 8))};
    if (in(0, 1))
      hf.accelerationControl = static_cast<AccelerationControl>(in(0, 127));
    if (in(0, 1))
      hf.lanePosition = static_cast<LanePosition>(in(-1, 14));
    if (in(0, 1))
      hf.steeringWheelAngle =
          SteeringWheelAngle{static_cast<SteeringWheelAngleValue>(in(-511, 512)),
                             static_cast<SteeringWheelAngleConfidence>(in(1, 127))};
    if (in(0, 1))
      hf.performanceClass = static_cast<PerformanceClass>(in(0, 7));
    if (in(0, 1)) {
      auto& lf = p.lowFrequencyContainer.emplace();
      lf.vehicleRole = static_cast<VehicleRole>(in(0, 15));
      lf.exteriorLights = static_cast<ExteriorLights>(in(0, 255));
      const auto n = static_cast<std::size_t>(in(0, 40));
      for (std::size_t k = 0; k < n; ++k) {
        PathPoint pt{{static_cast<DeltaLatitude>(in(-131071, 131072)),
                      static_cast<DeltaLongitude>(in(-131071, 131072)),
                      static_cast<DeltaAltitude>(in(-12700, 12800))},
                     {}};
        if (in(0, 1))
          pt.pathDeltaTime = static_cast<PathDeltaTime>(in(1, 65535));
        lf.pathHistory.push_back(pt);
      }
    }
    expect_round_trip(cam);
    if (::testing::Test::HasFailure())
      break;
  }
}

}  // namespace
}  // namespace tb::its::messages
