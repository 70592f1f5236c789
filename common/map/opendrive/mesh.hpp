#pragma once
/// @file Renderer-independent geometry for views and physics: s samples by a tolerance, lane
/// border and centre polylines, and the road-surface triangle mesh.

#include <cstdint>
#include <vector>

#include "common/map/opendrive/queries.hpp"

namespace tb::map::odr {

struct Vertex {
  double x = 0, y = 0, z = 0;
};

/// s values on [s0, s1] such that the chords between them stay within @p eps metres of the
/// road surface up to @p reach metres from the reference line (reference curvature, heading
/// and elevation change considered), never further apart than @p max_step. Includes s0, s1 and
/// every geometry and profile record start in between.
std::vector<double> sample_s(const Road& road, double s0, double s1, double eps, double reach,
                             double max_step = 5.0);

/// A lane's outer border (or centre) in section @p section, sampled by @p eps.
std::vector<Vertex> lane_border(const Road& road, std::size_t section, int lane, double eps);
std::vector<Vertex> lane_centre(const Road& road, std::size_t section, int lane, double eps);

/// Triangles of the road surface: per lane, strips between its inner and outer border.
/// `lanes[i]` names the lane of triangle i, so that physics can tell drivable surface from
/// the rest and views can colour by type.
struct RoadMesh {
  std::vector<Vertex> vertices;
  std::vector<std::uint32_t> indices;   ///< three per triangle, counter-clockwise seen from above
  std::vector<LaneRef> lanes;           ///< one per triangle
  std::vector<std::uint32_t> sections;  ///< one per triangle: the lane section (views colour by
                                        ///< the lane's type there)
  std::size_t triangles() const { return indices.size() / 3; }
};

/// The mesh of every lane of every road (zero-width stretches skipped), chords within @p eps.
RoadMesh road_mesh(const RoadNetwork& net, double eps = 0.02);

/// The rectangle in x and y that holds every vertex of a mesh (all 0 for an empty one).
struct Extent {
  double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
};
Extent extent(const RoadMesh& mesh);

}  // namespace tb::map::odr
