#include "sim-client/driver/traffic_lights.hpp"

#include <algorithm>
#include <tuple>

namespace tb::client {

using wire::sim::MovementPhaseState;

LightAspect aspect(MovementPhaseState s) {
  switch (s) {
    case MovementPhaseState::kPermissiveMovementAllowed:
    case MovementPhaseState::kProtectedMovementAllowed:
      return LightAspect::kGo;
    case MovementPhaseState::kPermissiveClearance:
    case MovementPhaseState::kProtectedClearance:
      return LightAspect::kAmber;
    case MovementPhaseState::kStopAndRemain:
    case MovementPhaseState::kPreMovement:
      return LightAspect::kStop;
    case MovementPhaseState::kUnavailable:
    case MovementPhaseState::kDark:
    case MovementPhaseState::kStopThenProceed:
    case MovementPhaseState::kCautionConflictingTraffic:
      break;
  }
  return LightAspect::kNone;
}

void TrafficLights::update(const wire::sim::SignalStates& s) {
  world_time_ms_ = s.world_time_ms;
  groups_ = s.groups;
  // The protocol sends them ascending; a lookup must not depend on it.
  std::sort(groups_.begin(), groups_.end(), [](const auto& a, const auto& b) {
    return std::tie(a.intersection_id, a.signal_group) <
           std::tie(b.intersection_id, b.signal_group);
  });
}

std::int64_t TrafficLights::world_ms(std::int64_t sim_time_ns) const {
  return (world_start_ns_ + sim_time_ns) / 1'000'000;
}

std::optional<wire::sim::SignalGroupState> TrafficLights::find(std::uint16_t intersection_id,
                                                               int signal_group,
                                                               std::int64_t sim_time_ns) const {
  if (groups_.empty() || world_ms(sim_time_ns) - world_time_ms_ > kMaxAgeMs)
    return std::nullopt;
  const auto key = std::make_tuple(intersection_id, signal_group);
  const auto it = std::lower_bound(groups_.begin(), groups_.end(), key, [](const auto& g, auto k) {
    return std::make_tuple(g.intersection_id, static_cast<int>(g.signal_group)) < k;
  });
  if (it == groups_.end() || it->intersection_id != intersection_id ||
      it->signal_group != signal_group)
    return std::nullopt;
  return *it;
}

LightAspect TrafficLights::aspect_of(std::uint16_t intersection_id, int signal_group,
                                     std::int64_t sim_time_ns) const {
  const auto g = find(intersection_id, signal_group, sim_time_ns);
  return g ? aspect(g->state) : LightAspect::kNone;
}

}  // namespace tb::client
