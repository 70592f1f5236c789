#pragma once
/// @file Summaries of a road network for people and scripts (scenario-check --describe and
/// --where).

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "common/map/opendrive/queries.hpp"
#include "common/map/scenario_map.hpp"

namespace tb::map {

/// Roads, junctions, connecting roads, metres of lane by type, bounding box, geoReference and
/// origin source, warnings and skipped signals/objects, and the traffic lights (signal groups,
/// their heads and lanes). @throws odr::MapError for lights SignalLayout refuses.
nlohmann::json describe(const odr::RoadNetwork& net, const OriginSource& origin);

/// The lane under (x, y) as JSON (road id, lane id, s, t, z, lane type, drivable), or null.
nlohmann::json where(const odr::RoadNetwork& net, double x, double y);

}  // namespace tb::map
