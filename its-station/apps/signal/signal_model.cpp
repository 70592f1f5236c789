#include "its-station/apps/signal/signal_model.hpp"

#include <cmath>
#include <set>

#include <fmt/format.h>

#include "its-station/messages/dsrc.hpp"

namespace tb::its::apps::signal {

std::string_view dsrc_name(MovementPhaseState s) {
  // The same values as on the air: the codec's names.
  const auto v = static_cast<unsigned>(s);
  if (v >= messages::kMovementPhaseStateCount)
    return "unavailable";
  return messages::to_string(static_cast<messages::MovementPhaseState>(v));
}

std::string_view light_name(MovementPhaseState s) {
  switch (s) {
    case MovementPhaseState::kUnavailable:
      return "unavailable";
    case MovementPhaseState::kDark:
      return "dark";
    case MovementPhaseState::kStopThenProceed:
    case MovementPhaseState::kStopAndRemain:
      return "red";
    case MovementPhaseState::kPreMovement:
      return "red_amber";
    case MovementPhaseState::kPermissiveMovementAllowed:
    case MovementPhaseState::kProtectedMovementAllowed:
      return "green";
    case MovementPhaseState::kPermissiveClearance:
    case MovementPhaseState::kProtectedClearance:
    case MovementPhaseState::kCautionConflictingTraffic:
      return "amber";
  }
  return "unavailable";
}

std::optional<MovementPhaseState> movement_phase_state(int value) {
  if (value < 0 || value > 9) {
    return std::nullopt;
  }
  return static_cast<MovementPhaseState>(value);
}

Aspect aspect(MovementPhaseState s) {
  switch (s) {
    case MovementPhaseState::kStopThenProceed:
    case MovementPhaseState::kStopAndRemain:
    case MovementPhaseState::kPreMovement:
      return Aspect::kStop;
    case MovementPhaseState::kPermissiveClearance:
    case MovementPhaseState::kProtectedClearance:
      return Aspect::kClearance;
    case MovementPhaseState::kPermissiveMovementAllowed:
    case MovementPhaseState::kProtectedMovementAllowed:
      return Aspect::kGo;
    case MovementPhaseState::kCautionConflictingTraffic:
      return Aspect::kCaution;
    case MovementPhaseState::kUnavailable:
    case MovementPhaseState::kDark:
      return Aspect::kUnknown;
  }
  return Aspect::kUnknown;
}

const GenericLane* IntersectionTopology::lane(std::uint8_t lane_id) const {
  for (const GenericLane& l : lanes) {
    if (l.lane_id == lane_id) {
      return &l;
    }
  }
  return nullptr;
}

std::optional<TopologyError> validate(const IntersectionTopology& t) {
  auto error = [&](std::string what) {
    return TopologyError{fmt::format("intersection {}: {}", t.intersection_id, what)};
  };
  if (!std::isfinite(t.ref_latitude_deg) || std::abs(t.ref_latitude_deg) > 90.0 ||
      !std::isfinite(t.ref_longitude_deg) || std::abs(t.ref_longitude_deg) > 180.0) {
    return error(fmt::format("refPoint ({}, {}) is not a position", t.ref_latitude_deg,
                             t.ref_longitude_deg));
  }
  if (t.speed_limit_mps && !(*t.speed_limit_mps > 0.0)) {
    return error(fmt::format("speedLimits {} m/s is not positive", *t.speed_limit_mps));
  }
  std::set<std::uint8_t> ids;
  for (const GenericLane& l : t.lanes) {
    const int id = l.lane_id;
    if (!ids.insert(l.lane_id).second) {
      return error(fmt::format("laneID {} appears twice", id));
    }
    if (!(l.lane_width_m > 0.0) || !std::isfinite(l.lane_width_m)) {
      return error(fmt::format("lane {}: laneWidth {} m is not positive", id, l.lane_width_m));
    }
    if (l.speed_limit_mps && !(*l.speed_limit_mps > 0.0)) {
      return error(
          fmt::format("lane {}: speedLimits {} m/s is not positive", id, *l.speed_limit_mps));
    }
    for (std::size_t i = 0; i < l.nodes.size(); ++i) {
      if (!std::isfinite(l.nodes[i].x) || !std::isfinite(l.nodes[i].y)) {
        return error(fmt::format("lane {}: node {} is not finite", id, i));
      }
    }
    if (l.ingress) {
      double length = 0.0;
      for (std::size_t i = 1; i < l.nodes.size(); ++i) {
        length += std::hypot(l.nodes[i].x - l.nodes[i - 1].x, l.nodes[i].y - l.nodes[i - 1].y);
      }
      if (l.nodes.size() < 2 || !(length > 0.0)) {
        return error(fmt::format("lane {}: an ingress lane needs two distinct nodes, has {}", id,
                                 l.nodes.size()));
      }
    }
    for (const Connection& c : l.connects_to) {
      if (c.signal_group && (*c.signal_group == 0 || *c.signal_group == 255)) {
        return error(fmt::format("lane {}: connection to lane {} has signalGroup {} (1..254)", id,
                                 static_cast<int>(c.connecting_lane),
                                 static_cast<int>(*c.signal_group)));
      }
    }
  }
  return std::nullopt;
}

}  // namespace tb::its::apps::signal
