#include "its-station/apps/signal/dsrc_convert.hpp"

#include <chrono>
#include <cmath>
#include <variant>

#include <fmt/format.h>

#include "common/geodesy/local_frame.hpp"

namespace tb::its::apps::signal {

namespace m = messages;

namespace {

constexpr double kMicroDegTenths = 1e7;  // Latitude/Longitude: 0.1 µdeg
constexpr double kVelocityUnit = 0.02;   // DE_Velocity: 0.02 m/s
constexpr m::Velocity kVelocityUnavailable = 8191;

std::optional<clock::WallTime> utc(std::optional<m::TimeMark> t, std::int64_t now_ms) {
  if (!t || *t >= m::kTimeMarkLeapSecond)
    return std::nullopt;
  return clock::WallTime{std::chrono::milliseconds{m::utc_ms_from_time_mark(*t, now_ms)}};
}

MovementEvent event_from(const m::MovementEvent& e, std::int64_t now_ms) {
  MovementEvent out;
  out.state = to_model(e.eventState);
  if (e.timing) {
    out.start_time = utc(e.timing->startTime, now_ms);
    out.min_end_time = utc(e.timing->minEndTime, now_ms);
    out.max_end_time = utc(e.timing->maxEndTime, now_ms);
    out.likely_time = utc(e.timing->likelyTime, now_ms);
  }
  return out;
}

}  // namespace

MovementPhaseState to_model(m::MovementPhaseState s) {
  return movement_phase_state(static_cast<int>(s)).value_or(MovementPhaseState::kUnavailable);
}

Expected<IntersectionTopology, TopologyError> topology_from_geometry(
    const m::IntersectionGeometry& g, clock::WallTime received_at) {
  const auto error = [&](std::string what) {
    return TopologyError{fmt::format("intersection {}: {}", g.id.id, what)};
  };
  IntersectionTopology t;
  t.intersection_id = g.id.id;
  t.revision = g.revision;
  t.ref_latitude_deg = g.refPoint.lat / kMicroDegTenths;
  t.ref_longitude_deg = g.refPoint.long_ / kMicroDegTenths;
  t.received_at = received_at;
  if (std::abs(t.ref_latitude_deg) > 90.0 || std::abs(t.ref_longitude_deg) > 180.0)
    return Unexpected{error(fmt::format("refPoint ({}, {}) 0.1 µdeg is not a position",
                                        g.refPoint.lat, g.refPoint.long_))};
  if (g.speedLimits) {
    for (const m::RegulatorySpeedLimit& l : *g.speedLimits)
      if (l.type == m::SpeedLimitType::vehicleMaxSpeed && l.speed != kVelocityUnavailable &&
          l.speed > 0)
        t.speed_limit_mps = l.speed * kVelocityUnit;
  }
  const double width_m = g.laneWidth ? *g.laneWidth / 100.0 : kDefaultLaneWidthM;
  const geodesy::LocalFrame frame({t.ref_latitude_deg, t.ref_longitude_deg, 0.0});

  for (const m::GenericLane& gl : g.laneSet) {
    GenericLane lane;
    lane.lane_id = gl.laneID;
    lane.ingress = (gl.laneAttributes.directionalUse & m::lane_direction::kIngressPath) != 0;
    lane.egress = (gl.laneAttributes.directionalUse & m::lane_direction::kEgressPath) != 0;
    lane.lane_width_m = width_m;
    const auto* nodes = std::get_if<m::NodeSetXY>(&gl.nodeList);
    if (nodes == nullptr)
      return Unexpected{error(fmt::format(
          "lane {}: nodeList is a computed lane (reference lane {}), which is not supported",
          static_cast<int>(gl.laneID),
          static_cast<int>(std::get<m::ComputedLane>(gl.nodeList).referenceLaneId)))};
    double x = 0.0;
    double y = 0.0;
    for (std::size_t i = 0; i < nodes->size(); ++i) {
      const m::NodeXY& n = (*nodes)[i];
      if (n.delta.choice == m::NodeOffsetPointXY::Choice::node_LatLon) {
        const double lat = n.delta.y / kMicroDegTenths;
        const double lon = n.delta.x / kMicroDegTenths;
        if (std::abs(lat) > 90.0 || std::abs(lon) > 180.0)
          return Unexpected{
              error(fmt::format("lane {}: node {} node-LatLon ({}, {}) is not a "
                                "position",
                                static_cast<int>(gl.laneID), i, n.delta.y, n.delta.x))};
        const geodesy::Enu e = frame.to_enu({lat, lon, 0.0});
        x = e.east;
        y = e.north;
      } else {
        x += n.delta.x / 100.0;
        y += n.delta.y / 100.0;
      }
      lane.nodes.push_back({x, y});
      if (i == 0 && n.attributes && n.attributes->dWidth)
        lane.lane_width_m = width_m + *n.attributes->dWidth / 100.0;
    }
    lane.speed_limit_mps = std::nullopt;
    if (gl.connectsTo) {
      for (const m::Connection& c : *gl.connectsTo)
        lane.connects_to.push_back({c.connectingLane.lane, c.signalGroup});
    }
    t.lanes.push_back(std::move(lane));
  }
  return t;
}

std::vector<SignalPhase> phases_from_state(const m::IntersectionState& s, clock::WallTime now,
                                           clock::WallTime received_at) {
  const std::int64_t now_ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count();
  std::vector<SignalPhase> out;
  out.reserve(s.states.size());
  for (const m::MovementState& ms : s.states) {
    if (ms.state_time_speed.empty())
      continue;
    SignalPhase p;
    p.signal_group = ms.signalGroup;
    p.received_at = received_at;
    p.current = event_from(ms.state_time_speed[0], now_ms);
    for (std::size_t i = 1; i < ms.state_time_speed.size(); ++i)
      p.upcoming.push_back(event_from(ms.state_time_speed[i], now_ms));
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace tb::its::apps::signal
