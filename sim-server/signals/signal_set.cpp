#include "sim-server/signals/signal_set.hpp"

#include <algorithm>
#include <stdexcept>

namespace tb::server {

SignalSet::SignalSet(const std::vector<scenario::SignalPlan>& plans, std::int64_t world_start_ms) {
  for (const scenario::SignalPlan& p : plans)
    controllers_.emplace_back(p, world_start_ms);
  std::sort(controllers_.begin(), controllers_.end(),
            [](const auto& a, const auto& b) { return a.intersection_id() < b.intersection_id(); });
  for (std::size_t i = 1; i < controllers_.size(); ++i) {
    if (controllers_[i].intersection_id() == controllers_[i - 1].intersection_id()) {
      throw std::invalid_argument("two signal plans for intersection " +
                                  std::to_string(controllers_[i].intersection_id()));
    }
  }
}

std::vector<wire::sim::SignalGroupState> SignalSet::step(std::int64_t world_ms) {
  std::vector<wire::sim::SignalGroupState> now;
  for (const SignalController& c : controllers_) {
    for (const GroupState& g : c.states(world_ms)) {
      const std::int64_t next = g.next_change_ms.value_or(0);
      // Fixed time: the change comes exactly then (minEndTime = likelyTime).
      now.push_back(
          {c.intersection_id(), static_cast<std::uint8_t>(g.signal_group), g.state, next, next});
    }
  }
  std::vector<wire::sim::SignalGroupState> changed;
  for (std::size_t i = 0; i < now.size(); ++i) {
    if (!stepped_ || now[i].state != latest_.groups[i].state)
      changed.push_back(now[i]);
  }
  stepped_ = true;
  latest_.world_time_ms = world_ms;
  latest_.groups = std::move(now);
  return changed;
}

}  // namespace tb::server
