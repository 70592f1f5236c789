#include "sim-server/signals/signal_controller.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tb::server {

namespace {

std::int64_t to_ms(double s) {
  return std::llround(s * 1000.0);
}

bool has(const std::vector<int>& ids, int id) {
  return std::find(ids.begin(), ids.end(), id) != ids.end();
}

}  // namespace

SignalController::SignalController(const scenario::SignalPlan& plan, std::int64_t world_start_ms) {
  if (plan.phases.empty())
    throw std::invalid_argument("signal plan for junction " + plan.junction + " has no phases");
  const bool decimal = !plan.junction.empty() && plan.junction.size() <= 5 &&
                       std::all_of(plan.junction.begin(), plan.junction.end(),
                                   [](char c) { return c >= '0' && c <= '9'; }) &&
                       std::stol(plan.junction) <= 65535;
  if (!decimal)
    throw std::invalid_argument("junction id " + plan.junction + " is not an IntersectionID");
  intersection_id_ = static_cast<std::uint16_t>(std::stol(plan.junction));
  groups_ = plan.groups;
  for (const scenario::SignalPhase& p : plan.phases)
    for (int g : p.green)
      if (!has(groups_, g))
        groups_.push_back(g);
  std::sort(groups_.begin(), groups_.end());

  // The cycle as stretches of constant state: each phase's green, then the change to the next
  // phase — amber for the groups losing green, all-red, red+amber for those gaining it; a
  // group green in both phases stays green through the change.
  std::int64_t at = 0;
  auto add = [&](std::int64_t length, auto state_of) {
    if (length <= 0)
      return;
    Interval iv{at, {}};
    for (int g : groups_)
      iv.states.push_back(state_of(g));
    intervals_.push_back(std::move(iv));
    at += length;
  };
  for (std::size_t i = 0; i < plan.phases.size(); ++i) {
    const auto& now = plan.phases[i].green;
    const auto& next = plan.phases[(i + 1) % plan.phases.size()].green;
    auto green_or = [&](MovementPhaseState other) {
      return [&, other](int g) {
        return has(now, g) && has(next, g) ? MovementPhaseState::kProtectedMovementAllowed : other;
      };
    };
    add(to_ms(plan.phases[i].duration_s), [&](int g) {
      return has(now, g) ? MovementPhaseState::kProtectedMovementAllowed
                         : MovementPhaseState::kStopAndRemain;
    });
    add(to_ms(plan.amber_s), [&](int g) {
      if (has(now, g) && !has(next, g))
        return MovementPhaseState::kProtectedClearance;
      return green_or(MovementPhaseState::kStopAndRemain)(g);
    });
    add(to_ms(plan.all_red_s), green_or(MovementPhaseState::kStopAndRemain));
    add(to_ms(plan.red_amber_s), [&](int g) {
      if (!has(now, g) && has(next, g))
        return MovementPhaseState::kPreMovement;
      return green_or(MovementPhaseState::kStopAndRemain)(g);
    });
  }
  cycle_ms_ = at;
  if (cycle_ms_ <= 0)
    throw std::invalid_argument("signal plan for junction " + plan.junction + " has no length");
  origin_ms_ = world_start_ms + to_ms(plan.offset_s);
}

std::size_t SignalController::interval_at(std::int64_t pos_ms) const {
  const auto it =
      std::upper_bound(intervals_.begin(), intervals_.end(), pos_ms,
                       [](std::int64_t p, const Interval& iv) { return p < iv.start_ms; });
  return static_cast<std::size_t>(it - intervals_.begin()) - 1;
}

std::vector<GroupState> SignalController::states(std::int64_t now_ms) const {
  // Position in the cycle; before the origin (the warm-up, a positive offset) too.
  std::int64_t pos = (now_ms - origin_ms_) % cycle_ms_;
  if (pos < 0)
    pos += cycle_ms_;
  const std::int64_t cycle_start = now_ms - pos;
  const std::size_t k = interval_at(pos);
  std::vector<GroupState> out;
  out.reserve(groups_.size());
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    GroupState s{groups_[g], intervals_[k].states[g], std::nullopt};
    // The next stretch, over at most one cycle, in which this group shows something else.
    for (std::size_t n = 1; n <= intervals_.size(); ++n) {
      const std::size_t j = (k + n) % intervals_.size();
      if (intervals_[j].states[g] != s.state) {
        const std::int64_t wraps = (k + n) / intervals_.size();
        s.next_change_ms =
            cycle_start + static_cast<std::int64_t>(wraps) * cycle_ms_ + intervals_[j].start_ms;
        break;
      }
    }
    out.push_back(s);
  }
  return out;
}

}  // namespace tb::server
