#pragma once
/// @file The traffic-light controllers sim-server runs (issue 34): pure logic from a scenario's
/// fixed-time plan and the world time to the state of every signal group, with the world time
/// of its next change. No clock, no sockets: the Hub asks with the time of each step.

#include <cstdint>
#include <optional>
#include <vector>

#include "common/scenario/scenario.hpp"
#include "common/wire/sim_protocol.hpp"

namespace tb::server {

using wire::sim::MovementPhaseState;

/// One signal group at one instant. For a fixed-time plan minEndTime = likelyTime = maxEndTime.
struct GroupState {
  int signal_group = 0;
  MovementPhaseState state = MovementPhaseState::kUnavailable;
  /// World time (UTC, Unix ms) the state ends; empty when it never does (a group green in
  /// every phase).
  std::optional<std::int64_t> next_change_ms;
};

/// One junction's fixed-time controller. The cycle (scenario.hpp, SignalPlan) starts at the
/// world's start time + offset_s and repeats, before sim time 0 too (the warm-up).
class SignalController {
 public:
  /// @p world_start_ms: UTC of sim time 0, Unix ms. @throws std::invalid_argument for a plan
  /// without phases or a junction id that is not an IntersectionID (the loader refuses both).
  SignalController(const scenario::SignalPlan& plan, std::int64_t world_start_ms);

  std::uint16_t intersection_id() const { return intersection_id_; }
  /// The junction's signal groups, ascending.
  const std::vector<int>& groups() const { return groups_; }
  std::int64_t cycle_ms() const { return cycle_ms_; }

  /// Every group's state at world time @p now_ms, in groups() order.
  std::vector<GroupState> states(std::int64_t now_ms) const;

 private:
  /// A stretch of the cycle in which no group changes.
  struct Interval {
    std::int64_t start_ms = 0;               ///< from the cycle's start
    std::vector<MovementPhaseState> states;  ///< by groups() index
  };
  std::size_t interval_at(std::int64_t pos_ms) const;

  std::uint16_t intersection_id_ = 0;
  std::vector<int> groups_;
  std::vector<Interval> intervals_;
  std::int64_t cycle_ms_ = 0;
  std::int64_t origin_ms_ = 0;  ///< world time of a cycle's start
};

}  // namespace tb::server
