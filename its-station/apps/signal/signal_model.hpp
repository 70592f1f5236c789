#pragma once
/// @file The vehicle's model of a signalised intersection, filled from decoded MAPEM/SPATEM
/// (TS 103 301; payloads ISO TS 19091 MapData and SPAT, DSRC names) by the station's wiring.
///
/// Geometry is metric in a local east/north frame around the intersection's reference point
/// (MapData `refPoint`; node offsets in cm become metres). Times are world-clock UTC
/// (docs/time.md): only the SPATEM codec converts TimeMarks.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/clock/clock.hpp"

namespace tb::its::apps::signal {

/// DSRC MovementPhaseState (ISO TS 19091 / SAE J2735), values as on the air.
enum class MovementPhaseState : std::uint8_t {
  kUnavailable = 0,
  kDark = 1,
  kStopThenProceed = 2,
  kStopAndRemain = 3,
  kPreMovement = 4,
  kPermissiveMovementAllowed = 5,
  kProtectedMovementAllowed = 6,
  kPermissiveClearance = 7,
  kProtectedClearance = 8,
  kCautionConflictingTraffic = 9,
};
/// The ASN.1 identifier, e.g. "stop-And-Remain".
std::string_view dsrc_name(MovementPhaseState s);
/// What the head shows, as the MQTT `signal` message names it: "red", "red_amber", "amber",
/// "green", "dark", "unavailable". stop-Then-Proceed (flashing red) is "red",
/// caution-Conflicting-Traffic (flashing amber) "amber".
std::string_view light_name(MovementPhaseState s);
/// Values outside 0..9 are not a MovementPhaseState.
std::optional<MovementPhaseState> movement_phase_state(int value);

/// What a phase asks of a driver at the stop line.
enum class Aspect {
  kStop,       ///< stop-Then-Proceed, stop-And-Remain, pre-Movement (red, red+amber)
  kClearance,  ///< permissive/protected-clearance (amber): stop if you can
  kGo,         ///< permissive/protected-Movement-Allowed (green)
  kCaution,    ///< caution-Conflicting-Traffic (flashing amber): no stop obligation
  kUnknown,    ///< unavailable, dark
};
Aspect aspect(MovementPhaseState s);

/// A point in the intersection's local frame, metres east/north of the reference point.
struct LocalPoint {
  double x = 0.0;
  double y = 0.0;
};

/// A manoeuvre from an ingress lane (DSRC Connection): the lane it leads to and the signal
/// group that governs it.
struct Connection {
  std::uint8_t connecting_lane = 0;          ///< ConnectingLane.lane (egress LaneID)
  std::optional<std::uint8_t> signal_group;  ///< SignalGroupID 1..254; none: unsignalised
};

/// DSRC GenericLane, the parts the vehicle's application uses.
struct GenericLane {
  std::uint8_t lane_id = 0;  ///< LaneID, unique within the intersection
  /// LaneDirection (laneAttributes.directionalUse) bits ingressPath / egressPath.
  bool ingress = false;
  bool egress = false;
  double lane_width_m = 3.5;  ///< laneWidth (the intersection's default when the lane has none)
  /// Centre line, metres in the local frame. For ingress lanes the first node is at the stop
  /// bar and the nodes go upstream (ISO TS 19091 NodeListXY: "the first node is at the stop
  /// line"), so travel towards the stop line runs from the last node to the first.
  std::vector<LocalPoint> nodes;
  std::optional<double> speed_limit_mps;  ///< a lane SpeedLimitList vehicleMaxSpeed, if any
  std::vector<Connection> connects_to;
};

/// DSRC IntersectionGeometry from a MAPEM.
struct IntersectionTopology {
  std::uint16_t intersection_id = 0;  ///< IntersectionReferenceID.id
  std::uint8_t revision = 0;          ///< MsgCount: a different revision replaces the geometry
  double ref_latitude_deg = 0.0;      ///< refPoint
  double ref_longitude_deg = 0.0;
  std::optional<double> speed_limit_mps;  ///< the intersection's SpeedLimitList, if any
  std::vector<GenericLane> lanes;
  clock::WallTime received_at{};

  const GenericLane* lane(std::uint8_t lane_id) const;
};

/// Why a topology cannot be used; names the lane and the field.
struct TopologyError {
  std::string message;
};
/// Checks what the matcher relies on: unique lane ids, positive widths, ≥ 2 distinct nodes per
/// ingress lane, finite coordinates, signal groups 1..254 (255 is reserved, 0 unknown).
std::optional<TopologyError> validate(const IntersectionTopology& t);

/// One entry of a MovementState's state-time-speed list (DSRC MovementEvent): a state and its
/// TimeChangeDetails, converted to world-clock UTC.
struct MovementEvent {
  MovementPhaseState state = MovementPhaseState::kUnavailable;
  std::optional<clock::WallTime> start_time;    ///< when the state began (or begins)
  std::optional<clock::WallTime> min_end_time;  ///< earliest end
  std::optional<clock::WallTime> max_end_time;  ///< latest end
  std::optional<clock::WallTime> likely_time;   ///< most likely end
};

/// A signal group's state from a SPATEM: the current event and, where the SPAT lists them,
/// the events that follow.
struct SignalPhase {
  std::uint8_t signal_group = 0;
  MovementEvent current;
  std::vector<MovementEvent> upcoming;
  clock::WallTime received_at{};
};

}  // namespace tb::its::apps::signal
