#pragma once
/// @file The Decentralized Environmental Notification Message of EN 302 637-3 V1.3.1 (module
/// DENM-PDU-Descriptions version 2) and its UPER (ITU-T X.691 unaligned) codec.
///
/// Covered: ItsPduHeader, the management, situation and location containers in full, and the
/// simple members of the à-la-carte container (lanePosition, externalTemperature,
/// positioningSolution). An à-la-carte container carrying impactReduction, roadWorks or
/// stationaryVehicle is answered with Error::kUnsupported naming the component.

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

struct AlacarteContainer {
  std::optional<LanePosition> lanePosition;
  std::optional<Temperature> externalTemperature;
  std::optional<PositioningSolutionType> positioningSolution;
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

/// Largest UPER encoding of a Denm as modelled here (7 traces of 40 points), in bytes.
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
