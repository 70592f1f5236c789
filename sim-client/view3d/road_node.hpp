#pragma once
/// @file The world's static geometry from the OpenDRIVE model: the road surface (common/map's
/// road_mesh, the same lane geometry and tolerance-driven sampling as the physics mesh), the
/// lane marks, and the ground (common/map's Terrain, the surface the physics drives on beside
/// the roads).
///
/// Choices: lanes are coloured by type (asphalt for the driving types, lighter for shoulders,
/// concrete for borders and curbs, paving for sidewalks); marks lie 2 cm above the surface
/// with a polygon offset and are drawn after it, so that they never z-fight; roads inside
/// junctions get no marks (real junctions have none across the box, and the connecting roads'
/// overlapping lines would be clutter), and their lanes other than carriageway lie 1 cm low,
/// so that where connecting roads overlap the asphalt is drawn once, without stripes; the
/// ground is drawn with depth writes (hills hide what lies behind them) the kerb drop (5 cm)
/// below the road, grass darkened with its slope, lit by its normals, and a skirt round it
/// continues it level out to beyond the fog's end.

#include <array>
#include <cstddef>
#include <vector>

#include <osg/Node>
#include <osg/ref_ptr>

#include "common/map/opendrive/road_network.hpp"

namespace tb::client::view3d {

/// The chord tolerance of the view's road surface and marks (metres).
inline constexpr double kRoadTolerance = 0.05;
/// How far the marks lie above the surface (metres).
inline constexpr double kMarkLift = 0.02;
/// How far the lanes of junction roads that are not carriageway (sidewalks, borders,
/// shoulders) lie below the surface, so that another connecting road's carriageway over them
/// wins the depth test (metres).
inline constexpr double kJunctionVergeDrop = 0.01;

/// One painted line (a solid line, or one dash of a broken one) as a strip between two edges.
struct MarkStrip {
  std::array<float, 3> colour{1, 1, 1};
  std::vector<std::array<double, 3>> left, right;  ///< the strip's two edges, same length
};

/// The lane marks of @p net as strips (renderer-free, so that tests can check them).
std::vector<MarkStrip> lane_mark_strips(const map::odr::RoadNetwork& net, double eps);

/// RGB of a lane type on the surface.
std::array<float, 3> lane_colour(const std::string& type);
/// RGB of a road mark colour ("standard", "white", "yellow", ...).
std::array<float, 3> mark_colour(const std::string& colour);

struct RoadNodeStats {
  std::size_t surface_triangles = 0;
  std::size_t mark_triangles = 0;
  std::size_t terrain_triangles = 0;  ///< the ground and the skirt round it
};

/// Surface, marks and ground as one node (building the ground takes ~0.1 s on the shipped
/// four-way junction: common/map/opendrive/README.md, Terrain).
osg::ref_ptr<osg::Node> make_road_node(const map::odr::RoadNetwork& net,
                                       RoadNodeStats* stats = nullptr);

}  // namespace tb::client::view3d
