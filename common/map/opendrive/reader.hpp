#pragma once
/// @file OpenDRIVE 1.4-1.7 importer. Every defect the model cannot be built around is a
/// MapError naming the file, the element path and the reason; things it reads past (tunnels,
/// bridges, crossfall, surface) are counted or named once in RoadNetwork::warnings.

#include <string>
#include <string_view>

#include "common/map/opendrive/road_network.hpp"

namespace tb::map::odr {

/// Caps on what a file may say, each a MapError naming the element when passed: they keep
/// absurd input (the fuzzer's 1e300) from turning into a lane index or a mesh of gigabytes.
/// The largest magnitude of any number (coordinates, s, lengths, coefficients), m: projected
/// coordinates (UTM northings up to 1e7 m) fit.
inline constexpr double kMaxCoordinate = 1e8;
/// One road's length, and all roads' together, m.
inline constexpr double kMaxRoadLength = 1e5;
inline constexpr double kMaxNetworkLength = 1e7;
/// How far lanes may reach from their road's reference line, m.
inline constexpr double kMaxLateral = 1000.0;
/// The tightest curve of a reference line, 1/m (a radius of 0.1 m).
inline constexpr double kMaxCurvature = 10.0;

/// Reads the .xodr file at @p path. @throws MapError
RoadNetwork load_opendrive(const std::string& path);

/// Parses OpenDRIVE text; @p source names it in errors. @throws MapError
RoadNetwork parse_opendrive(std::string_view xml, const std::string& source);

}  // namespace tb::map::odr
