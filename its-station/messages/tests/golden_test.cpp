// Golden byte vectors for one CAM (HF only), one CAM with the low-frequency container and path
// history, and one DENM. Each was worked out from the ASN.1 (EN 302 637-2 V1.4.1, EN 302 637-3
// V1.3.1, TS 102 894-2 V1.3.1) field by field: the width of a constrained integer is the bits of
// (ub - lb) (X.691 11.5.7.1), the value sent is value - lb, an extensible SEQUENCE / CHOICE /
// ENUMERATED starts with a 0 extension bit, OPTIONAL components give one presence bit each in
// order (X.691 19.2), a SEQUENCE OF with SIZE(lb..ub) sends size - lb (20.6), and the encoding is
// padded with zero bits to an octet. The tables beside the bytes are that working; the integration
// test (tshark_it.cpp) checks the same messages against Wireshark's dissector.

#include <gtest/gtest.h>

#include <vector>

#include "its-station/messages/cam.hpp"
#include "its-station/messages/denm.hpp"
#include "its-station/messages/tests/bits.hpp"
#include "its-station/messages/tests/samples.hpp"

namespace tb::its::messages {
namespace {

// clang-format off
// CAM, high-frequency container only: 41 bytes
//  bit  width  component                    value / constraint             bits
//     0    8   protocolVersion              2 in (0..255)                  00000010
//     8    8   messageID                    2 in (0..255)                  00000010
//    16   32   stationID                    1234567 in (0..4294967295)     00000000000100101101011010000111
//    48   16   generationDeltaTime          12345 in (0..65535)            0011000000111001
//    64    1   camParameters ext                                           0
//    65    1   lowFrequencyContainer?       absent                         0
//    66    1   specialVehicleContainer?     absent                         0
//    67    1   basicContainer ext                                          0
//    68    8   stationType                  5 in (0..255)                  00000101
//    76   31   latitude                     410255000 in (-900000000..900000001) 1001110000110001110011110011000
//   107   32   longitude                    289742000 in (-1800000000..1800000001) 01111100100011101110111010110000
//   139   12   semiMajorConfidence          500 in (0..4095)               000111110100
//   151   12   semiMinorConfidence          300 in (0..4095)               000100101100
//   163   12   semiMajorOrientation         900 in (0..3601)               001110000100
//   175   20   altitudeValue                4000 in (-100000..800001)      00011001011001000000
//   195    4   altitudeConfidence           alt-002-00 (index 7 of 16)     0111
//   199    1   highFrequencyContainer ext                                  0
//   200    1   highFrequencyContainer idx   basicVehicleContainerHighFrequency 0
//   201    7   HF optional bitmap           accCtl lanePos steer latAcc vertAcc perf toll 0000000
//   208   12   headingValue                 900 in (0..3601)               001110000100
//   220    7   headingConfidence            10 in (1..127)                 0001001
//   227   14   speedValue                   1389 in (0..16383)             00010101101101
//   241    7   speedConfidence              100 in (1..127)                1100011
//   248    2   driveDirection               forward (index 0 of 3)         00
//   250   10   vehicleLengthValue           45 in (1..1023)                0000101100
//   260    3   vehicleLengthConfInd         noTrailerPresent (index 0 of 5) 000
//   263    6   vehicleWidth                 18 in (1..62)                  010001
//   269    9   longitudinalAccValue         5 in (-160..161)               010100101
//   278    7   longitudinalAccConfidence    10 in (0..102)                 0001010
//   285   11   curvatureValue               0 in (-1023..1023)             01111111111
//   296    3   curvatureConfidence          unavailable (index 7 of 8)     111
//   299    1   curvatureCalculationMode ext root value                     0
//   300    2   curvatureCalculationMode     yawRateUsed (index 0 of 3)     00
//   302   16   yawRateValue                 -150 in (-32766..32767)        0111111101101000
//   318    4   yawRateConfidence            degSec-001-00 (index 3 of 9)   0011
//   322    6   padding                                                     000000
const std::vector<std::uint8_t> kCamHfGolden = {
    0x02, 0x02, 0x00, 0x12, 0xD6, 0x87, 0x30, 0x39, 0x00, 0x59, 0xC3, 0x1C,
    0xF3, 0x0F, 0x91, 0xDD, 0xD6, 0x03, 0xE8, 0x25, 0x87, 0x08, 0x32, 0xC8,
    0x0E, 0x00, 0x38, 0x41, 0x22, 0xB6, 0xE3, 0x02, 0xC0, 0x8A, 0x94, 0x53,
    0xFF, 0xE1, 0xFD, 0xA0, 0xC0,
};

// CAM with HF optionals, low-frequency container and 3 path points: 72 bytes
//  bit  width  component                    value / constraint             bits
//     0    8   protocolVersion              2 in (0..255)                  00000010
//     8    8   messageID                    2 in (0..255)                  00000010
//    16   32   stationID                    7654321 in (0..4294967295)     00000000011101001100101110110001
//    48   16   generationDeltaTime          65535 in (0..65535)            1111111111111111
//    64    1   camParameters ext                                           0
//    65    1   lowFrequencyContainer?       present                        1
//    66    1   specialVehicleContainer?     absent                         0
//    67    1   basicContainer ext                                          0
//    68    8   stationType                  5 in (0..255)                  00000101
//    76   31   latitude                     -338688000 in (-900000000..900000001) 0100001011101001111000100000000
//   107   32   longitude                    1512093000 in (-1800000000..1800000001) 11000101011010101000011101001000
//   139   12   semiMajorConfidence          4095 in (0..4095)              111111111111
//   151   12   semiMinorConfidence          4094 in (0..4095)              111111111110
//   163   12   semiMajorOrientation         3601 in (0..3601)              111000010001
//   175   20   altitudeValue                -100000 in (-100000..800001)   00000000000000000000
//   195    4   altitudeConfidence           unavailable (index 15 of 16)   1111
//   199    1   highFrequencyContainer ext                                  0
//   200    1   highFrequencyContainer idx   basicVehicleContainerHighFrequency 0
//   201    7   HF optional bitmap           accCtl lanePos steer latAcc vertAcc perf toll 1011000
//   208   12   headingValue                 900 in (0..3601)               001110000100
//   220    7   headingConfidence            10 in (1..127)                 0001001
//   227   14   speedValue                   1389 in (0..16383)             00010101101101
//   241    7   speedConfidence              100 in (1..127)                1100011
//   248    2   driveDirection               forward (index 0 of 3)         00
//   250   10   vehicleLengthValue           45 in (1..1023)                0000101100
//   260    3   vehicleLengthConfInd         noTrailerPresent (index 0 of 5) 000
//   263    6   vehicleWidth                 18 in (1..62)                  010001
//   269    9   longitudinalAccValue         5 in (-160..161)               010100101
//   278    7   longitudinalAccConfidence    10 in (0..102)                 0001010
//   285   11   curvatureValue               0 in (-1023..1023)             01111111111
//   296    3   curvatureConfidence          unavailable (index 7 of 8)     111
//   299    1   curvatureCalculationMode ext root value                     0
//   300    2   curvatureCalculationMode     yawRateUsed (index 0 of 3)     00
//   302   16   yawRateValue                 -150 in (-32766..32767)        0111111101101000
//   318    4   yawRateConfidence            degSec-001-00 (index 3 of 9)   0011
//   322    7   accelerationControl          bits 0,4 set                   1000100
//   329   10   steeringWheelAngleValue      -20 in (-511..512)             0111101011
//   339    7   steeringWheelAngleConf       2 in (1..127)                  0000001
//   346    9   lateralAccValue              -12 in (-160..161)             010010100
//   355    7   lateralAccConfidence         102 in (0..102)                1100110
//   362    1   lowFrequencyContainer ext    choice index: 1 alternative, no bits 0
//   363    4   vehicleRole                  default (index 0 of 16)        0000
//   367    8   exteriorLights               bits 0,2 set                   10100000
//   375    6   pathHistory size             3 in (0..40)                   000011
//   381    1   pathPoint[0] pathDeltaTime?                                 1
//   382   18   deltaLatitude                -1234 in (-131071..131072)     011111101100101101
//   400   18   deltaLongitude               567 in (-131071..131072)       100000001000110110
//   418   15   deltaAltitude                12800 in (-12700..12800)       110001110011100
//   433    1   pathDeltaTime ext                                           0
//   434   16   pathDeltaTime                10 in (1..65535)               0000000000001001
//   450    1   pathPoint[1] pathDeltaTime?                                 0
//   451   18   deltaLatitude                131072 in (-131071..131072)    111111111111111111
//   469   18   deltaLongitude               -131071 in (-131071..131072)   000000000000000000
//   487   15   deltaAltitude                -12700 in (-12700..12800)      000000000000000
//   502    1   pathPoint[2] pathDeltaTime?                                 1
//   503   18   deltaLatitude                0 in (-131071..131072)         011111111111111111
//   521   18   deltaLongitude               0 in (-131071..131072)         011111111111111111
//   539   15   deltaAltitude                0 in (-12700..12800)           011000110011100
//   554    1   pathDeltaTime ext                                           0
//   555   16   pathDeltaTime                65535 in (1..65535)            1111111111111110
//   571    5   padding                                                     00000
const std::vector<std::uint8_t> kCamLfGolden = {
    0x02, 0x02, 0x00, 0x74, 0xCB, 0xB1, 0xFF, 0xFF, 0x40, 0x54, 0x2E, 0x9E,
    0x20, 0x18, 0xAD, 0x50, 0xE9, 0x1F, 0xFF, 0xFF, 0xDC, 0x22, 0x00, 0x00,
    0x1E, 0x58, 0x38, 0x41, 0x22, 0xB6, 0xE3, 0x02, 0xC0, 0x8A, 0x94, 0x53,
    0xFF, 0xE1, 0xFD, 0xA0, 0xE2, 0x3D, 0x60, 0x52, 0x99, 0x81, 0x40, 0x1D,
    0xFB, 0x2D, 0x80, 0x8D, 0xB1, 0xCE, 0x00, 0x02, 0x5F, 0xFF, 0xF8, 0x00,
    0x00, 0x00, 0x02, 0xFF, 0xFF, 0xBF, 0xFF, 0xEC, 0x67, 0x1F, 0xFF, 0xC0,
};

// DENM collisionRisk/longitudinalCollisionRisk with management, situation, location: 70 bytes
//  bit  width  component                    value / constraint             bits
//     0    8   protocolVersion              2 in (0..255)                  00000010
//     8    8   messageID                    1 in (0..255)                  00000001
//    16   32   stationID                    1234567 in (0..4294967295)     00000000000100101101011010000111
//    48    1   situation?                                                  1
//    49    1   location?                                                   1
//    50    1   alacarte?                                                   0
//    51    1   management ext                                              0
//    52    1   termination?                                                0
//    53    1   relevanceDistance?                                          1
//    54    1   relevanceTrafficDirection?                                  1
//    55    1   validityDuration? (DEFAULT)                                 1
//    56    1   transmissionInterval?                                       1
//    57   32   originatingStationID         1234567 in (0..4294967295)     00000000000100101101011010000111
//    89   16   sequenceNumber               42 in (0..65535)               0000000000101010
//   105   42   detectionTime                694224000000 in (0..4398046511103) 001010000110100010111110011001010000000000
//   147   42   referenceTime                694224000100 in (0..4398046511103) 001010000110100010111110011001010001100100
//   189   31   latitude                     410255000 in (-900000000..900000001) 1001110000110001110011110011000
//   220   32   longitude                    289742000 in (-1800000000..1800000001) 01111100100011101110111010110000
//   252   12   semiMajorConfidence          500 in (0..4095)               000111110100
//   264   12   semiMinorConfidence          300 in (0..4095)               000100101100
//   276   12   semiMajorOrientation         900 in (0..3601)               001110000100
//   288   20   altitudeValue                4000 in (-100000..800001)      00011001011001000000
//   308    4   altitudeConfidence           alt-002-00 (index 7 of 16)     0111
//   312    3   relevanceDistance            lessThan200m (index 2 of 8)    010
//   315    2   relevanceTrafficDirection    upstreamTraffic (index 1 of 4) 01
//   317   17   validityDuration             10 in (0..86400)               00000000000001010
//   334   14   transmissionInterval         100 in (1..10000)              00000001100011
//   348    8   stationType                  5 in (0..255)                  00000101
//   356    1   situation ext                                               0
//   357    1   linkedCause?                                                0
//   358    1   eventHistory?                                               0
//   359    3   informationQuality           3 in (0..7)                    011
//   362    1   eventType ext                                               0
//   363    8   causeCode                    97 in (0..255)                 01100001
//   371    8   subCauseCode                 1 in (0..255)                  00000001
//   379    1   location ext                                                0
//   380    1   eventSpeed?                                                 1
//   381    1   eventPositionHeading?                                       1
//   382    1   roadType?                                                   1
//   383   14   speedValue                   1389 in (0..16383)             00010101101101
//   397    7   speedConfidence              100 in (1..127)                1100011
//   404   12   headingValue                 900 in (0..3601)               001110000100
//   416    7   headingConfidence            10 in (1..127)                 0001001
//   423    3   traces size                  1 in (1..7)                    000
//   426    6   pathHistory size             2 in (0..40)                   000010
//   432    1   pathPoint[0] pathDeltaTime?                                 1
//   433   18   deltaLatitude                100 in (-131071..131072)       100000000001100011
//   451   18   deltaLongitude               -100 in (-131071..131072)      011111111110011011
//   469   15   deltaAltitude                0 in (-12700..12800)           011000110011100
//   484    1   pathDeltaTime ext                                           0
//   485   16   pathDeltaTime                50 in (1..65535)               0000000000110001
//   501    1   pathPoint[1] pathDeltaTime?                                 0
//   502   18   deltaLatitude                250 in (-131071..131072)       100000000011111001
//   520   18   deltaLongitude               -250 in (-131071..131072)      011111111100000101
//   538   15   deltaAltitude                -10 in (-12700..12800)         011000110010010
//   553    2   roadType                     nonUrban-WithStructuralSeparation (index 3 of 4) 11
//   555    5   padding                                                     00000
const std::vector<std::uint8_t> kDenmGolden = {
    0x02, 0x01, 0x00, 0x12, 0xD6, 0x87, 0xC7, 0x80, 0x09, 0x6B, 0x43, 0x80,
    0x15, 0x14, 0x34, 0x5F, 0x32, 0x80, 0x05, 0x0D, 0x17, 0xCC, 0xA3, 0x24,
    0xE1, 0x8E, 0x79, 0x87, 0xC8, 0xEE, 0xEB, 0x01, 0xF4, 0x12, 0xC3, 0x84,
    0x19, 0x64, 0x07, 0x48, 0x00, 0x28, 0x06, 0x30, 0x50, 0xCC, 0x20, 0x2E,
    0x2B, 0x6E, 0x33, 0x84, 0x12, 0x02, 0xC0, 0x0C, 0x6F, 0xFC, 0xDB, 0x19,
    0xC0, 0x01, 0x8A, 0x00, 0xF9, 0x7F, 0xC1, 0x58, 0xC9, 0x60,
};
// clang-format on

TEST(Golden, CamHighFrequencyOnlyEncodesToTheWorkedOutBytes) {
  auto bytes = encode(samples::cam_hf());
  ASSERT_TRUE(bytes) << asn1::to_string(bytes.error());
  EXPECT_EQ(*bytes, kCamHfGolden);
  auto cam = decode_cam(kCamHfGolden);
  ASSERT_TRUE(cam) << asn1::to_string(cam.error());
  EXPECT_EQ(*cam, samples::cam_hf());
}

TEST(Golden, CamWithLowFrequencyContainerEncodesToTheWorkedOutBytes) {
  auto bytes = encode(samples::cam_lf());
  ASSERT_TRUE(bytes) << asn1::to_string(bytes.error());
  EXPECT_EQ(*bytes, kCamLfGolden);
  auto cam = decode_cam(kCamLfGolden);
  ASSERT_TRUE(cam) << asn1::to_string(cam.error());
  EXPECT_EQ(*cam, samples::cam_lf());
}

TEST(Golden, DenmEncodesToTheWorkedOutBytes) {
  auto bytes = encode(samples::denm_collision_risk());
  ASSERT_TRUE(bytes) << asn1::to_string(bytes.error());
  EXPECT_EQ(*bytes, kDenmGolden);
  auto denm = decode_denm(kDenmGolden);
  ASSERT_TRUE(denm) << asn1::to_string(denm.error());
  EXPECT_EQ(*denm, samples::denm_collision_risk());
}

// The containers added since, worked out the same way but written as bit strings, one line per
// component: bits_of(v, w) is v in w bits, a constrained value already less its lower bound.
using testing::bits_of;
using testing::to_bits;

// ReferencePosition samples::istanbul(): latitude, longitude, ellipse, altitude.
std::string istanbul_bits() {
  return bits_of(410255000 + 900000000, 31) + bits_of(289742000 + 1800000000LL, 32) +
         bits_of(500, 12) + bits_of(300, 12) + bits_of(900, 12) + bits_of(4000 + 100000, 20) +
         bits_of(7, 4);
}

std::string ia5(const char* s) {
  std::string b;
  for (; *s != '\0'; ++s)
    b += bits_of(static_cast<unsigned char>(*s), 7);  // X.691 30.5.4: 7 bits, the code itself
  return b;
}

TEST(Golden, DenmAlacarteContainerEncodesToTheWorkedOutBits) {
  Denm d = samples::denm_collision_risk();
  d.denm.alacarte = samples::alacarte_full();
  const std::string alacarte =
      std::string("0") +   // AlacarteContainer ext
      "111111" +           // lanePosition? impactReduction? externalTemperature?
                           // roadWorks? positioningSolution? stationaryVehicle?
      bits_of(2 + 1, 4) +  // lanePosition 2 in (-1..14)
      // ImpactReductionContainer: no extension marker, no OPTIONAL components
      bits_of(40 - 1, 7) +       // heightLonCarrLeft 40 in (1..100)
      bits_of(41 - 1, 7) +       // heightLonCarrRight 41 in (1..100)
      bits_of(50 - 1, 7) +       // posLonCarrLeft 50 in (1..127)
      bits_of(51 - 1, 7) +       // posLonCarrRight 51 in (1..127)
      "0" + bits_of(2 - 1, 2) +  // positionOfPillars SIZE(1..3, ...): root, size 2
      bits_of(10 - 1, 5) +       //   PosPillar 10 in (1..30)
      bits_of(25 - 1, 5) +       //   PosPillar 25
      bits_of(20 - 1, 6) +       // posCentMass 20 in (1..63)
      bits_of(27 - 1, 7) +       // wheelBaseVehicle 27 in (1..127)
      bits_of(30 - 1, 8) +       // turningRadius 30 in (1..255)
      bits_of(9 - 1, 5) +        // posFrontAx 9 in (1..20)
      "11000100000000000000" +   // positionOfOccupants SIZE(20): bits 0, 1, 5, bit 0 first
      bits_of(15 - 1, 10) +      // vehicleMass 15 in (1..1024)
      "0" +                      // requestResponseIndication request (index 0 of 2)
      bits_of(-5 + 60, 7) +      // externalTemperature -5 in (-60..67)
      // RoadWorksContainerExtended: no extension marker, nine OPTIONAL components, all present
      "111111111" + "10" +             // lightBarSirenInUse SIZE(2): lightBarActivated (bit 0)
      "0" + "011" +                    // closedLanes ext; inner? outer? drivingLaneStatus?
      "01" +                           //   outerhardShoulderStatus closed (index 1 of 3)
      bits_of(2 - 1, 4) + "01" +       //   drivingLaneStatus SIZE(1..13): 2 bits, bit 1 set
      "0" + bits_of(2 - 1, 2) +        // restriction SIZE(1..3, ...): root, size 2
      bits_of(8, 8) + bits_of(6, 8) +  //   heavyTruck (8), bus (6)
      bits_of(60 - 1, 8) +             // speedLimit 60 in (1..255)
      "0" + bits_of(3, 8) + bits_of(1, 8) +     // incidentIndication: ext, roadworks (3), 1
      bits_of(1 - 1, 6) +                       // recommendedPath SIZE(1..40): 1 point
      istanbul_bits() +                         //   ReferencePosition
      bits_of(100 + 131071, 18) +               // startingPointSpeedLimit: deltaLatitude 100
      bits_of(-200 + 131071, 18) +              //   deltaLongitude -200
      bits_of(0 + 12700, 15) +                  //   deltaAltitude 0
      "0" + bits_of(2, 2) +                     // trafficFlowRule: ext, passToRight (index 2 of 4)
      "0" + bits_of(1 - 1, 3) +                 // referenceDenms SIZE(1..8, ...): root, size 1
      bits_of(1234567, 32) + bits_of(42, 16) +  //   ActionID
      "0" + bits_of(2, 3) +                     // positioningSolution: ext, dGNSS (index 2 of 6)
      // StationaryVehicleContainer: no extension marker, six OPTIONAL components, all present
      "111111" + bits_of(1, 2) +              // stationarySince lessThan2Minutes (index 1 of 4)
      "0" + bits_of(94, 8) + bits_of(2, 8) +  // stationaryCause: ext, stationaryVehicle, 2
      // DangerousGoodsExtended: ext, then emergencyActionCode? phoneNumber? companyName?
      "0" + "111" + bits_of(9, 5) +     //   dangerousGoodsType flammableLiquids (index 9 of 20)
      bits_of(1203, 14) +               //   unNumber 1203 in (0..9999)
      "0" + "1" + "0" +                 //   elevatedTemperature, tunnelsRestricted, limitedQuantity
      bits_of(3 - 1, 5) + ia5("3YE") +  // emergencyActionCode IA5String SIZE(1..24)
      // phoneNumber NumericString SIZE(1..16): 3 characters, 4 bits each, the index in
      // " 0123456789" (X.691 30.5.4): '1' is 2, '2' is 3
      bits_of(3 - 1, 4) + bits_of(2, 4) + bits_of(2, 4) + bits_of(3, 4) +
      // companyName UTF8String: not PER-visible, an 8-bit octet count (X.691 11.9.3.6), then
      // the octets of "Ölwerk"
      bits_of(7, 8) + bits_of(0xC3, 8) + bits_of(0x96, 8) + bits_of('l', 8) + bits_of('w', 8) +
      bits_of('e', 8) + bits_of('r', 8) + bits_of('k', 8) +
      bits_of(2, 7) +                   // numberOfOccupants 2 in (0..127)
      "0" + "11" +                      // vehicleIdentification ext, wMInumber? vDS?
      bits_of(3 - 1, 2) + ia5("WVW") +  //   wMInumber IA5String SIZE(1..3)
      ia5("ZZZ1KZ") +                   //   vDS IA5String SIZE(6): no length
      "0000100";                        // energyStorageType SIZE(7): diesel (bit 4)

  auto bytes = encode(d);
  ASSERT_TRUE(bytes) << asn1::to_string(bytes.error());
  const std::string got = to_bits(*bytes);
  const std::string golden = to_bits(kDenmGolden);
  // The golden DENM with its alacarte presence bit (50) set, then the container at bit 555.
  std::string want = golden.substr(0, 555);
  want[50] = '1';
  want += alacarte;
  want += std::string((8 - want.size() % 8) % 8, '0');
  EXPECT_EQ(got, want);
  auto back = decode_denm(*bytes);
  ASSERT_TRUE(back) << asn1::to_string(back.error());
  EXPECT_EQ(*back, d);
}

TEST(Golden, RoadSideUnitCamEncodesToTheWorkedOutBits) {
  const std::string want_body =
      bits_of(2, 8) + bits_of(2, 8) + bits_of(5550001, 32) +  // ItsPduHeader
      bits_of(12345, 16) +                                    // generationDeltaTime
      "000" +                 // camParameters ext, lowFrequency?, specialVehicle?
      "0" + bits_of(15, 8) +  // basicContainer ext, stationType roadSideUnit (15)
      istanbul_bits() +       // referencePosition
      "0" + "1" +             // highFrequencyContainer: ext, rsuContainerHighFrequency (1)
      "0" + "1" +             // RSUContainerHighFrequency ext, zones?
      bits_of(2 - 1, 4) +     // protectedCommunicationZonesRSU SIZE(1..16): 2 zones
      // zone 1: ext, expiryTime? radius? id?, type (one root value: no index bits)
      "0" + "111" + "0" + bits_of(694224000000ULL, 42) +  // expiryTime in (0..4398046511103)
      bits_of(410260000 + 900000000, 31) +                // protectedZoneLatitude
      bits_of(289750000 + 1800000000LL, 32) +             // protectedZoneLongitude
      "0" + bits_of(50 - 1, 8) +                          // protectedZoneRadius 50 in (1..255, ...)
      bits_of(12345, 27) +                                // protectedZoneID in (0..134217727)
      // zone 2: ext, none of the optionals; temporaryCenDsrcTolling is the first extension
      // value: extension bit 1, then index 0 as a normally small number (X.691 14.3, 11.6)
      "0" + "000" + "1" + "0000000" + bits_of(410270000 + 900000000, 31) +
      bits_of(289760000 + 1800000000LL, 32);
  auto bytes = encode(samples::cam_rsu());
  ASSERT_TRUE(bytes) << asn1::to_string(bytes.error());
  const std::string want = want_body + std::string((8 - want_body.size() % 8) % 8, '0');
  EXPECT_EQ(to_bits(*bytes), want);
  auto back = decode_cam(*bytes);
  ASSERT_TRUE(back) << asn1::to_string(back.error());
  EXPECT_EQ(*back, samples::cam_rsu());
}

}  // namespace
}  // namespace tb::its::messages
