#pragma once
/// @file From the decoded DSRC frames of a MAPEM / SPATEM (its-station/messages/dsrc.hpp, ISO TS
/// 19091 / SAE J2735 names) to the signal application's model (signal_model.hpp): geometry in
/// metres around the intersection's refPoint, times as world-clock UTC.

#include <cstdint>
#include <vector>

#include "common/clock/clock.hpp"
#include "common/util/expected.hpp"
#include "its-station/apps/signal/signal_model.hpp"
#include "its-station/messages/dsrc.hpp"

namespace tb::its::apps::signal {

/// Lane width when neither the lane's first node (dWidth) nor the intersection (laneWidth)
/// gives one: J2735 leaves it open; 3.5 m is a European main-road lane (and the model's default).
inline constexpr double kDefaultLaneWidthM = 3.5;

/// IntersectionGeometry → IntersectionTopology, stamped @p received_at.
/// - refPoint (0.1 µdeg) → degrees; the local frame is east/north of it.
/// - NodeSetXY: each node-XYn offset is from the node before it, the first from the refPoint
///   (SAE J2735 DF_Node-XY-20b … DF_Node-XY-32b: "offset values from the last point in X and
///   Y"); so node positions are the running sum of the offsets, cm → m. A node-LatLon
///   (DF_Node-LLmD-64b) is an absolute position; later XY offsets continue from it.
/// - directionalUse: bit ingressPath / egressPath (DE_LaneDirection); both for a two-way lane.
/// - width: laneWidth of the intersection (DF_IntersectionGeometry), plus the first node's
///   dWidth where given (DF_NodeAttributeSetXY: a change of width from that node on), else
///   kDefaultLaneWidthM.
/// - speed limit: the intersection's SpeedLimitList vehicleMaxSpeed (Velocity 0.02 m/s); lanes
///   carry none (a node's LaneDataAttributeList is refused by the codec).
/// - connectsTo: connectingLane.lane and signalGroup; connections to another intersection's lane
///   (remoteIntersection) are kept as they come.
/// Refused (TopologyError naming the lane and field): a computed lane (ComputedLane, not
/// supported: no node list of its own here), a node list that leaves the globe.
Expected<IntersectionTopology, TopologyError> topology_from_geometry(
    const messages::IntersectionGeometry& g, clock::WallTime received_at);

/// IntersectionState → one SignalPhase per MovementState, stamped @p received_at: the first
/// MovementEvent of state-time-speed is the current one, the rest upcoming. TimeMarks become
/// UTC against @p now (the station's own ITS clock): the instant in the hour before, of or after
/// now nearest to it (messages::utc_ms_from_time_mark; ISO TS 19091 DE_TimeMark counts tenths of
/// a second from the start of the UTC hour). 36000 (leap second) and 36001 (unknown) give no
/// time.
std::vector<SignalPhase> phases_from_state(const messages::IntersectionState& s,
                                           clock::WallTime now, clock::WallTime received_at);

/// DSRC MovementPhaseState (the codec's) → the model's, value for value.
MovementPhaseState to_model(messages::MovementPhaseState s);

}  // namespace tb::its::apps::signal
