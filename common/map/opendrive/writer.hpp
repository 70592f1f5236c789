#pragma once
/// @file Writes a RoadNetwork as OpenDRIVE 1.7 text that other tools open (esmini, CARLA,
/// RoadRunner): the roads, lanes and junctions the model holds; its objects and signals are not
/// written (yet).

#include <string>

#include "common/map/opendrive/road_network.hpp"

namespace tb::map::odr {

std::string write_opendrive(const RoadNetwork& net);

}  // namespace tb::map::odr
