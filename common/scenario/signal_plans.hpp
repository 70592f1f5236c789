#pragma once
/// @file Reading a scenario's `signals` (fixed-time plans, issue 34) against the traffic lights
/// of its map. Internal to the scenario loader; the fields are in docs/scenario.md, "Signals".

#include <optional>
#include <string>
#include <vector>

#include "common/map/scenario_map.hpp"
#include "common/scenario/json_reader.hpp"
#include "common/scenario/scenario.hpp"

namespace tb::scenario::detail {

/// Default plan of a junction the scenario gives none for: one phase per signal group in id
/// order (groups never green together cannot conflict, whatever the junction's layout),
/// each kDefaultGreenS of green, with the SignalPlan defaults for amber and all-red.
inline constexpr double kDefaultGreenS = 20.0;

/// The plans of @p node (the `signals` array, absent: nullopt) for the lights of @p map, and a
/// default plan for every signalised junction it leaves out. @p map_name names the map in
/// messages. @throws ScenarioError naming the field; a map whose lights the index refuses
/// (map::odr::SignalLayout) at /map/file.
std::vector<SignalPlan> read_signal_plans(std::optional<Node> node, const map::ScenarioMap& map,
                                          const std::string& map_name, const std::string& file);

}  // namespace tb::scenario::detail
