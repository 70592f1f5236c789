#pragma once
/// @file The Cooperative Awareness Message of EN 302 637-2 V1.4.1 (module CAM-PDU-Descriptions
/// version 2) and its UPER (ITU-T X.691 unaligned) codec.
///
/// Covered, for protocolVersion 2 and 1: ItsPduHeader, the basic container, both alternatives
/// of the high-frequency container (a vehicle's basicVehicleContainerHighFrequency with all its
/// optional fields, and a road-side unit's rsuContainerHighFrequency with its protected
/// communication zones), the low-frequency container of a vehicle (vehicleRole,
/// exteriorLights, pathHistory of up to 40 points) and every special-vehicle container (public
/// transport, special transport, dangerous goods, road works, rescue, emergency, safety car).
/// Extension additions of extensible SEQUENCEs are skipped when decoding, as X.691 clause 19
/// allows a decoder of an earlier version to.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <variant>
#include <vector>

#include "common/util/expected.hpp"
#include "its-station/asn1/error.hpp"
#include "its-station/messages/cdd.hpp"

namespace tb::its::messages {

using asn1::CodecError;

/// Milliseconds, TimestampIts mod 65536 of the position's time (EN 302 637-2 B.3).
using GenerationDeltaTime = std::uint16_t;

/// SEQUENCE {stationType, referencePosition, ...}.
struct BasicContainer {
  StationType stationType = station_type::kPassengerCar;
  ReferencePosition referencePosition;
  friend bool operator==(const BasicContainer&, const BasicContainer&) = default;
};

struct BasicVehicleContainerHighFrequency {
  Heading heading;
  Speed speed;
  DriveDirection driveDirection = DriveDirection::unavailable;
  VehicleLength vehicleLength;
  VehicleWidth vehicleWidth = kVehicleWidthUnavailable;
  LongitudinalAcceleration longitudinalAcceleration;
  Curvature curvature;
  CurvatureCalculationMode curvatureCalculationMode = CurvatureCalculationMode::unavailable;
  YawRate yawRate;
  std::optional<AccelerationControl> accelerationControl;
  std::optional<LanePosition> lanePosition;
  std::optional<SteeringWheelAngle> steeringWheelAngle;
  std::optional<LateralAcceleration> lateralAcceleration;
  std::optional<VerticalAcceleration> verticalAcceleration;
  std::optional<PerformanceClass> performanceClass;
  std::optional<CenDsrcTollingZone> cenDsrcTollingZone;
  friend bool operator==(const BasicVehicleContainerHighFrequency&,
                         const BasicVehicleContainerHighFrequency&) = default;
};

struct BasicVehicleContainerLowFrequency {
  VehicleRole vehicleRole = VehicleRole::default_;
  ExteriorLights exteriorLights = 0;
  PathHistory pathHistory;
  friend bool operator==(const BasicVehicleContainerLowFrequency&,
                         const BasicVehicleContainerLowFrequency&) = default;
};

/// ProtectedCommunicationZone ::= SEQUENCE {protectedZoneType, expiryTime OPTIONAL,
/// protectedZoneLatitude, protectedZoneLongitude, protectedZoneRadius OPTIONAL,
/// protectedZoneID OPTIONAL, ...} (CDD version 1: no extension marker).
struct ProtectedCommunicationZone {
  ProtectedZoneType protectedZoneType = ProtectedZoneType::permanentCenDsrcTolling;
  std::optional<TimestampIts> expiryTime;
  Latitude protectedZoneLatitude = kLatitudeUnavailable;
  Longitude protectedZoneLongitude = kLongitudeUnavailable;
  std::optional<ProtectedZoneRadius> protectedZoneRadius;
  std::optional<ProtectedZoneID> protectedZoneID;
  friend bool operator==(const ProtectedCommunicationZone&,
                         const ProtectedCommunicationZone&) = default;
};
/// SEQUENCE (SIZE(1..16)) OF ProtectedCommunicationZone.
using ProtectedCommunicationZonesRSU = BoundedVector<ProtectedCommunicationZone, 16>;

/// RSUContainerHighFrequency ::= SEQUENCE {protectedCommunicationZonesRSU OPTIONAL, ...}: the
/// high-frequency container of a road-side unit's CAM (EN 302 637-2 B.2.3).
struct RSUContainerHighFrequency {
  std::optional<ProtectedCommunicationZonesRSU> protectedCommunicationZonesRSU;
  friend bool operator==(const RSUContainerHighFrequency&,
                         const RSUContainerHighFrequency&) = default;
};

/// HighFrequencyContainer ::= CHOICE {basicVehicleContainerHighFrequency,
/// rsuContainerHighFrequency, ...}: the variant's index is the CHOICE index.
using HighFrequencyContainer =
    std::variant<BasicVehicleContainerHighFrequency, RSUContainerHighFrequency>;

// ---- Special-vehicle containers (EN 302 637-2 B.2.x) -------------------------------------------
struct PublicTransportContainer {
  bool embarkationStatus = false;
  std::optional<PtActivation> ptActivation;
  friend bool operator==(const PublicTransportContainer&,
                         const PublicTransportContainer&) = default;
};
struct SpecialTransportContainer {
  SpecialTransportType specialTransportType = 0;
  LightBarSirenInUse lightBarSirenInUse = 0;
  friend bool operator==(const SpecialTransportContainer&,
                         const SpecialTransportContainer&) = default;
};
struct DangerousGoodsContainer {
  DangerousGoodsBasic dangerousGoodsBasic = 0;
  friend bool operator==(const DangerousGoodsContainer&, const DangerousGoodsContainer&) = default;
};
struct RoadWorksContainerBasic {
  std::optional<SubCauseCodeType> roadworksSubCauseCode;
  LightBarSirenInUse lightBarSirenInUse = 0;
  std::optional<ClosedLanes> closedLanes;
  friend bool operator==(const RoadWorksContainerBasic&, const RoadWorksContainerBasic&) = default;
};
struct RescueContainer {
  LightBarSirenInUse lightBarSirenInUse = 0;
  friend bool operator==(const RescueContainer&, const RescueContainer&) = default;
};
struct EmergencyContainer {
  LightBarSirenInUse lightBarSirenInUse = 0;
  std::optional<CauseCode> incidentIndication;
  std::optional<EmergencyPriority> emergencyPriority;
  friend bool operator==(const EmergencyContainer&, const EmergencyContainer&) = default;
};
struct SafetyCarContainer {
  LightBarSirenInUse lightBarSirenInUse = 0;
  std::optional<CauseCode> incidentIndication;
  std::optional<TrafficRule> trafficRule;
  std::optional<SpeedLimit> speedLimit;
  friend bool operator==(const SafetyCarContainer&, const SafetyCarContainer&) = default;
};
/// CHOICE {publicTransportContainer, specialTransportContainer, dangerousGoodsContainer,
/// roadWorksContainerBasic, rescueContainer, emergencyContainer, safetyCarContainer, ...}: the
/// variant's index is the CHOICE index.
using SpecialVehicleContainer =
    std::variant<PublicTransportContainer, SpecialTransportContainer, DangerousGoodsContainer,
                 RoadWorksContainerBasic, RescueContainer, EmergencyContainer, SafetyCarContainer>;

/// SEQUENCE {basicContainer, highFrequencyContainer, lowFrequencyContainer OPTIONAL,
/// specialVehicleContainer OPTIONAL, ...}. lowFrequencyContainer is always
/// basicVehicleContainerLowFrequency (its only root alternative).
struct CamParameters {
  BasicContainer basicContainer;
  HighFrequencyContainer highFrequencyContainer;  ///< a vehicle's unless set to an RSU's
  std::optional<BasicVehicleContainerLowFrequency> lowFrequencyContainer;
  std::optional<SpecialVehicleContainer> specialVehicleContainer;
  friend bool operator==(const CamParameters&, const CamParameters&) = default;
};

struct CoopAwareness {
  GenerationDeltaTime generationDeltaTime = 0;
  CamParameters camParameters;
  friend bool operator==(const CoopAwareness&, const CoopAwareness&) = default;
};

/// CAM ::= SEQUENCE {header ItsPduHeader, cam CoopAwareness}.
struct Cam {
  ItsPduHeader header{kProtocolVersion, kMessageIdCam, 0};
  CoopAwareness cam;
  friend bool operator==(const Cam&, const Cam&) = default;
};

/// The vehicle high-frequency container of @p p, or null when it is an RSU's CAM.
inline BasicVehicleContainerHighFrequency* vehicle_hf(CamParameters& p) {
  return std::get_if<BasicVehicleContainerHighFrequency>(&p.highFrequencyContainer);
}
inline const BasicVehicleContainerHighFrequency* vehicle_hf(const CamParameters& p) {
  return std::get_if<BasicVehicleContainerHighFrequency>(&p.highFrequencyContainer);
}

/// Largest UPER encoding of a Cam as modelled here (all optional fields, 40 path points, or an
/// RSU container with 16 zones), in bytes; a buffer this big never gives kBufferTooSmall.
inline constexpr std::size_t kCamMaxEncodedSize = 1024;

/// Encodes @p cam into @p out, by the rules of header.protocolVersion (2, or 1); returns the
/// number of bytes written. Fails with
/// kValueOutOfRange (naming the field and value) when a field is outside its ASN.1
/// constraint, kWrongMessageId unless header.messageID is cam (2), kBufferTooSmall when @p out
/// is too short. No heap allocation.
Expected<std::size_t, CodecError> encode(const Cam& cam, std::span<std::uint8_t> out);
Expected<std::vector<std::uint8_t>, CodecError> encode(const Cam& cam);

/// Decodes one UPER-encoded CAM from @p bytes into @p out; returns the bytes consumed
/// (the encoding padded to a whole octet). Rejects a messageID other than cam,
/// protocolVersion other than 1 or 2 (see kProtocolVersion1), values outside their constraints,
/// truncated input and unsupported choices. Never reads outside @p bytes; no heap allocation.
/// After an error @p out is unspecified: use it only on success.
Expected<std::size_t, CodecError> decode(std::span<const std::uint8_t> bytes, Cam& out);
Expected<Cam, CodecError> decode_cam(std::span<const std::uint8_t> bytes);

}  // namespace tb::its::messages
