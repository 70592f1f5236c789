#pragma once
/// @file Every junction's controller of a scenario, evaluated once per physics step: the latest
/// states as the sim protocol's SignalStates, and which groups changed in the step.

#include <cstdint>
#include <vector>

#include "common/scenario/scenario.hpp"
#include "common/wire/sim_protocol.hpp"
#include "sim-server/signals/signal_controller.hpp"

namespace tb::server {

class SignalSet {
 public:
  /// @p world_start_ms: UTC of sim time 0, Unix ms. @throws std::invalid_argument as
  /// SignalController, or for two plans of one intersection.
  SignalSet(const std::vector<scenario::SignalPlan>& plans, std::int64_t world_start_ms);

  bool empty() const { return controllers_.empty(); }
  /// Evaluates every controller at world time @p world_ms; returns the groups whose state
  /// differs from the previous call's (every group on the first call).
  std::vector<wire::sim::SignalGroupState> step(std::int64_t world_ms);
  /// The states of the latest step(), ascending by (intersection, signal group).
  const wire::sim::SignalStates& latest() const { return latest_; }

 private:
  std::vector<SignalController> controllers_;  ///< ascending by intersection id
  wire::sim::SignalStates latest_;
  bool stepped_ = false;
};

}  // namespace tb::server
