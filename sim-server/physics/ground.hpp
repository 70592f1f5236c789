#pragma once
/// @file The ground of the world as triangles: the road surface of the scenario's map and what
/// a car that leaves it drives on, with a ray test of its own for the wheels.
///
/// Flat maps (no elevation, no superelevation: every built-in layout) are the plane z = 0 over
/// the roads' extent plus a margin, in 50 m cells. Other maps are
/// - the road surface from the lanes (odr::road_mesh, chords within 2 cm, with elevation and
///   superelevation; lanes of a road share their borders and sections their boundary s, and
///   the ray test accepts hits up to 0.1 mm outside a triangle, so that no wheel falls through
///   a seam between sections or between a road and the junction road it continues into);
/// - the terrain (common/map/opendrive/terrain.hpp) fitted to those very triangles over the
///   roads' extent plus the margin: the kerb drop (5 cm) below every road at its edge, blended
///   smoothly between the roads and never above a lane, in 4 m cells. The 3D view draws the
///   same terrain (built from the same map with the same options when the margin is the
///   default 200 m), so a car that leaves the road drives on the ground its driver sees.
///   Its cells are ray-tested directly (the two triangles of each cell the ray crosses), not
///   through the index of the road triangles.
///
/// Coordinates are the physics frame: the map's frame shifted by `origin` (Bullet computes in
/// single precision; a map in projected coordinates, x ~ 700 km, would lose centimetres).

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "common/map/opendrive/terrain.hpp"
#include "common/map/scenario_map.hpp"

namespace tb::server::physics {

struct Vec3 {
  double x = 0, y = 0, z = 0;
};

struct GroundHit {
  Vec3 point;
  Vec3 normal;            ///< unit, pointing up (towards the ray's start)
  double fraction = 1.0;  ///< along the ray, [0, 1]
};

class Ground {
 public:
  /// @p margin_m: how far the ground reaches beyond the roads' extent. @p mesh: the road
  /// surface and the terrain as triangles (required for maps that are not flat); without, the
  /// plane z = 0 alone.
  Ground(const map::ScenarioMap& map, double margin_m, bool mesh);

  /// Only the plane z = 0: no triangles to test.
  bool flat() const { return flat_; }
  /// The map frame's point (0, 0, 0) in the physics frame is -origin().
  const Vec3& origin() const { return origin_; }
  /// Vertices (x, y, z in the physics frame) and three indices per triangle, counter-clockwise
  /// seen from above: the roads, then the terrain's cells, or the plane in 50 m cells on a flat
  /// map (for Bullet's collision shape; cast() tests the plane exactly).
  const std::vector<std::array<float, 3>>& vertices() const { return vertices_; }
  const std::vector<std::uint32_t>& indices() const { return indices_; }
  std::size_t triangles() const { return indices_.size() / 3; }
  /// The extent of the ground (physics frame), margin included.
  double min_x() const { return min_x_; }
  double min_y() const { return min_y_; }
  double max_x() const { return max_x_; }
  double max_y() const { return max_y_; }

  /// The ground beside the roads (map frame), when the road surface is a mesh.
  const map::odr::Terrain* terrain() const { return terrain_ ? &*terrain_ : nullptr; }

  /// Where the segment from -> to first meets the ground coming from above (nearest to
  /// `from`); empty when it meets nothing (outside the extent, or pointing up).
  std::optional<GroundHit> cast(const Vec3& from, const Vec3& to) const;

 private:
  void add_triangle(const Vec3& a, const Vec3& b, const Vec3& c);
  void add_plane();
  void add_terrain();
  void build_index();
  /// The nearest hit of from -> to on triangle @p t closer than @p best (Möller–Trumbore).
  void hit_triangle(std::size_t t, const Vec3& from, const Vec3& d,
                    std::optional<GroundHit>& best) const;

  bool flat_ = true;
  Vec3 origin_;
  std::vector<std::array<float, 3>> vertices_;
  std::vector<std::uint32_t> indices_;
  std::size_t indexed_ = 0;  ///< triangles of the roads, before the terrain's or the plane's
  std::optional<map::odr::Terrain> terrain_;
  std::size_t terrain_base_ = 0;  ///< the terrain's first vertex
  double min_x_ = 0, min_y_ = 0, max_x_ = 0, max_y_ = 0;
  // Uniform grid over the triangles' footprints (CSR), for the wheels' short vertical rays.
  double cell_ = 2.0;
  std::size_t nx_ = 1, ny_ = 1;
  std::vector<std::uint32_t> cell_start_;
  std::vector<std::uint32_t> items_;
};

}  // namespace tb::server::physics
