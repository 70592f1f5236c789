#pragma once
/// @file The Decentralized Environmental Notification Message of EN 302 637-3 V1.3.1 (module
/// DENM-PDU-Descriptions version 2) and its UPER (ITU-T X.691 unaligned) codec.
///
/// Covered: ItsPduHeader and every container in full: management, situation, location and the
/// à-la-carte container with all its members (lanePosition, impactReduction,
/// externalTemperature, roadWorks, positioningSolution, stationaryVehicle), for protocolVersion
/// 2 and 1 (whose CDD differs in CauseCode, ClosedLanes and DangerousGoodsExtended, cdd.hpp).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "common/util/expected.hpp"
#include "its-station/asn1/error.hpp"
#include "its-station/messages/cdd.hpp"

namespace tb::its::messages {

using asn1::CodecError;

/// ENUMERATED {isCancellation(0), isNegation(1)}: the originator cancels its own event, any
/// other station negates it (EN 302 637-3 clause 8.1).
enum class Termination : std::uint8_t { isCancellation = 0, isNegation = 1 };

/// DEFAULT of ManagementContainer.validityDuration, seconds (EN 302 637-3 annex A).
inline constexpr ValidityDuration kDefaultValidity = 600;

struct ManagementContainer {
  ActionID actionID;
  TimestampIts detectionTime = 0;
  TimestampIts referenceTime = 0;
  std::optional<Termination> termination;
  ReferencePosition eventPosition;
  std::optional<RelevanceDistance> relevanceDistance;
  std::optional<RelevanceTrafficDirection> relevanceTrafficDirection;
  /// Encoded only when it differs from the DEFAULT (canonical PER, X.691 19.5).
  ValidityDuration validityDuration = kDefaultValidity;
  std::optional<TransmissionInterval> transmissionInterval;
  StationType stationType = station_type::kPassengerCar;
  friend bool operator==(const ManagementContainer&, const ManagementContainer&) = default;
};

struct SituationContainer {
  InformationQuality informationQuality = 0;
  CauseCode eventType;
  std::optional<CauseCode> linkedCause;
  std::optional<EventHistory> eventHistory;
  friend bool operator==(const SituationContainer&, const SituationContainer&) = default;
};

struct LocationContainer {
  std::optional<Speed> eventSpeed;
  std::optional<Heading> eventPositionHeading;
  Traces traces;  ///< SIZE(1..7): at least one PathHistory (which may be empty)
  std::optional<RoadType> roadType;
  friend bool operator==(const LocationContainer&, const LocationContainer&) = default;
};

using Temperature = std::int8_t;  // degree Celsius, (-60..67)

/// ENUMERATED {noPositioningSolution, sGNSS, dGNSS, sGNSSplusDR, dGNSSplusDR, dR, ...}.
enum class PositioningSolutionType : std::uint8_t {
  noPositioningSolution = 0,
  sGNSS = 1,
  dGNSS = 2,
  sGNSSplusDR = 3,
  dGNSSplusDR = 4,
  dR = 5,
};

/// SEQUENCE {heightLonCarrLeft, heightLonCarrRight, posLonCarrLeft, posLonCarrRight,
/// positionOfPillars, posCentMass, wheelBaseVehicle, turningRadius, posFrontAx,
/// positionOfOccupants, vehicleMass, requestResponseIndication}: the vehicle's build, for
/// reducing the impact of a collision. The defaults are the CDD's unavailable values.
struct ImpactReductionContainer {
  HeightLonCarr heightLonCarrLeft = 100;
  HeightLonCarr heightLonCarrRight = 100;
  PosLonCarr posLonCarrLeft = 127;
  PosLonCarr posLonCarrRight = 127;
  PositionOfPillars positionOfPillars{30};  ///< SIZE(1..3): one, unavailable
  PosCentMass posCentMass = 63;
  WheelBaseVehicle wheelBaseVehicle = 127;
  TurningRadius turningRadius = 255;
  PosFrontAx posFrontAx = 20;
  PositionOfOccupants positionOfOccupants = 0;
  VehicleMass vehicleMass = 1024;
  RequestResponseIndication requestResponseIndication = RequestResponseIndication::request;
  friend bool operator==(const ImpactReductionContainer&,
                         const ImpactReductionContainer&) = default;
};

/// ReferenceDenms ::= SEQUENCE (SIZE(1..8, ...)) OF ActionID: only root sizes are held.
using ReferenceDenms = BoundedVector<ActionID, 8>;

/// SEQUENCE {lightBarSirenInUse, closedLanes, restriction, speedLimit, incidentIndication,
/// recommendedPath, startingPointSpeedLimit, trafficFlowRule, referenceDenms}, all OPTIONAL, no
/// extension marker.
struct RoadWorksContainerExtended {
  std::optional<LightBarSirenInUse> lightBarSirenInUse;
  std::optional<ClosedLanes> closedLanes;
  std::optional<RestrictedTypes> restriction;
  std::optional<SpeedLimit> speedLimit;
  std::optional<CauseCode> incidentIndication;
  std::optional<ItineraryPath> recommendedPath;
  std::optional<DeltaReferencePosition> startingPointSpeedLimit;
  std::optional<TrafficRule> trafficFlowRule;
  std::optional<ReferenceDenms> referenceDenms;
  friend bool operator==(const RoadWorksContainerExtended&,
                         const RoadWorksContainerExtended&) = default;
};

/// SEQUENCE {stationarySince, stationaryCause, carryingDangerousGoods, numberOfOccupants,
/// vehicleIdentification, energyStorageType}, all OPTIONAL, no extension marker.
struct StationaryVehicleContainer {
  std::optional<StationarySince> stationarySince;
  std::optional<CauseCode> stationaryCause;
  std::optional<DangerousGoodsExtended> carryingDangerousGoods;
  std::optional<NumberOfOccupants> numberOfOccupants;
  std::optional<VehicleIdentification> vehicleIdentification;
  std::optional<EnergyStorageType> energyStorageType;
  friend bool operator==(const StationaryVehicleContainer&,
                         const StationaryVehicleContainer&) = default;
};

/// SEQUENCE {lanePosition, impactReduction, externalTemperature, roadWorks,
/// positioningSolution, stationaryVehicle (all OPTIONAL), ...}.
struct AlacarteContainer {
  std::optional<LanePosition> lanePosition;
  std::optional<ImpactReductionContainer> impactReduction;
  std::optional<Temperature> externalTemperature;
  std::optional<RoadWorksContainerExtended> roadWorks;
  std::optional<PositioningSolutionType> positioningSolution;
  std::optional<StationaryVehicleContainer> stationaryVehicle;
  friend bool operator==(const AlacarteContainer&, const AlacarteContainer&) = default;
};

struct DecentralizedEnvironmentalNotificationMessage {
  ManagementContainer management;
  std::optional<SituationContainer> situation;
  std::optional<LocationContainer> location;
  std::optional<AlacarteContainer> alacarte;
  friend bool operator==(const DecentralizedEnvironmentalNotificationMessage&,
                         const DecentralizedEnvironmentalNotificationMessage&) = default;
};

/// DENM ::= SEQUENCE {header ItsPduHeader, denm DecentralizedEnvironmentalNotificationMessage}.
struct Denm {
  ItsPduHeader header{kProtocolVersion, kMessageIdDenm, 0};
  DecentralizedEnvironmentalNotificationMessage denm;
  friend bool operator==(const Denm&, const Denm&) = default;
};

/// Largest UPER encoding of a Denm as modelled here (7 traces of 40 points, 23 event points,
/// every à-la-carte member at its largest), in bytes, with room to spare.
inline constexpr std::size_t kDenmMaxEncodedSize = 4096;

/// As for Cam (cam.hpp): encode into @p out and return the bytes written, or an error naming
/// the field outside its constraint; messageID must be denm (1), protocolVersion 2 or 1.
Expected<std::size_t, CodecError> encode(const Denm& denm, std::span<std::uint8_t> out);
Expected<std::vector<std::uint8_t>, CodecError> encode(const Denm& denm);

/// Decodes one UPER-encoded DENM of protocolVersion 2 or 1; returns the bytes consumed. Never
/// reads outside @p bytes. After an error @p out is unspecified: use it only on success.
Expected<std::size_t, CodecError> decode(std::span<const std::uint8_t> bytes, Denm& out);
Expected<Denm, CodecError> decode_denm(std::span<const std::uint8_t> bytes);

}  // namespace tb::its::messages
