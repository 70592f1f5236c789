#pragma once
/// @file Where a scenario's road-side units stand (issue 34): the ground under each and its
/// antenna above it, in the map's frame. The emulator's GPS agent reports this position to the
/// RSU's gpsd and the radio medium places the RSU's radio there.

#include <vector>

#include "common/map/scenario_map.hpp"
#include "common/scenario/scenario.hpp"

namespace tb::map {

struct RsuSite {
  double x = 0.0, y = 0.0;
  double ground_z = 0.0;   ///< the surface under (x, y)
  double antenna_z = 0.0;  ///< ground_z + the RSU's height
};

/// One site per RSU of @p rsus, in order. The ground is the road surface where (x, y) lies on
/// a lane, else the terrain the 3D view and the physics use (odr::Terrain, built once here when
/// the map has relief and an RSU stands off the lanes), else the plane z = 0 on a flat map.
std::vector<RsuSite> rsu_sites(const std::vector<scenario::Rsu>& rsus, const ScenarioMap& map);

}  // namespace tb::map
