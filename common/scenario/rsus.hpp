#pragma once
/// @file Reading a scenario's `rsus` (road-side units, issue 34) against its map. Internal to
/// the scenario loader; the fields are in docs/scenario.md, "Road-side units".

#include <optional>
#include <string>
#include <vector>

#include "common/map/scenario_map.hpp"
#include "common/scenario/json_reader.hpp"
#include "common/scenario/scenario.hpp"

namespace tb::scenario::detail {

/// How far from the nearest road surface (the outer border of its outermost lane) an RSU may
/// stand: a unit on a mast at the kerb, or on a gantry, is within a few metres; 50 m leaves
/// room for a cabinet set back from a wide junction and catches coordinates in the wrong frame.
inline constexpr double kMaxRsuRoadDistanceM = 50.0;

/// Distance from (@p x, @p y) to the nearest road surface of @p net, m (0 on a road). Each road
/// is sampled every metre of its reference line; the error is below 0.5 m.
double distance_to_road(const map::odr::RoadNetwork& net, double x, double y);

/// The RSUs of @p node (the `rsus` array; nullopt: none). Each must serve a signalised junction
/// of @p map and stand on the map (docs/scenario.md); an id or a station id already used by a
/// vehicle of @p s or another RSU is refused. @throws ScenarioError naming the field.
std::vector<Rsu> read_rsus(std::optional<Node> node, const Scenario& s, const map::ScenarioMap& map,
                           const std::string& map_name, const std::vector<Node>& vehicle_nodes);

}  // namespace tb::scenario::detail
