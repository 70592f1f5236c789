#pragma once
/// @file Data elements and frames of the ISO TS 19091 (2018) DSRC module (the SAE J2735 names)
/// that SPATEM and MAPEM (ETSI TS 103 301 v2.1.1) carry.
///
/// As in cdd.hpp: member names are the ASN.1 component names (`class` is `class_`, the
/// hyphenated ones use `_`), values are held in the units the ASN.1 encodes (TimeMark in 0.1 s
/// of the UTC hour, node offsets in cm, latitude in 0.1 µdeg, Velocity in 0.02 m/s), bit
/// strings are integers whose bit n is the named bit n, and SEQUENCE OF types are
/// BoundedVector. Where the module's upper bound would make a message too large to hold
/// inline, the bound here is smaller (the `k...Max` constants, README "Bounds"); a longer list
/// is kSizeOutOfRange on both sides.
///
/// Regional extensions (SEQUENCE OF RegionalExtension, an open type each) are not held: the
/// decoder skips them and the encoder writes none. Ranges are checked by the codec, not here.

#include <cstdint>
#include <optional>
#include <variant>

#include "its-station/messages/bounded_vector.hpp"
#include "its-station/messages/cdd.hpp"

namespace tb::its::messages {

// ---- ItsPduHeader messageIDs of TS 103 301 ---------------------------------------------------
inline constexpr std::uint8_t kMessageIdSpatem = 4;
inline constexpr std::uint8_t kMessageIdMapem = 5;

// ---- Data elements ---------------------------------------------------------------------------
using MinuteOfTheYear = std::uint32_t;  // (0..527040), 527040 = unavailable
inline constexpr MinuteOfTheYear kMinuteOfTheYearUnavailable = 527040;
using DSecond = std::uint16_t;  // ms within the minute (0..65535), 60000..61999 leap second
using MsgCount = std::uint8_t;  // (0..127)
using IntersectionID = std::uint16_t;
using RoadRegulatorID = std::uint16_t;
using SignalGroupID = std::uint8_t;  // 0 and 255 are reserved by J2735 (not checked)
using LaneID = std::uint8_t;
using LaneConnectionID = std::uint8_t;
using RestrictionClassID = std::uint8_t;
using ApproachID = std::uint8_t;              // (0..15)
using LayerID = std::uint8_t;                 // (0..100)
using LaneWidth = std::uint16_t;              // cm (0..32767)
using Elevation = std::int32_t;               // 0.1 m (-4096..61439), -4096 = unavailable
using Velocity = std::uint16_t;               // 0.02 m/s (0..8191), 8191 = unavailable
using ZoneLength = std::uint16_t;             // m (0..10000)
using SpeedAdvice = std::uint16_t;            // 0.1 m/s (0..500)
using TimeIntervalConfidence = std::uint8_t;  // (0..15), a table of probabilities in J2735

/// TimeMark ::= INTEGER (0..36001): tenths of a second since the start of the current or next
/// UTC hour; 36000 marks a leap second, 36001 "unknown" (ISO TS 19091 / J2735 DE_TimeMark).
using TimeMark = std::uint16_t;
inline constexpr TimeMark kTimeMarkMax = 36001;
inline constexpr TimeMark kTimeMarkLeapSecond = 36000;
inline constexpr TimeMark kTimeMarkUnknown = 36001;

/// The TimeMark of a UTC instant (ms since the Unix epoch): tenths since the hour, rounded
/// down. The sender's side of the only conversion the testbed makes (contract: times travel as
/// UTC ms inside the testbed).
constexpr TimeMark time_mark_from_utc_ms(std::int64_t utc_ms) {
  const std::int64_t in_hour = ((utc_ms % 3'600'000) + 3'600'000) % 3'600'000;
  return static_cast<TimeMark>(in_hour / 100);
}
/// The UTC instant (ms since the Unix epoch) a received TimeMark @p t (0..35999) means: the one
/// nearest to the receiver's own clock @p now_utc_ms, i.e. in the hour before, of, or after now
/// (TimeMarks look ahead at most half an hour in practice). Not for 36000/36001.
constexpr std::int64_t utc_ms_from_time_mark(TimeMark t, std::int64_t now_utc_ms) {
  const std::int64_t hour = now_utc_ms - (((now_utc_ms % 3'600'000) + 3'600'000) % 3'600'000);
  std::int64_t best = hour + std::int64_t{t} * 100;
  for (const std::int64_t candidate : {best - 3'600'000, best + 3'600'000}) {
    const std::int64_t d_best = best > now_utc_ms ? best - now_utc_ms : now_utc_ms - best;
    const std::int64_t d = candidate > now_utc_ms ? candidate - now_utc_ms : now_utc_ms - candidate;
    if (d < d_best)
      best = candidate;
  }
  return best;
}

/// MovementPhaseState ::= ENUMERATED, no extension marker (the contract's signal states).
enum class MovementPhaseState : std::uint8_t {
  unavailable = 0,
  dark = 1,
  stop_Then_Proceed = 2,
  stop_And_Remain = 3,
  pre_Movement = 4,
  permissive_Movement_Allowed = 5,
  protected_Movement_Allowed = 6,
  permissive_clearance = 7,
  protected_clearance = 8,
  caution_Conflicting_Traffic = 9,
};
inline constexpr unsigned kMovementPhaseStateCount = 10;
/// The ASN.1 name, e.g. "stop-And-Remain" (the contract's `event_state`).
const char* to_string(MovementPhaseState s);

/// IntersectionStatusObject ::= BIT STRING (SIZE(16)); bit n is (1 << n).
using IntersectionStatusObject = std::uint16_t;
namespace intersection_status {
inline constexpr IntersectionStatusObject kManualControlIsEnabled = 1u << 0;
inline constexpr IntersectionStatusObject kStopTimeIsActivated = 1u << 1;
inline constexpr IntersectionStatusObject kFailureFlash = 1u << 2;
inline constexpr IntersectionStatusObject kPreemptIsActive = 1u << 3;
inline constexpr IntersectionStatusObject kSignalPriorityIsActive = 1u << 4;
inline constexpr IntersectionStatusObject kFixedTimeOperation = 1u << 5;
inline constexpr IntersectionStatusObject kTrafficDependentOperation = 1u << 6;
inline constexpr IntersectionStatusObject kStandbyOperation = 1u << 7;
inline constexpr IntersectionStatusObject kFailureMode = 1u << 8;
inline constexpr IntersectionStatusObject kOff = 1u << 9;
inline constexpr IntersectionStatusObject kRecentMAPmessageUpdate = 1u << 10;
inline constexpr IntersectionStatusObject kRecentChangeInMAPassignedLanesIDsUsed = 1u << 11;
inline constexpr IntersectionStatusObject kNoValidMAPisAvailableAtThisTime = 1u << 12;
inline constexpr IntersectionStatusObject kNoValidSPATisAvailableAtThisTime = 1u << 13;
}  // namespace intersection_status

/// AllowedManeuvers ::= BIT STRING (SIZE(12)); bit n is (1 << n).
using AllowedManeuvers = std::uint16_t;
namespace allowed_maneuvers {
inline constexpr AllowedManeuvers kManeuverStraightAllowed = 1u << 0;
inline constexpr AllowedManeuvers kManeuverLeftAllowed = 1u << 1;
inline constexpr AllowedManeuvers kManeuverRightAllowed = 1u << 2;
inline constexpr AllowedManeuvers kManeuverUTurnAllowed = 1u << 3;
inline constexpr AllowedManeuvers kManeuverLeftTurnOnRedAllowed = 1u << 4;
inline constexpr AllowedManeuvers kManeuverRightTurnOnRedAllowed = 1u << 5;
inline constexpr AllowedManeuvers kManeuverLaneChangeAllowed = 1u << 6;
inline constexpr AllowedManeuvers kManeuverNoStoppingAllowed = 1u << 7;
inline constexpr AllowedManeuvers kYieldAllwaysRequired = 1u << 8;
inline constexpr AllowedManeuvers kGoWithHalt = 1u << 9;
inline constexpr AllowedManeuvers kCaution = 1u << 10;
}  // namespace allowed_maneuvers

/// LaneDirection ::= BIT STRING {ingressPath (0), egressPath (1)} (SIZE(2)).
using LaneDirection = std::uint8_t;
namespace lane_direction {
inline constexpr LaneDirection kIngressPath = 1u << 0;
inline constexpr LaneDirection kEgressPath = 1u << 1;
}  // namespace lane_direction

/// LaneSharing ::= BIT STRING (SIZE(10)).
using LaneSharing = std::uint16_t;
namespace lane_sharing {
inline constexpr LaneSharing kOverlappingLaneDescriptionProvided = 1u << 0;
inline constexpr LaneSharing kMultipleLanesTreatedAsOneLane = 1u << 1;
inline constexpr LaneSharing kOtherNonMotorizedTrafficTypes = 1u << 2;
inline constexpr LaneSharing kIndividualMotorizedVehicleTraffic = 1u << 3;
inline constexpr LaneSharing kBusVehicleTraffic = 1u << 4;
inline constexpr LaneSharing kTaxiVehicleTraffic = 1u << 5;
inline constexpr LaneSharing kPedestriansTraffic = 1u << 6;
inline constexpr LaneSharing kCyclistVehicleTraffic = 1u << 7;
inline constexpr LaneSharing kTrackedVehicleTraffic = 1u << 8;
inline constexpr LaneSharing kPedestrianTraffic = 1u << 9;
}  // namespace lane_sharing

/// DescriptiveName ::= IA5String (SIZE(1..63)).
using DescriptiveName = CharString<63>;

// ---- Frames both messages use ----------------------------------------------------------------

/// IntersectionReferenceID ::= SEQUENCE {region RoadRegulatorID OPTIONAL, id IntersectionID}.
struct IntersectionReferenceID {
  std::optional<RoadRegulatorID> region;
  IntersectionID id = 0;
  friend bool operator==(const IntersectionReferenceID&, const IntersectionReferenceID&) = default;
};

// ---- SPAT frames -----------------------------------------------------------------------------

/// TimeChangeDetails ::= SEQUENCE {startTime?, minEndTime, maxEndTime?, likelyTime?,
/// confidence?, nextTime?}, no extension marker.
struct TimeChangeDetails {
  std::optional<TimeMark> startTime;
  TimeMark minEndTime = kTimeMarkUnknown;
  std::optional<TimeMark> maxEndTime;
  std::optional<TimeMark> likelyTime;
  std::optional<TimeIntervalConfidence> confidence;
  std::optional<TimeMark> nextTime;
  friend bool operator==(const TimeChangeDetails&, const TimeChangeDetails&) = default;
};

/// AdvisorySpeedType ::= ENUMERATED {none, greenwave, ecoDrive, transit, ...}.
enum class AdvisorySpeedType : std::uint8_t { none = 0, greenwave = 1, ecoDrive = 2, transit = 3 };

/// The DSRC module's own SpeedConfidence ::= ENUMERATED {unavailable (0) .. prec0-01ms (7)}, no
/// extension marker (the copy in camsenec/mitvane comments it out; the ISO file and
/// Wireshark's SpeedConfidenceDSRC have it): not the CDD's SpeedConfidence.
enum class SpeedConfidenceDSRC : std::uint8_t {
  unavailable = 0,
  prec100ms = 1,
  prec10ms = 2,
  prec5ms = 3,
  prec1ms = 4,
  prec0_1ms = 5,
  prec0_05ms = 6,
  prec0_01ms = 7,
};

/// AdvisorySpeed ::= SEQUENCE {type, speed?, confidence?, distance?, class?, regional?, ...}.
struct AdvisorySpeed {
  AdvisorySpeedType type = AdvisorySpeedType::none;
  std::optional<SpeedAdvice> speed;
  std::optional<SpeedConfidenceDSRC> confidence;
  std::optional<ZoneLength> distance;
  std::optional<RestrictionClassID> class_;
  friend bool operator==(const AdvisorySpeed&, const AdvisorySpeed&) = default;
};
/// AdvisorySpeedList ::= SEQUENCE (SIZE(1..16)) OF AdvisorySpeed; held: up to 4.
inline constexpr std::size_t kAdvisorySpeedsMax = 4;
using AdvisorySpeedList = BoundedVector<AdvisorySpeed, kAdvisorySpeedsMax>;

/// MovementEvent ::= SEQUENCE {eventState, timing?, speeds?, regional?, ...}.
struct MovementEvent {
  MovementPhaseState eventState = MovementPhaseState::unavailable;
  std::optional<TimeChangeDetails> timing;
  std::optional<AdvisorySpeedList> speeds;
  friend bool operator==(const MovementEvent&, const MovementEvent&) = default;
};
/// MovementEventList ::= SEQUENCE (SIZE(1..16)) OF MovementEvent (the module's bound).
inline constexpr std::size_t kMovementEventsMax = 16;
using MovementEventList = BoundedVector<MovementEvent, kMovementEventsMax>;

/// ConnectionManeuverAssist ::= SEQUENCE {connectionID, queueLength?, availableStorageLength?,
/// waitOnStop?, pedBicycleDetect?, regional?, ...}.
struct ConnectionManeuverAssist {
  LaneConnectionID connectionID = 0;
  std::optional<ZoneLength> queueLength;
  std::optional<ZoneLength> availableStorageLength;
  std::optional<bool> waitOnStop;
  std::optional<bool> pedBicycleDetect;
  friend bool operator==(const ConnectionManeuverAssist&,
                         const ConnectionManeuverAssist&) = default;
};
/// ManeuverAssistList ::= SEQUENCE (SIZE(1..16)) OF ConnectionManeuverAssist (module's bound).
inline constexpr std::size_t kManeuverAssistsMax = 16;
using ManeuverAssistList = BoundedVector<ConnectionManeuverAssist, kManeuverAssistsMax>;

/// MovementState ::= SEQUENCE {movementName?, signalGroup, state-time-speed,
/// maneuverAssistList?, regional?, ...}.
struct MovementState {
  std::optional<DescriptiveName> movementName;
  SignalGroupID signalGroup = 0;
  MovementEventList state_time_speed;  ///< SIZE(1..16): at least one
  std::optional<ManeuverAssistList> maneuverAssistList;
  friend bool operator==(const MovementState&, const MovementState&) = default;
};
/// MovementList ::= SEQUENCE (SIZE(1..255)) OF MovementState; held: up to 64 signal groups.
inline constexpr std::size_t kMovementStatesMax = 64;
using MovementList = BoundedVector<MovementState, kMovementStatesMax>;

/// EnabledLaneList ::= SEQUENCE (SIZE(1..16)) OF LaneID.
using EnabledLaneList = BoundedVector<LaneID, 16>;

/// IntersectionState ::= SEQUENCE {name?, id, revision, status, moy?, timeStamp?,
/// enabledLanes?, states, maneuverAssistList?, regional?, ...}.
struct IntersectionState {
  std::optional<DescriptiveName> name;
  IntersectionReferenceID id;
  MsgCount revision = 0;
  IntersectionStatusObject status = 0;
  std::optional<MinuteOfTheYear> moy;
  std::optional<DSecond> timeStamp;
  std::optional<EnabledLaneList> enabledLanes;
  MovementList states;  ///< SIZE(1..): at least one
  std::optional<ManeuverAssistList> maneuverAssistList;
  friend bool operator==(const IntersectionState&, const IntersectionState&) = default;
};
/// IntersectionStateList ::= SEQUENCE (SIZE(1..32)) OF IntersectionState; held: up to 4.
inline constexpr std::size_t kIntersectionStatesMax = 4;
using IntersectionStateList = BoundedVector<IntersectionState, kIntersectionStatesMax>;

// ---- MapData frames --------------------------------------------------------------------------

/// LayerType ::= ENUMERATED {none, mixedContent, generalMapData, intersectionData, curveData,
/// roadwaySectionData, parkingAreaData, sharedLaneData, ...}.
enum class LayerType : std::uint8_t {
  none = 0,
  mixedContent = 1,
  generalMapData = 2,
  intersectionData = 3,
  curveData = 4,
  roadwaySectionData = 5,
  parkingAreaData = 6,
  sharedLaneData = 7,
};

/// Position3D ::= SEQUENCE {lat Latitude, long Longitude, elevation Elevation?, regional?, ...}
/// (Latitude and Longitude of the CDD, 0.1 µdeg).
struct Position3D {
  Latitude lat = 0;
  Longitude long_ = 0;
  std::optional<Elevation> elevation;
  friend bool operator==(const Position3D&, const Position3D&) = default;
};

/// SpeedLimitType ::= ENUMERATED {unknown, maxSpeedInSchoolZone, ..., vehiclesWithTrailers-
/// NightMaxSpeed (12), ...}.
enum class SpeedLimitType : std::uint8_t {
  unknown = 0,
  maxSpeedInSchoolZone = 1,
  maxSpeedInSchoolZoneWhenChildrenArePresent = 2,
  maxSpeedInConstructionZone = 3,
  vehicleMinSpeed = 4,
  vehicleMaxSpeed = 5,
  vehicleNightMaxSpeed = 6,
  truckMinSpeed = 7,
  truckMaxSpeed = 8,
  truckNightMaxSpeed = 9,
  vehiclesWithTrailersMinSpeed = 10,
  vehiclesWithTrailersMaxSpeed = 11,
  vehiclesWithTrailersNightMaxSpeed = 12,
};

/// RegulatorySpeedLimit ::= SEQUENCE {type SpeedLimitType, speed Velocity}.
struct RegulatorySpeedLimit {
  SpeedLimitType type = SpeedLimitType::unknown;
  Velocity speed = 0;
  friend bool operator==(const RegulatorySpeedLimit&, const RegulatorySpeedLimit&) = default;
};
/// SpeedLimitList ::= SEQUENCE (SIZE(1..9)) OF RegulatorySpeedLimit.
using SpeedLimitList = BoundedVector<RegulatorySpeedLimit, 9>;

/// LaneTypeAttributes ::= CHOICE {vehicle, crosswalk, bikeLane, sidewalk, median, striping,
/// trackedVehicle, parking, ...}: the alternative and its BIT STRING (SIZE(16)), except
/// LaneAttributes-Vehicle (SIZE(8, ...)), of which only the 8 root bits are held.
struct LaneTypeAttributes {
  enum class Choice : std::uint8_t {
    vehicle = 0,
    crosswalk = 1,
    bikeLane = 2,
    sidewalk = 3,
    median = 4,
    striping = 5,
    trackedVehicle = 6,
    parking = 7,
  };
  Choice choice = Choice::vehicle;
  std::uint16_t bits = 0;  ///< bit n of the alternative's BIT STRING is (1 << n)
  friend bool operator==(const LaneTypeAttributes&, const LaneTypeAttributes&) = default;
};
inline constexpr unsigned kLaneTypeAttributesCount = 8;

/// LaneAttributes ::= SEQUENCE {directionalUse LaneDirection, sharedWith LaneSharing,
/// laneType LaneTypeAttributes, regional?}, no extension marker.
struct LaneAttributes {
  LaneDirection directionalUse = 0;
  LaneSharing sharedWith = 0;
  LaneTypeAttributes laneType;
  friend bool operator==(const LaneAttributes&, const LaneAttributes&) = default;
};

/// NodeOffsetPointXY ::= CHOICE {node-XY1 Node-XY-20b .. node-XY6 Node-XY-32b, node-LatLon
/// Node-LLmD-64b, regional}: offsets in cm from the previous node (the reference point for the
/// first), x east, y north; for node-LatLon x is the longitude and y the latitude (0.1 µdeg).
/// The regional alternative is refused (kUnsupported).
struct NodeOffsetPointXY {
  enum class Choice : std::uint8_t {
    node_XY1 = 0,  ///< Offset-B10 (-512..511)
    node_XY2 = 1,  ///< Offset-B11
    node_XY3 = 2,  ///< Offset-B12
    node_XY4 = 3,  ///< Offset-B13
    node_XY5 = 4,  ///< Offset-B14
    node_XY6 = 5,  ///< Offset-B16 (-32768..32767)
    node_LatLon = 6,
  };
  Choice choice = Choice::node_XY1;
  std::int32_t x = 0;
  std::int32_t y = 0;
  friend bool operator==(const NodeOffsetPointXY&, const NodeOffsetPointXY&) = default;
};
/// The smallest node-XYn alternative that holds (@p x, @p y) cm, node-XY6 if none does (its
/// range is then checked by the encoder).
NodeOffsetPointXY node_xy(std::int32_t x, std::int32_t y);

/// NodeAttributeXY ::= ENUMERATED {reserved, stopLine, roundedCapStyleA, roundedCapStyleB,
/// mergePoint, divergePoint, downstreamStopLine, downstreamStartNode, closedToTraffic,
/// safeIsland, curbPresentAtStepOff, hydrantPresent, ...}.
enum class NodeAttributeXY : std::uint8_t {
  reserved = 0,
  stopLine = 1,
  roundedCapStyleA = 2,
  roundedCapStyleB = 3,
  mergePoint = 4,
  divergePoint = 5,
  downstreamStopLine = 6,
  downstreamStartNode = 7,
  closedToTraffic = 8,
  safeIsland = 9,
  curbPresentAtStepOff = 10,
  hydrantPresent = 11,
};
inline constexpr unsigned kNodeAttributeXYCount = 12;
/// SegmentAttributeXY ::= ENUMERATED {reserved .. unEvenPavementPresent (37), ...}: held as its
/// root index (the module's 38 names are not repeated here).
using SegmentAttributeXY = std::uint8_t;
inline constexpr unsigned kSegmentAttributeXYCount = 38;

/// NodeAttributeSetXY ::= SEQUENCE {localNode NodeAttributeXYList (SIZE(1..8))?, disabled,
/// enabled SegmentAttributeXYList (SIZE(1..8))?, data LaneDataAttributeList?, dWidth,
/// dElevation Offset-B10?, regional?, ...}. `data` is refused (kUnsupported): its speed-limit
/// lists per node would make every node large.
struct NodeAttributeSetXY {
  std::optional<BoundedVector<NodeAttributeXY, 8>> localNode;
  std::optional<BoundedVector<SegmentAttributeXY, 8>> disabled;
  std::optional<BoundedVector<SegmentAttributeXY, 8>> enabled;
  std::optional<std::int16_t> dWidth;      ///< cm (-512..511)
  std::optional<std::int16_t> dElevation;  ///< cm (-512..511)
  friend bool operator==(const NodeAttributeSetXY&, const NodeAttributeSetXY&) = default;
};

/// NodeXY ::= SEQUENCE {delta NodeOffsetPointXY, attributes NodeAttributeSetXY?, ...}.
struct NodeXY {
  NodeOffsetPointXY delta;
  std::optional<NodeAttributeSetXY> attributes;
  friend bool operator==(const NodeXY&, const NodeXY&) = default;
};
/// NodeSetXY ::= SEQUENCE (SIZE(2..63)) OF NodeXY (the module's bound).
inline constexpr std::size_t kNodesMax = 63;
using NodeSetXY = BoundedVector<NodeXY, kNodesMax>;

/// ComputedLane ::= SEQUENCE {referenceLaneId, offsetXaxis, offsetYaxis CHOICE {small
/// DrivenLineOffsetSm (-2047..2047), large DrivenLineOffsetLg (-32767..32767)}, rotateXY Angle
/// (0..28800)?, scaleXaxis, scaleYaxis Scale-B12 (-2048..2047)?, regional?, ...}.
struct DrivenLineOffset {
  bool large = false;      ///< the CHOICE: small (false) or large (true)
  std::int16_t value = 0;  ///< cm
  friend bool operator==(const DrivenLineOffset&, const DrivenLineOffset&) = default;
};
struct ComputedLane {
  LaneID referenceLaneId = 0;
  DrivenLineOffset offsetXaxis;
  DrivenLineOffset offsetYaxis;
  std::optional<std::uint16_t> rotateXY;   ///< 0.0125 degree
  std::optional<std::int16_t> scaleXaxis;  ///< 0.05 percent
  std::optional<std::int16_t> scaleYaxis;
  friend bool operator==(const ComputedLane&, const ComputedLane&) = default;
};

/// NodeListXY ::= CHOICE {nodes NodeSetXY, computed ComputedLane, ...}.
using NodeListXY = std::variant<NodeSetXY, ComputedLane>;

/// ConnectingLane ::= SEQUENCE {lane LaneID, maneuver AllowedManeuvers?}.
struct ConnectingLane {
  LaneID lane = 0;
  std::optional<AllowedManeuvers> maneuver;
  friend bool operator==(const ConnectingLane&, const ConnectingLane&) = default;
};

/// Connection ::= SEQUENCE {connectingLane, remoteIntersection?, signalGroup?, userClass?,
/// connectionID?}, no extension marker.
struct Connection {
  ConnectingLane connectingLane;
  std::optional<IntersectionReferenceID> remoteIntersection;
  std::optional<SignalGroupID> signalGroup;
  std::optional<RestrictionClassID> userClass;
  std::optional<LaneConnectionID> connectionID;
  friend bool operator==(const Connection&, const Connection&) = default;
};
/// ConnectsToList ::= SEQUENCE (SIZE(1..16)) OF Connection (the module's bound).
using ConnectsToList = BoundedVector<Connection, 16>;
/// OverlayLaneList ::= SEQUENCE (SIZE(1..5)) OF LaneID.
using OverlayLaneList = BoundedVector<LaneID, 5>;

/// GenericLane ::= SEQUENCE {laneID, name?, ingressApproach?, egressApproach?, laneAttributes,
/// maneuvers?, nodeList, connectsTo?, overlays?, regional?, ...}.
struct GenericLane {
  LaneID laneID = 0;
  std::optional<DescriptiveName> name;
  std::optional<ApproachID> ingressApproach;
  std::optional<ApproachID> egressApproach;
  LaneAttributes laneAttributes;
  std::optional<AllowedManeuvers> maneuvers;
  NodeListXY nodeList;
  std::optional<ConnectsToList> connectsTo;
  std::optional<OverlayLaneList> overlays;
  friend bool operator==(const GenericLane&, const GenericLane&) = default;
};
/// LaneList ::= SEQUENCE (SIZE(1..255)) OF GenericLane; held: up to 64 lanes.
inline constexpr std::size_t kLanesMax = 64;
using LaneList = BoundedVector<GenericLane, kLanesMax>;

/// IntersectionGeometry ::= SEQUENCE {name?, id, revision, refPoint Position3D, laneWidth?,
/// speedLimits?, laneSet, preemptPriorityData?, regional?, ...}. preemptPriorityData
/// (SignalControlZones, each nothing but a regional extension) is skipped like the regional
/// extensions.
struct IntersectionGeometry {
  std::optional<DescriptiveName> name;
  IntersectionReferenceID id;
  MsgCount revision = 0;
  Position3D refPoint;
  std::optional<LaneWidth> laneWidth;
  std::optional<SpeedLimitList> speedLimits;
  LaneList laneSet;  ///< SIZE(1..): at least one
  friend bool operator==(const IntersectionGeometry&, const IntersectionGeometry&) = default;
};
/// IntersectionGeometryList ::= SEQUENCE (SIZE(1..32)) OF IntersectionGeometry; held: up to 4.
inline constexpr std::size_t kIntersectionGeometriesMax = 4;
using IntersectionGeometryList = BoundedVector<IntersectionGeometry, kIntersectionGeometriesMax>;

/// DataParameters ::= SEQUENCE {processMethod, processAgency, lastCheckedDate, geoidUsed
/// IA5String (SIZE(1..255)) (all OPTIONAL), ...}.
struct DataParameters {
  std::optional<CharString<255>> processMethod;
  std::optional<CharString<255>> processAgency;
  std::optional<CharString<255>> lastCheckedDate;
  std::optional<CharString<255>> geoidUsed;
  friend bool operator==(const DataParameters&, const DataParameters&) = default;
};

/// RestrictionAppliesTo ::= ENUMERATED {none, equippedTransit, ..., otherUnknownDisabilities
/// (13), ...}: held as its root index.
using RestrictionAppliesTo = std::uint8_t;
inline constexpr unsigned kRestrictionAppliesToCount = 14;
/// RestrictionClassAssignment ::= SEQUENCE {id RestrictionClassID, users RestrictionUserTypeList
/// (SIZE(1..16))}; each RestrictionUserType is a CHOICE {basicType RestrictionAppliesTo,
/// regional, ...} of which basicType is held (regional is kUnsupported).
struct RestrictionClassAssignment {
  RestrictionClassID id = 0;
  BoundedVector<RestrictionAppliesTo, 16> users;
  friend bool operator==(const RestrictionClassAssignment&,
                         const RestrictionClassAssignment&) = default;
};
/// RestrictionClassList ::= SEQUENCE (SIZE(1..254)) OF RestrictionClassAssignment.
using RestrictionClassList = BoundedVector<RestrictionClassAssignment, 254>;

}  // namespace tb::its::messages
