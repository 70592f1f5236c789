#pragma once
/// @file Data elements and frames of the ETSI common data dictionary, TS 102 894-2 V1.3.1
/// (ASN.1 module ITS-Container version 2), as CAM (EN 302 637-2 V1.4.1) and DENM
/// (EN 302 637-3 V1.3.1) use them.
///
/// Values are held in the units the ASN.1 encodes (latitude in 0.1 microdegree, speed in
/// 0.01 m/s, heading in 0.1 degree, ...) so that a decoded message re-encodes bit for bit; the
/// `unavailable` and `outOfRange` values of the dictionary are named constants. Member names are
/// the ASN.1 component names. Ranges are checked by the encoder and decoder, not here.

#include <cstddef>
#include <cstdint>
#include <optional>

#include "its-station/messages/bounded_vector.hpp"

namespace tb::its::messages {

// ---- ItsPduHeader (CDD A.114) ----------------------------------------------------------------
using StationID = std::uint32_t;  // (0..4294967295)

/// messageID values of ItsPduHeader.
inline constexpr std::uint8_t kMessageIdDenm = 1;
inline constexpr std::uint8_t kMessageIdCam = 2;
/// protocolVersion of EN 302 637-2 V1.4.1 / EN 302 637-3 V1.3.1 (CDD version 2).
inline constexpr std::uint8_t kProtocolVersion = 2;
/// protocolVersion of the earlier EN 302 637-2 V1.3.x / EN 302 637-3 V1.2.x (CDD version 1),
/// decoded and encoded too: the same structure but for CurvatureValue's range and the
/// extension markers of CauseCode and CenDsrcTollingZone.
inline constexpr std::uint8_t kProtocolVersion1 = 1;

struct ItsPduHeader {
  std::uint8_t protocolVersion = kProtocolVersion;  // (0..255)
  std::uint8_t messageID = 0;                       // (0..255)
  StationID stationID = 0;
  friend bool operator==(const ItsPduHeader&, const ItsPduHeader&) = default;
};

// ---- Station type (CDD A.78) -----------------------------------------------------------------
using StationType = std::uint8_t;  // (0..255)
namespace station_type {
inline constexpr StationType kUnknown = 0;
inline constexpr StationType kPedestrian = 1;
inline constexpr StationType kCyclist = 2;
inline constexpr StationType kMoped = 3;
inline constexpr StationType kMotorcycle = 4;
inline constexpr StationType kPassengerCar = 5;
inline constexpr StationType kBus = 6;
inline constexpr StationType kLightTruck = 7;
inline constexpr StationType kHeavyTruck = 8;
inline constexpr StationType kTrailer = 9;
inline constexpr StationType kSpecialVehicles = 10;
inline constexpr StationType kTram = 11;
inline constexpr StationType kRoadSideUnit = 15;
}  // namespace station_type

// ---- Position ----------------------------------------------------------------------------------
using Latitude = std::int32_t;   // 0.1 microdegree, (-900000000..900000001)
using Longitude = std::int32_t;  // 0.1 microdegree, (-1800000000..1800000001)
inline constexpr Latitude kLatitudeUnavailable = 900000001;
inline constexpr Longitude kLongitudeUnavailable = 1800000001;

using SemiAxisLength = std::uint16_t;  // cm, (0..4095)
inline constexpr SemiAxisLength kSemiAxisLengthOutOfRange = 4094;
inline constexpr SemiAxisLength kSemiAxisLengthUnavailable = 4095;

using HeadingValue = std::uint16_t;  // 0.1 degree from WGS84 north, clockwise, (0..3601)
inline constexpr HeadingValue kHeadingValueUnavailable = 3601;

struct PosConfidenceEllipse {
  SemiAxisLength semiMajorConfidence = kSemiAxisLengthUnavailable;
  SemiAxisLength semiMinorConfidence = kSemiAxisLengthUnavailable;
  HeadingValue semiMajorOrientation = kHeadingValueUnavailable;
  friend bool operator==(const PosConfidenceEllipse&, const PosConfidenceEllipse&) = default;
};

using AltitudeValue = std::int32_t;  // cm above the WGS84 ellipsoid, (-100000..800001)
inline constexpr AltitudeValue kAltitudeValueUnavailable = 800001;

/// ENUMERATED, 16 values, not extensible: alt-000-01 (0) … alt-200-00 (13).
enum class AltitudeConfidence : std::uint8_t {
  alt_000_01 = 0,
  alt_000_02 = 1,
  alt_000_05 = 2,
  alt_000_10 = 3,
  alt_000_20 = 4,
  alt_000_50 = 5,
  alt_001_00 = 6,
  alt_002_00 = 7,
  alt_005_00 = 8,
  alt_010_00 = 9,
  alt_020_00 = 10,
  alt_050_00 = 11,
  alt_100_00 = 12,
  alt_200_00 = 13,
  outOfRange = 14,
  unavailable = 15,
};

struct Altitude {
  AltitudeValue altitudeValue = kAltitudeValueUnavailable;
  AltitudeConfidence altitudeConfidence = AltitudeConfidence::unavailable;
  friend bool operator==(const Altitude&, const Altitude&) = default;
};

struct ReferencePosition {
  Latitude latitude = kLatitudeUnavailable;
  Longitude longitude = kLongitudeUnavailable;
  PosConfidenceEllipse positionConfidenceEllipse;
  Altitude altitude;
  friend bool operator==(const ReferencePosition&, const ReferencePosition&) = default;
};

using DeltaLatitude = std::int32_t;   // 0.1 microdegree, (-131071..131072)
using DeltaLongitude = std::int32_t;  // 0.1 microdegree, (-131071..131072)
using DeltaAltitude = std::int16_t;   // cm, (-12700..12800)
inline constexpr DeltaLatitude kDeltaLatitudeUnavailable = 131072;
inline constexpr DeltaLongitude kDeltaLongitudeUnavailable = 131072;
inline constexpr DeltaAltitude kDeltaAltitudeUnavailable = 12800;

struct DeltaReferencePosition {
  DeltaLatitude deltaLatitude = 0;
  DeltaLongitude deltaLongitude = 0;
  DeltaAltitude deltaAltitude = 0;
  friend bool operator==(const DeltaReferencePosition&, const DeltaReferencePosition&) = default;
};

/// 10 ms units, (1..65535, ...): only root values are held; the decoder rejects extensions.
using PathDeltaTime = std::uint16_t;

struct PathPoint {
  DeltaReferencePosition pathPosition;
  std::optional<PathDeltaTime> pathDeltaTime;
  friend bool operator==(const PathPoint&, const PathPoint&) = default;
};

/// SEQUENCE (SIZE(0..40)) OF PathPoint.
inline constexpr std::size_t kPathHistoryMaxPoints = 40;
using PathHistory = BoundedVector<PathPoint, kPathHistoryMaxPoints>;

// ---- Motion ------------------------------------------------------------------------------------
using HeadingConfidence = std::uint8_t;  // 0.1 degree, (1..127)
inline constexpr HeadingConfidence kHeadingConfidenceOutOfRange = 126;
inline constexpr HeadingConfidence kHeadingConfidenceUnavailable = 127;

struct Heading {
  HeadingValue headingValue = kHeadingValueUnavailable;
  HeadingConfidence headingConfidence = kHeadingConfidenceUnavailable;
  friend bool operator==(const Heading&, const Heading&) = default;
};

using SpeedValue = std::uint16_t;  // 0.01 m/s, (0..16383)
inline constexpr SpeedValue kSpeedValueUnavailable = 16383;
using SpeedConfidence = std::uint8_t;  // 0.01 m/s, (1..127)
inline constexpr SpeedConfidence kSpeedConfidenceOutOfRange = 126;
inline constexpr SpeedConfidence kSpeedConfidenceUnavailable = 127;

struct Speed {
  SpeedValue speedValue = kSpeedValueUnavailable;
  SpeedConfidence speedConfidence = kSpeedConfidenceUnavailable;
  friend bool operator==(const Speed&, const Speed&) = default;
};

enum class DriveDirection : std::uint8_t { forward = 0, backward = 1, unavailable = 2 };

using VehicleLengthValue = std::uint16_t;  // 0.1 m, (1..1023)
inline constexpr VehicleLengthValue kVehicleLengthValueOutOfRange = 1022;
inline constexpr VehicleLengthValue kVehicleLengthValueUnavailable = 1023;

enum class VehicleLengthConfidenceIndication : std::uint8_t {
  noTrailerPresent = 0,
  trailerPresentWithKnownLength = 1,
  trailerPresentWithUnknownLength = 2,
  trailerPresenceIsUnknown = 3,
  unavailable = 4,
};

struct VehicleLength {
  VehicleLengthValue vehicleLengthValue = kVehicleLengthValueUnavailable;
  VehicleLengthConfidenceIndication vehicleLengthConfidenceIndication =
      VehicleLengthConfidenceIndication::unavailable;
  friend bool operator==(const VehicleLength&, const VehicleLength&) = default;
};

using VehicleWidth = std::uint8_t;  // 0.1 m, (1..62)
inline constexpr VehicleWidth kVehicleWidthOutOfRange = 61;
inline constexpr VehicleWidth kVehicleWidthUnavailable = 62;

using AccelerationValue = std::int16_t;  // 0.1 m/s², (-160..161)
inline constexpr AccelerationValue kAccelerationValueUnavailable = 161;
using AccelerationConfidence = std::uint8_t;  // 0.1 m/s², (0..102)
inline constexpr AccelerationConfidence kAccelerationConfidenceOutOfRange = 101;
inline constexpr AccelerationConfidence kAccelerationConfidenceUnavailable = 102;

/// Positive forward.
struct LongitudinalAcceleration {
  AccelerationValue longitudinalAccelerationValue = kAccelerationValueUnavailable;
  AccelerationConfidence longitudinalAccelerationConfidence = kAccelerationConfidenceUnavailable;
  friend bool operator==(const LongitudinalAcceleration&,
                         const LongitudinalAcceleration&) = default;
};
/// Positive to the left.
struct LateralAcceleration {
  AccelerationValue lateralAccelerationValue = kAccelerationValueUnavailable;
  AccelerationConfidence lateralAccelerationConfidence = kAccelerationConfidenceUnavailable;
  friend bool operator==(const LateralAcceleration&, const LateralAcceleration&) = default;
};
/// Positive up.
struct VerticalAcceleration {
  AccelerationValue verticalAccelerationValue = kAccelerationValueUnavailable;
  AccelerationConfidence verticalAccelerationConfidence = kAccelerationConfidenceUnavailable;
  friend bool operator==(const VerticalAcceleration&, const VerticalAcceleration&) = default;
};

/// Positive to the left. protocolVersion 2: 1/10000 m⁻¹ in (-1023..1023), 1023 unavailable;
/// protocolVersion 1: 1/30000 m⁻¹ in (-30000..30001), 30001 unavailable. Held as encoded for
/// the header's version.
using CurvatureValue = std::int16_t;
inline constexpr CurvatureValue kCurvatureValueUnavailable = 1023;
inline constexpr CurvatureValue kCurvatureValueUnavailableV1 = 30001;

enum class CurvatureConfidence : std::uint8_t {
  onePerMeter_0_00002 = 0,
  onePerMeter_0_0001 = 1,
  onePerMeter_0_0005 = 2,
  onePerMeter_0_002 = 3,
  onePerMeter_0_01 = 4,
  onePerMeter_0_1 = 5,
  outOfRange = 6,
  unavailable = 7,
};

struct Curvature {
  CurvatureValue curvatureValue = kCurvatureValueUnavailable;
  CurvatureConfidence curvatureConfidence = CurvatureConfidence::unavailable;
  friend bool operator==(const Curvature&, const Curvature&) = default;
};

/// ENUMERATED {yawRateUsed, yawRateNotUsed, unavailable, ...}.
enum class CurvatureCalculationMode : std::uint8_t {
  yawRateUsed = 0,
  yawRateNotUsed = 1,
  unavailable = 2,
};

using YawRateValue = std::int16_t;  // 0.01 degree/s, positive to the left, (-32766..32767)
inline constexpr YawRateValue kYawRateValueUnavailable = 32767;

enum class YawRateConfidence : std::uint8_t {
  degSec_000_01 = 0,
  degSec_000_05 = 1,
  degSec_000_10 = 2,
  degSec_001_00 = 3,
  degSec_005_00 = 4,
  degSec_010_00 = 5,
  degSec_100_00 = 6,
  outOfRange = 7,
  unavailable = 8,
};

struct YawRate {
  YawRateValue yawRateValue = kYawRateValueUnavailable;
  YawRateConfidence yawRateConfidence = YawRateConfidence::unavailable;
  friend bool operator==(const YawRate&, const YawRate&) = default;
};

/// BIT STRING (SIZE(7)); bit n of the ASN.1 named-bit list is (1 << n) here.
using AccelerationControl = std::uint8_t;
namespace acceleration_control {
inline constexpr AccelerationControl kBrakePedalEngaged = 1 << 0;
inline constexpr AccelerationControl kGasPedalEngaged = 1 << 1;
inline constexpr AccelerationControl kEmergencyBrakeEngaged = 1 << 2;
inline constexpr AccelerationControl kCollisionWarningEngaged = 1 << 3;
inline constexpr AccelerationControl kAccEngaged = 1 << 4;
inline constexpr AccelerationControl kCruiseControlEngaged = 1 << 5;
inline constexpr AccelerationControl kSpeedLimiterEngaged = 1 << 6;
}  // namespace acceleration_control

using LanePosition = std::int8_t;  // (-1..14): offTheRoad(-1), hardShoulder(0), outermost(1)…

using SteeringWheelAngleValue = std::int16_t;  // 1.5 degree, positive left, (-511..512)
inline constexpr SteeringWheelAngleValue kSteeringWheelAngleValueUnavailable = 512;
using SteeringWheelAngleConfidence = std::uint8_t;  // 1.5 degree, (1..127)
inline constexpr SteeringWheelAngleConfidence kSteeringWheelAngleConfidenceOutOfRange = 126;
inline constexpr SteeringWheelAngleConfidence kSteeringWheelAngleConfidenceUnavailable = 127;

struct SteeringWheelAngle {
  SteeringWheelAngleValue steeringWheelAngleValue = kSteeringWheelAngleValueUnavailable;
  SteeringWheelAngleConfidence steeringWheelAngleConfidence =
      kSteeringWheelAngleConfidenceUnavailable;
  friend bool operator==(const SteeringWheelAngle&, const SteeringWheelAngle&) = default;
};

using PerformanceClass = std::uint8_t;  // (0..7), 0 unavailable

using ProtectedZoneID = std::uint32_t;  // (0..134217727)

/// SEQUENCE {protectedZoneLatitude, protectedZoneLongitude, cenDsrcTollingZoneID OPTIONAL, ...}
struct CenDsrcTollingZone {
  Latitude protectedZoneLatitude = kLatitudeUnavailable;
  Longitude protectedZoneLongitude = kLongitudeUnavailable;
  std::optional<ProtectedZoneID> cenDsrcTollingZoneID;
  friend bool operator==(const CenDsrcTollingZone&, const CenDsrcTollingZone&) = default;
};

// ---- Vehicle role and lights -------------------------------------------------------------------
/// ENUMERATED with 16 values, not extensible.
enum class VehicleRole : std::uint8_t {
  default_ = 0,
  publicTransport = 1,
  specialTransport = 2,
  dangerousGoods = 3,
  roadWork = 4,
  rescue = 5,
  emergency = 6,
  safetyCar = 7,
  agriculture = 8,
  commercial = 9,
  military = 10,
  roadOperator = 11,
  taxi = 12,
  reserved1 = 13,
  reserved2 = 14,
  reserved3 = 15,
};

/// BIT STRING (SIZE(8)); bit n of the ASN.1 named-bit list is (1 << n) here.
using ExteriorLights = std::uint8_t;
namespace exterior_lights {
inline constexpr ExteriorLights kLowBeamHeadlightsOn = 1 << 0;
inline constexpr ExteriorLights kHighBeamHeadlightsOn = 1 << 1;
inline constexpr ExteriorLights kLeftTurnSignalOn = 1 << 2;
inline constexpr ExteriorLights kRightTurnSignalOn = 1 << 3;
inline constexpr ExteriorLights kDaytimeRunningLightsOn = 1 << 4;
inline constexpr ExteriorLights kReverseLightOn = 1 << 5;
inline constexpr ExteriorLights kFogLightOn = 1 << 6;
inline constexpr ExteriorLights kParkingLightsOn = 1 << 7;
}  // namespace exterior_lights

// ---- Special vehicles (CAM special-vehicle containers) ----------------------------------------
/// BIT STRING (SIZE(2)): lightBarActivated (bit 0), sirenActivated (bit 1).
using LightBarSirenInUse = std::uint8_t;
namespace light_bar_siren {
inline constexpr LightBarSirenInUse kLightBarActivated = 1 << 0;
inline constexpr LightBarSirenInUse kSirenActivated = 1 << 1;
}  // namespace light_bar_siren
/// BIT STRING (SIZE(4)): heavyLoad, excessWidth, excessLength, excessHeight (bits 0..3).
using SpecialTransportType = std::uint8_t;
/// BIT STRING (SIZE(2)): requestForRightOfWay (0), requestForFreeCrossingAtATrafficLight (1).
using EmergencyPriority = std::uint8_t;
/// ENUMERATED explosives1 (0) … miscellaneousDangerousSubstances (19), not extensible.
using DangerousGoodsBasic = std::uint8_t;
using SpeedLimit = std::uint8_t;  // km/h, (1..255)

/// ENUMERATED {noPassing, noPassingForTrucks, passToRight, passToLeft, ...}.
enum class TrafficRule : std::uint8_t {
  noPassing = 0,
  noPassingForTrucks = 1,
  passToRight = 2,
  passToLeft = 3,
};

enum class HardShoulderStatus : std::uint8_t {
  availableForStopping = 0,
  closed = 1,
  availableForDriving = 2,
};

/// BIT STRING (SIZE(1..13)), SIZE(1..14) in CDD version 1: @p size bits; bit n (lane n from
/// the outside) is (1 << n).
struct DrivingLaneStatus {
  std::uint16_t bits = 0;
  std::uint8_t size = 1;
  friend bool operator==(const DrivingLaneStatus&, const DrivingLaneStatus&) = default;
};

/// SEQUENCE {innerhardShoulderStatus, outerhardShoulderStatus, drivingLaneStatus (all
/// OPTIONAL), ...} in CDD version 2. CDD version 1 (protocolVersion 1) has SEQUENCE
/// {hardShoulderStatus OPTIONAL, drivingLaneStatus BIT STRING (SIZE(1..14)), ...}: its one hard
/// shoulder is the outer one (its LanePosition counts from the outside), so it is held in
/// outerhardShoulderStatus, innerhardShoulderStatus stays empty and drivingLaneStatus is present.
struct ClosedLanes {
  std::optional<HardShoulderStatus> innerhardShoulderStatus;
  std::optional<HardShoulderStatus> outerhardShoulderStatus;
  std::optional<DrivingLaneStatus> drivingLaneStatus;
  friend bool operator==(const ClosedLanes&, const ClosedLanes&) = default;
};

/// SEQUENCE {ptActivationType (0..255), ptActivationData OCTET STRING (SIZE(1..20))}.
struct PtActivation {
  std::uint8_t ptActivationType = 0;
  BoundedVector<std::uint8_t, 20> ptActivationData;
  friend bool operator==(const PtActivation&, const PtActivation&) = default;
};

// ---- Road-side units (CAM RSU high-frequency container) ---------------------------------------
/// ENUMERATED {permanentCenDsrcTolling (0), ..., temporaryCenDsrcTolling (1)}: the second value
/// is an extension addition of CDD version 2 (encoded as extension index 0); CDD version 1 has
/// only the first, named cenDsrcTolling.
enum class ProtectedZoneType : std::uint8_t {
  permanentCenDsrcTolling = 0,
  temporaryCenDsrcTolling = 1,
};
using ProtectedZoneRadius = std::uint8_t;  // m, (1..255, ...): only root values are held

// ---- Vehicle details (DENM à-la-carte container) -----------------------------------------------
using HeightLonCarr = std::uint8_t;      // cm, (1..100), 100 unavailable
using PosLonCarr = std::uint8_t;         // cm, (1..127), 127 unavailable
using PosPillar = std::uint8_t;          // 10 cm, (1..30), 30 unavailable
using PosCentMass = std::uint8_t;        // 10 cm, (1..63), 63 unavailable
using WheelBaseVehicle = std::uint8_t;   // 10 cm, (1..127), 127 unavailable
using TurningRadius = std::uint8_t;      // 0.4 m, (1..255), 255 unavailable
using PosFrontAx = std::uint8_t;         // 10 cm, (1..20), 20 unavailable
using VehicleMass = std::uint16_t;       // 100 kg, (1..1024), 1024 unavailable
using NumberOfOccupants = std::uint8_t;  // (0..127), 127 unavailable
/// SEQUENCE (SIZE(1..3, ...)) OF PosPillar: only root sizes are held.
using PositionOfPillars = BoundedVector<PosPillar, 3>;
/// BIT STRING (SIZE(20)): row1LeftOccupied (bit 0) … row4NotPresent (bit 19).
using PositionOfOccupants = std::uint32_t;
/// BIT STRING (SIZE(7)): hydrogenStorage (bit 0), electricEnergyStorage, liquidPropaneGas,
/// compressedNaturalGas, diesel, gasoline, ammonia (bit 6).
using EnergyStorageType = std::uint8_t;
/// SEQUENCE (SIZE(1..3, ...)) OF StationType: only root sizes are held.
using RestrictedTypes = BoundedVector<StationType, 3>;

enum class RequestResponseIndication : std::uint8_t { request = 0, response = 1 };

enum class StationarySince : std::uint8_t {
  lessThan1Minute = 0,
  lessThan2Minutes = 1,
  lessThan15Minutes = 2,
  equalOrGreater15Minutes = 3,
};

/// A character string of at most @p N characters (IA5String, NumericString), one char each.
template <std::size_t N>
using CharString = BoundedVector<char, N>;
/// Builds a CharString from @p s; the characters past @p N are dropped (the caller's to avoid).
template <std::size_t N>
CharString<N> char_string(const char* s) {
  CharString<N> out;
  for (; s != nullptr && *s != '\0' && out.push_back(*s); ++s) {
  }
  return out;
}

/// SEQUENCE {dangerousGoodsType, unNumber (0..9999), elevatedTemperature, tunnelsRestricted,
/// limitedQuantity, emergencyActionCode IA5String (SIZE(1..24)) OPTIONAL, phoneNumber
/// OPTIONAL, companyName UTF8String (SIZE(1..24)) OPTIONAL, ...}. phoneNumber is a
/// NumericString (SIZE(1..16)) in CDD version 2 and an IA5String (SIZE(1..24)) in version 1,
/// which also has no extension marker here. companyName holds the UTF-8 octets (up to 24
/// characters of up to 4 octets).
struct DangerousGoodsExtended {
  DangerousGoodsBasic dangerousGoodsType = 0;
  std::uint16_t unNumber = 0;
  bool elevatedTemperature = false;
  bool tunnelsRestricted = false;
  bool limitedQuantity = false;
  std::optional<CharString<24>> emergencyActionCode;
  std::optional<CharString<24>> phoneNumber;
  std::optional<BoundedVector<std::uint8_t, 96>> companyName;
  friend bool operator==(const DangerousGoodsExtended&, const DangerousGoodsExtended&) = default;
};

/// SEQUENCE {wMInumber IA5String (SIZE(1..3)) OPTIONAL, vDS IA5String (SIZE(6)) OPTIONAL, ...}.
struct VehicleIdentification {
  std::optional<CharString<3>> wMInumber;
  std::optional<CharString<6>> vDS;  ///< exactly 6 characters
  friend bool operator==(const VehicleIdentification&, const VehicleIdentification&) = default;
};

// ---- Time --------------------------------------------------------------------------------------
/// Milliseconds since 2004-01-01T00:00:00.000 UTC (0..4398046511103).
using TimestampIts = std::uint64_t;
inline constexpr TimestampIts kTimestampItsMax = 4398046511103ULL;

// ---- Events (DENM) -----------------------------------------------------------------------------
using SequenceNumber = std::uint16_t;  // (0..65535)

struct ActionID {
  StationID originatingStationID = 0;
  SequenceNumber sequenceNumber = 0;
  friend bool operator==(const ActionID&, const ActionID&) = default;
};

using CauseCodeType = std::uint8_t;     // (0..255)
using SubCauseCodeType = std::uint8_t;  // (0..255)
namespace cause_code {
inline constexpr CauseCodeType kTrafficCondition = 1;
inline constexpr CauseCodeType kAccident = 2;
inline constexpr CauseCodeType kRoadworks = 3;
inline constexpr CauseCodeType kWrongWayDriving = 14;
inline constexpr CauseCodeType kSlowVehicle = 26;
inline constexpr CauseCodeType kDangerousEndOfQueue = 27;
inline constexpr CauseCodeType kVehicleBreakdown = 91;
inline constexpr CauseCodeType kStationaryVehicle = 94;
inline constexpr CauseCodeType kEmergencyVehicleApproaching = 95;
inline constexpr CauseCodeType kCollisionRisk = 97;
inline constexpr CauseCodeType kDangerousSituation = 99;
}  // namespace cause_code
namespace collision_risk_sub_cause {
inline constexpr SubCauseCodeType kUnavailable = 0;
inline constexpr SubCauseCodeType kLongitudinalCollisionRisk = 1;
inline constexpr SubCauseCodeType kCrossingCollisionRisk = 2;
inline constexpr SubCauseCodeType kLateralCollisionRisk = 3;
inline constexpr SubCauseCodeType kVulnerableRoadUser = 4;
}  // namespace collision_risk_sub_cause

/// SEQUENCE {causeCode, subCauseCode, ...}.
struct CauseCode {
  CauseCodeType causeCode = 0;
  SubCauseCodeType subCauseCode = 0;
  friend bool operator==(const CauseCode&, const CauseCode&) = default;
};

using InformationQuality = std::uint8_t;  // (0..7), 0 unavailable, 1 lowest, 7 highest

enum class RelevanceDistance : std::uint8_t {
  lessThan50m = 0,
  lessThan100m = 1,
  lessThan200m = 2,
  lessThan500m = 3,
  lessThan1000m = 4,
  lessThan5km = 5,
  lessThan10km = 6,
  over10km = 7,
};

enum class RelevanceTrafficDirection : std::uint8_t {
  allTrafficDirections = 0,
  upstreamTraffic = 1,
  downstreamTraffic = 2,
  oppositeTraffic = 3,
};

using ValidityDuration = std::uint32_t;      // s, (0..86400)
using TransmissionInterval = std::uint16_t;  // ms, (1..10000)

struct EventPoint {
  DeltaReferencePosition eventPosition;
  std::optional<PathDeltaTime> eventDeltaTime;
  InformationQuality informationQuality = 0;
  friend bool operator==(const EventPoint&, const EventPoint&) = default;
};
/// SEQUENCE (SIZE(1..23)) OF EventPoint.
using EventHistory = BoundedVector<EventPoint, 23>;

/// SEQUENCE SIZE(1..7) OF PathHistory.
using Traces = BoundedVector<PathHistory, 7>;

/// SEQUENCE SIZE(1..40) OF ReferencePosition.
using ItineraryPath = BoundedVector<ReferencePosition, 40>;

enum class RoadType : std::uint8_t {
  urban_NoStructuralSeparationToOppositeLanes = 0,
  urban_WithStructuralSeparationToOppositeLanes = 1,
  nonUrban_NoStructuralSeparationToOppositeLanes = 2,
  nonUrban_WithStructuralSeparationToOppositeLanes = 3,
};

}  // namespace tb::its::messages
