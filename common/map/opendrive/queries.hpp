#pragma once
/// @file Queries on a RoadNetwork in its inertial frame: a lane position to a surface pose, and
/// a point to the lane under it through a uniform-grid spatial index.

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/map/opendrive/road_network.hpp"

namespace tb::map::odr {

/// A lane of a road (road index into RoadNetwork::roads, OpenDRIVE lane id).
struct LaneRef {
  int road = -1;
  int lane = 0;
  bool operator==(const LaneRef&) const = default;
};

/// Where a point lies: road, lane, section, road coordinates and the surface height there.
struct LanePosition {
  LaneRef ref;
  std::size_t section = 0;
  double s = 0.0;
  double t = 0.0;
  double z = 0.0;  ///< surface height at (s, t)
};

/// The lane @p lane of road @p road at @p s. @throws MapError (path `road[@id='..']`) for a road
/// index out of range, s outside [0, length], or a lane the section at s does not have.
const Lane& lane_at(const RoadNetwork& net, int road, int lane, double s);

/// t of lane @p lane's centre at s (the centre lane: the laneOffset line).
double lane_centre_t(const Road& road, int lane, double s);

/// The road surface @p offset metres left (+t) of lane @p lane's centre at s, heading along s
/// including the centre line's lateral drift (lanes that widen or shift). @throws MapError as
/// lane_at().
SurfacePose lane_pose(const RoadNetwork& net, int road, int lane, double s, double offset = 0.0);

/// A vehicle placed on a lane: OpenDRIVE road id (string), lane id, s, lateral offset from
/// the lane's centre (m, + to the left of the road's s direction).
struct LaneSpawn {
  std::string road;
  int lane = 0;
  double s = 0.0;
  double offset = 0.0;
};

/// The pose of a vehicle spawned at @p spawn, facing its lane's direction of travel (yaw, pitch
/// and roll turned round on lanes that run against s). @throws MapError (path
/// `road[@id='..']`) for a road that does not exist, s outside [0, length], a lane that does
/// not exist at s, or one that is not drivable there (its type, or no width).
SurfacePose spawn_pose(const RoadNetwork& net, const LaneSpawn& spawn);

/// Which lane holds @p t at (section, s); 0 when t is outside every lane of the section.
int lane_of(const Road& road, std::size_t section, double s, double t);

/// Finds the lane under a point. Roads are cut into pieces of at most 2 m whose bounding boxes
/// (lanes included) go into a uniform grid; a query looks at one cell, rejects pieces by a
/// cheap local test and projects onto the survivors' reference lines by Newton's method.
class LaneLocator {
 public:
  explicit LaneLocator(const RoadNetwork& net);

  /// The lane under (x, y). Where lanes overlap (junctions, bridges) the first lane of
  /// @p prefer that matches wins (a vehicle's previous lane, then its successors), then a lane
  /// whose surface is within 3 m of @p z (the nearest), then a drivable lane, then the lowest
  /// road index. Empty when the point is on no lane.
  std::optional<LanePosition> locate(double x, double y, std::optional<double> z = std::nullopt,
                                     std::span<const LaneRef> prefer = {}) const;
  /// Every lane under (x, y), one entry per road.
  std::vector<LanePosition> locate_all(double x, double y) const;

  std::size_t pieces() const { return pieces_.size(); }

 private:
  struct Piece {
    int road;
    const Geometry* geometry;  ///< pieces never span two geometries
    double s0, s1;
    double x0, y0, c0, s0n;  ///< start point, cos/sin of the start heading
    double reach;            ///< largest |t| of any lane border on the piece, plus margin
    double slack;            ///< along-track tolerance of the pre-test (curvature * reach)
  };
  void add_road(int index);
  void build_grid();
  bool project(const Piece& p, double x, double y, double& s, double& t) const;

  const RoadNetwork& net_;
  std::vector<Piece> pieces_;
  double min_x_ = 0, min_y_ = 0, cell_ = 8.0;
  std::size_t nx_ = 1, ny_ = 1;
  std::vector<std::uint32_t> cell_start_;  ///< CSR: cell i holds items[start[i] .. start[i+1])
  std::vector<std::uint32_t> items_;
};

}  // namespace tb::map::odr
