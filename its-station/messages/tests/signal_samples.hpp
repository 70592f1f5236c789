#pragma once
/// @file Sample SPATEMs and MAPEMs shared by the unit tests, the tshark interoperability test,
/// the fuzz seed writer and the benchmarks. The large ones are built on the heap (sizeof(Spatem)
/// is about half a megabyte).

#include <memory>
#include <string>

#include "its-station/messages/mapem.hpp"
#include "its-station/messages/spatem.hpp"

namespace tb::its::messages::samples {

/// The worked example of signal_golden_test.cpp: one intersection, two signal groups with
/// timing (green until 123.4 s past the hour at the latest 130.0 s, red until 126.4 s, likely
/// 127.0 s).
inline std::unique_ptr<Spatem> spatem_two_groups() {
  auto m = std::make_unique<Spatem>();
  m->header.stationID = 1001;
  IntersectionState& is = m->spat.intersections.emplace_back();
  is.id.id = 34;
  is.revision = 1;
  is.status = intersection_status::kFixedTimeOperation;
  is.moy = 475200;  // 11 Nov, 00:00
  is.timeStamp = 12345;
  MovementState& g1 = is.states.emplace_back();
  g1.signalGroup = 1;
  MovementEvent& e1 = g1.state_time_speed.emplace_back();
  e1.eventState = MovementPhaseState::protected_Movement_Allowed;
  e1.timing.emplace();
  e1.timing->minEndTime = 1234;
  e1.timing->maxEndTime = 1300;
  MovementState& g2 = is.states.emplace_back();
  g2.signalGroup = 2;
  MovementEvent& e2 = g2.state_time_speed.emplace_back();
  e2.eventState = MovementPhaseState::stop_And_Remain;
  e2.timing.emplace();
  e2.timing->minEndTime = 1264;
  e2.timing->likelyTime = 1270;
  e2.timing->confidence = 15;
  return m;
}

/// What the testbed's RSU sends for a four-way junction: one intersection, @p groups signal
/// groups (1..n) each with the current phase and the next one, every time filled in.
inline std::unique_ptr<Spatem> spatem_typical(unsigned groups = 8) {
  auto m = std::make_unique<Spatem>();
  m->header.stationID = 90001;
  m->spat.timeStamp = 475200 + 12 * 60 + 5;
  IntersectionState& is = m->spat.intersections.emplace_back();
  is.id.id = 1;
  is.revision = 3;
  is.status = intersection_status::kFixedTimeOperation;
  is.moy = 475200 + 12 * 60 + 5;
  is.timeStamp = 41250;
  static constexpr MovementPhaseState kCycle[] = {
      MovementPhaseState::stop_And_Remain, MovementPhaseState::pre_Movement,
      MovementPhaseState::protected_Movement_Allowed, MovementPhaseState::protected_clearance};
  for (unsigned g = 0; g < groups; ++g) {
    MovementState& s = is.states.emplace_back();
    s.signalGroup = static_cast<SignalGroupID>(g + 1);
    for (unsigned k = 0; k < 2; ++k) {
      MovementEvent& e = s.state_time_speed.emplace_back();
      e.eventState = kCycle[(g + k) % 4];
      TimeChangeDetails& t = e.timing.emplace();
      t.startTime = static_cast<TimeMark>(7000 + 100 * g + 300 * k);
      t.minEndTime = static_cast<TimeMark>(7300 + 100 * g + 300 * k);
      t.maxEndTime = static_cast<TimeMark>(7400 + 100 * g + 300 * k);
      t.likelyTime = static_cast<TimeMark>(7300 + 100 * g + 300 * k);
      t.confidence = 15;
    }
  }
  return m;
}

/// Every optional component present and every list at the bound held here (or at @p upper
/// false: every value at its lower bound, lists of one).
inline std::unique_ptr<Spatem> spatem_at_bounds(bool upper) {
  auto m = std::make_unique<Spatem>();
  m->header.stationID = upper ? 4294967295u : 0;
  SPAT& s = m->spat;
  s.timeStamp = upper ? 527040 : 0;
  s.name = char_string<63>(upper ? std::string(63, '~').c_str() : "\x01");
  const std::size_t intersections = upper ? kIntersectionStatesMax : 1;
  const std::size_t states = upper ? kMovementStatesMax : 1;
  const std::size_t events = upper ? kMovementEventsMax : 1;
  const std::size_t speeds = upper ? kAdvisorySpeedsMax : 1;
  const std::size_t assists = upper ? kManeuverAssistsMax : 1;
  const TimeMark t = upper ? kTimeMarkMax : 0;
  ConnectionManeuverAssist cma;
  cma.connectionID = upper ? 255 : 0;
  cma.queueLength = upper ? 10000 : 0;
  cma.availableStorageLength = upper ? 10000 : 0;
  cma.waitOnStop = upper;
  cma.pedBicycleDetect = !upper;
  ManeuverAssistList assist;
  for (std::size_t i = 0; i < assists; ++i)
    assist.push_back(cma);
  AdvisorySpeed a;
  a.type = upper ? AdvisorySpeedType::transit : AdvisorySpeedType::none;
  a.speed = upper ? 500 : 0;
  a.confidence = upper ? SpeedConfidenceDSRC::prec0_01ms : SpeedConfidenceDSRC::unavailable;
  a.distance = upper ? 10000 : 0;
  a.class_ = upper ? 255 : 0;
  for (std::size_t i = 0; i < intersections; ++i) {
    IntersectionState& is = s.intersections.emplace_back();
    is.name = s.name;
    is.id.region = upper ? 65535 : 0;
    is.id.id = static_cast<IntersectionID>(upper ? 65535 - i : i);
    is.revision = upper ? 127 : 0;
    is.status = upper ? 0xFFFF : 0;
    is.moy = upper ? 527040 : 0;
    is.timeStamp = upper ? 65535 : 0;
    is.enabledLanes.emplace();
    for (std::size_t l = 0; l < (upper ? 16u : 1u); ++l)
      is.enabledLanes->push_back(static_cast<LaneID>(upper ? 255 - l : l));
    is.maneuverAssistList = assist;
    for (std::size_t g = 0; g < states; ++g) {
      MovementState& ms = is.states.emplace_back();
      ms.movementName = char_string<63>(upper ? "protected left turn" : "x");
      ms.signalGroup = static_cast<SignalGroupID>(upper ? 255 - g : g);
      ms.maneuverAssistList = assist;
      for (std::size_t e = 0; e < events; ++e) {
        MovementEvent& ev = ms.state_time_speed.emplace_back();
        ev.eventState = upper ? MovementPhaseState::caution_Conflicting_Traffic
                              : MovementPhaseState::unavailable;
        ev.timing = TimeChangeDetails{t, t, t, t, upper ? 15 : 0, t};
        ev.speeds.emplace();
        for (std::size_t k = 0; k < speeds; ++k)
          ev.speeds->push_back(a);
      }
    }
  }
  return m;
}

/// The worked example of mapem_test.cpp: one intersection with one ingress lane of three nodes
/// (the first, at the stop line, 12 m south of the reference point) and two connections.
inline std::unique_ptr<Mapem> mapem_one_lane() {
  auto m = std::make_unique<Mapem>();
  m->header.stationID = 1001;
  m->map.msgIssueRevision = 1;
  IntersectionGeometry& g = m->map.intersections.emplace().emplace_back();
  g.id.id = 34;
  g.revision = 1;
  g.refPoint.lat = 410255000;
  g.refPoint.long_ = 289742000;
  g.laneWidth = 350;
  GenericLane& l = g.laneSet.emplace_back();
  l.laneID = 1;
  l.ingressApproach = 1;
  l.laneAttributes.directionalUse = lane_direction::kIngressPath;
  l.maneuvers =
      allowed_maneuvers::kManeuverStraightAllowed | allowed_maneuvers::kManeuverRightAllowed;
  NodeSetXY& nodes = l.nodeList.emplace<NodeSetXY>();
  NodeXY& stop = nodes.emplace_back();
  stop.delta = node_xy(-175, -1200);  // node-XY3: -1200 needs Offset-B12
  stop.attributes.emplace().localNode.emplace().push_back(NodeAttributeXY::stopLine);
  nodes.emplace_back().delta = node_xy(0, -1000);  // node-XY2
  nodes.emplace_back().delta = node_xy(0, -500);   // node-XY1
  ConnectsToList& c = l.connectsTo.emplace();
  Connection& straight = c.emplace_back();
  straight.connectingLane = {5, allowed_maneuvers::kManeuverStraightAllowed};
  straight.signalGroup = 2;
  Connection& right = c.emplace_back();
  right.connectingLane = {7, allowed_maneuvers::kManeuverRightAllowed};
  right.signalGroup = 3;
  return m;
}

/// What the testbed's RSU sends for a four-way junction: 4 arms, each with 2 ingress lanes
/// (5 nodes, then 4 when curved: 6) and 1 egress lane (4 nodes); each ingress lane connects
/// straight on and turning, with the signal group of its arm.
inline std::unique_ptr<Mapem> mapem_typical() {
  auto m = std::make_unique<Mapem>();
  m->header.stationID = 90001;
  m->map.timeStamp = 475200 + 12 * 60;
  m->map.msgIssueRevision = 3;
  IntersectionGeometry& g = m->map.intersections.emplace().emplace_back();
  g.id.id = 1;
  g.revision = 3;
  g.refPoint = {410255000, 289742000, 400};
  g.laneWidth = 350;
  g.speedLimits.emplace().push_back({SpeedLimitType::vehicleMaxSpeed, 694});  // 50 km/h
  for (int arm = 0; arm < 4; ++arm) {
    for (int k = 0; k < 3; ++k) {
      const bool ingress = k < 2;
      GenericLane& l = g.laneSet.emplace_back();
      l.laneID = static_cast<LaneID>(1 + arm * 3 + k);
      if (ingress)
        l.ingressApproach = static_cast<ApproachID>(arm + 1);
      else
        l.egressApproach = static_cast<ApproachID>(arm + 1);
      l.laneAttributes.directionalUse =
          ingress ? lane_direction::kIngressPath : lane_direction::kEgressPath;
      l.laneAttributes.sharedWith = lane_sharing::kIndividualMotorizedVehicleTraffic;
      NodeSetXY& nodes = l.nodeList.emplace<NodeSetXY>();
      const int n = ingress ? 5 + k : 4;
      // The arm's direction: +x, +y, -x, -y; lanes 3.5 m apart across it.
      const int dx = arm == 0 ? 1 : arm == 2 ? -1 : 0;
      const int dy = arm == 1 ? 1 : arm == 3 ? -1 : 0;
      const int across = (ingress ? -175 - 350 * k : 175);
      for (int i = 0; i < n; ++i) {
        NodeXY& node = nodes.emplace_back();
        if (i == 0) {
          node.delta = node_xy(dx * 1500 - dy * across, dy * 1500 + dx * across);
          if (ingress)
            node.attributes.emplace().localNode.emplace().push_back(NodeAttributeXY::stopLine);
        } else {
          node.delta =
              node_xy(dx * (1000 + 37 * i) + dy * 11 * i, dy * (1000 + 37 * i) - dx * 11 * i);
        }
      }
      if (ingress) {
        l.maneuvers = k == 0 ? allowed_maneuvers::kManeuverStraightAllowed |
                                   allowed_maneuvers::kManeuverLeftAllowed
                             : allowed_maneuvers::kManeuverStraightAllowed |
                                   allowed_maneuvers::kManeuverRightAllowed;
        ConnectsToList& c = l.connectsTo.emplace();
        Connection& s = c.emplace_back();
        s.connectingLane = {static_cast<LaneID>(1 + ((arm + 2) % 4) * 3 + 2),
                            allowed_maneuvers::kManeuverStraightAllowed};
        s.signalGroup = static_cast<SignalGroupID>(1 + arm % 2 * 2);
        Connection& t = c.emplace_back();
        t.connectingLane = {static_cast<LaneID>(1 + ((arm + (k == 0 ? 1 : 3)) % 4) * 3 + 2),
                            k == 0 ? allowed_maneuvers::kManeuverLeftAllowed
                                   : allowed_maneuvers::kManeuverRightAllowed};
        t.signalGroup = static_cast<SignalGroupID>(1 + arm % 2 * 2 + (k == 0 ? 1 : 0));
        t.connectionID = static_cast<LaneConnectionID>(arm * 2 + k);
      }
    }
  }
  return m;
}

/// Every optional component present and every list at the bound held here (@p upper), or
/// every value at its lower bound and lists at their smallest.
inline std::unique_ptr<Mapem> mapem_at_bounds(bool upper) {
  auto m = std::make_unique<Mapem>();
  m->header.stationID = upper ? 4294967295u : 0;
  MapData& d = m->map;
  d.timeStamp = upper ? 527040 : 0;
  d.msgIssueRevision = upper ? 127 : 0;
  d.layerType = upper ? LayerType::sharedLaneData : LayerType::none;
  d.layerID = upper ? 100 : 0;
  const std::string long_text(255, upper ? '~' : ' ');
  d.dataParameters = DataParameters{char_string<255>(upper ? long_text.c_str() : "a"),
                                    char_string<255>(upper ? long_text.c_str() : "b"),
                                    char_string<255>(upper ? long_text.c_str() : "c"),
                                    char_string<255>(upper ? long_text.c_str() : "d")};
  RestrictionClassList& rl = d.restrictionList.emplace();
  for (std::size_t i = 0; i < (upper ? 254u : 1u); ++i) {
    RestrictionClassAssignment& a = rl.emplace_back();
    a.id = static_cast<RestrictionClassID>(upper ? 255 - i : i);
    for (std::size_t k = 0; k < (upper ? 16u : 1u); ++k)
      a.users.push_back(static_cast<RestrictionAppliesTo>(upper ? 13 - k % 14 : 0));
  }
  const DescriptiveName name = char_string<63>(upper ? std::string(63, 'Z').c_str() : "\x7F");
  NodeAttributeSetXY attrs;
  attrs.localNode.emplace();
  attrs.disabled.emplace();
  attrs.enabled.emplace();
  for (std::size_t k = 0; k < (upper ? 8u : 1u); ++k) {
    attrs.localNode->push_back(upper ? NodeAttributeXY::hydrantPresent : NodeAttributeXY::reserved);
    attrs.disabled->push_back(static_cast<SegmentAttributeXY>(upper ? 37 : 0));
    attrs.enabled->push_back(static_cast<SegmentAttributeXY>(upper ? 36 - k : k));
  }
  attrs.dWidth = upper ? 511 : -512;
  attrs.dElevation = upper ? 511 : -512;
  Connection conn;
  conn.connectingLane = {static_cast<LaneID>(upper ? 255 : 0),
                         static_cast<AllowedManeuvers>(upper ? 0xFFF : 0)};
  conn.remoteIntersection = IntersectionReferenceID{static_cast<RoadRegulatorID>(upper ? 65535 : 0),
                                                    static_cast<IntersectionID>(upper ? 65535 : 0)};
  conn.signalGroup = upper ? 255 : 0;
  conn.userClass = upper ? 255 : 0;
  conn.connectionID = upper ? 255 : 0;
  using C = NodeOffsetPointXY::Choice;
  d.intersections.emplace();
  for (std::size_t i = 0; i < (upper ? kIntersectionGeometriesMax : 1u); ++i) {
    IntersectionGeometry& g = d.intersections->emplace_back();
    g.name = name;
    g.id = {upper ? 65535 : 0, static_cast<IntersectionID>(upper ? 65535 - i : i)};
    g.revision = upper ? 127 : 0;
    g.refPoint = {upper ? 900000001 : -900000000, upper ? 1800000001 : -1800000000,
                  upper ? 61439 : -4096};
    g.laneWidth = upper ? 32767 : 0;
    SpeedLimitList& sl = g.speedLimits.emplace();
    for (std::size_t k = 0; k < (upper ? 9u : 1u); ++k)
      sl.push_back(
          {upper ? SpeedLimitType::vehiclesWithTrailersNightMaxSpeed : SpeedLimitType::unknown,
           static_cast<Velocity>(upper ? 8191 : 0)});
    for (std::size_t li = 0; li < (upper ? kLanesMax : 2u); ++li) {
      GenericLane& l = g.laneSet.emplace_back();
      l.laneID = static_cast<LaneID>(upper ? 255 - li : li);
      l.name = name;
      l.ingressApproach = upper ? 15 : 0;
      l.egressApproach = upper ? 15 : 0;
      l.laneAttributes.directionalUse = upper ? 3 : 0;
      l.laneAttributes.sharedWith = upper ? 0x3FF : 0;
      // Every LaneTypeAttributes alternative, each at its widest.
      l.laneAttributes.laneType.choice = static_cast<LaneTypeAttributes::Choice>(li % 8);
      l.laneAttributes.laneType.bits = upper ? (li % 8 == 0 ? 0xFF : 0xFFFF) : 0;
      l.maneuvers = upper ? 0xFFF : 0;
      if (li == 1) {
        // The other NodeListXY alternative.
        ComputedLane& cl = l.nodeList.emplace<ComputedLane>();
        cl.referenceLaneId = upper ? 255 : 0;
        cl.offsetXaxis = {upper, static_cast<std::int16_t>(upper ? 32767 : -2047)};
        cl.offsetYaxis = {!upper, static_cast<std::int16_t>(upper ? 2047 : -32767)};
        cl.rotateXY = upper ? 28800 : 0;
        cl.scaleXaxis = upper ? 2047 : -2048;
        cl.scaleYaxis = upper ? 2047 : -2048;
      } else {
        NodeSetXY& nodes = l.nodeList.emplace<NodeSetXY>();
        for (std::size_t k = 0; k < (upper ? kNodesMax : 2u); ++k) {
          NodeXY& n = nodes.emplace_back();
          const auto choice = static_cast<C>(k % 7);
          if (choice == C::node_LatLon) {
            n.delta = {choice, upper ? 1800000001 : -1800000000, upper ? 900000001 : -900000000};
          } else {
            static constexpr int kBits[] = {10, 11, 12, 13, 14, 16};
            const int b = kBits[k % 7];
            const std::int32_t v = upper ? (1 << (b - 1)) - 1 : -(1 << (b - 1));
            n.delta = {choice, v, v};
          }
          n.attributes = attrs;
        }
      }
      ConnectsToList& c = l.connectsTo.emplace();
      for (std::size_t k = 0; k < (upper ? 16u : 1u); ++k)
        c.push_back(conn);
      OverlayLaneList& o = l.overlays.emplace();
      for (std::size_t k = 0; k < (upper ? 5u : 1u); ++k)
        o.push_back(static_cast<LaneID>(upper ? 255 : 0));
    }
  }
  return m;
}

/// Every optional component of samples::spatem_at_bounds(true), with lists of two: a frame's worth
/// (the tshark test, fuzz seeds).
inline std::unique_ptr<Spatem> spatem_every_optional() {
  auto m = samples::spatem_at_bounds(true);
  m->spat.intersections.resize_down(1);
  IntersectionState& is = m->spat.intersections[0];
  is.states.resize_down(2);
  is.maneuverAssistList->resize_down(2);
  is.enabledLanes->resize_down(2);
  for (MovementState& s : is.states) {
    s.state_time_speed.resize_down(2);
    s.maneuverAssistList->resize_down(2);
    for (MovementEvent& ev : s.state_time_speed)
      ev.speeds->resize_down(2);
  }
  return m;
}

/// Every optional component of samples::mapem_at_bounds(true) and every alternative (lane
/// types, node offsets, computed lanes), with short lists: a frame's worth
/// (the tshark test, fuzz seeds).
inline std::unique_ptr<Mapem> mapem_every_optional() {
  auto m = samples::mapem_at_bounds(true);
  m->map.intersections->resize_down(1);
  m->map.restrictionList->resize_down(2);
  for (RestrictionClassAssignment& a : *m->map.restrictionList)
    a.users.resize_down(2);
  IntersectionGeometry& g = (*m->map.intersections)[0];
  g.laneSet.resize_down(8);
  for (GenericLane& l : g.laneSet) {
    if (auto* nodes = std::get_if<NodeSetXY>(&l.nodeList))
      nodes->resize_down(7);
    l.connectsTo->resize_down(2);
  }
  return m;
}

}  // namespace tb::its::messages::samples
