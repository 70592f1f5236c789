#pragma once
/// @file OpenDRIVE 1.4-1.7 importer. Every defect the model cannot be built around is a
/// MapError naming the file, the element path and the reason; things it reads past (signals,
/// objects, crossfall, surface) are counted or named once in RoadNetwork::warnings.

#include <string>
#include <string_view>

#include "common/map/opendrive/road_network.hpp"

namespace tb::map::odr {

/// Reads the .xodr file at @p path. @throws MapError
RoadNetwork load_opendrive(const std::string& path);

/// Parses OpenDRIVE text; @p source names it in errors. @throws MapError
RoadNetwork parse_opendrive(std::string_view xml, const std::string& source);

}  // namespace tb::map::odr
