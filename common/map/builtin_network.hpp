#pragma once
/// @file The built-in layouts (straight, ring, crossing) generated as an OpenDRIVE road network,
/// so that every consumer can read one model and `scenario-check --export-xodr` can write them.
///
/// Mapping: the built-in road's middle is the OpenDRIVE reference line; laneOffset moves the
/// centre lane to the border between the two directions. Built-in lane i (0 = right edge) of
/// n lanes with k oncoming becomes OpenDRIVE lane -(n - k - i) for i < n - k (right, along s)
/// and i - (n - k) + 1 otherwise (left, against s). The ring is one closed arc road whose
/// successor is itself; the crossing is two straight roads crossing at grade without a
/// junction, as in the built-in layout (it has no turning lanes).

#include "common/map/opendrive/road_network.hpp"
#include "common/scenario/scenario.hpp"

namespace tb::map {

/// @throws std::invalid_argument for a spec no layout can be built from (as RoadMap).
odr::RoadNetwork generate_network(const scenario::MapSpec& spec);

/// OpenDRIVE lane id of built-in lane @p index.
int opendrive_lane_id(const scenario::MapSpec& spec, int index);

}  // namespace tb::map
