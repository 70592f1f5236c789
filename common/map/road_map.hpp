#pragma once
/// @file Road and lane geometry of the built-in map layouts (scenario "map" field).
///
/// Every lane's centre line is a straight segment or a full circle, so that positions, headings
/// and projections are exact and cost O(1). Lanes are numbered from the right edge of their
/// road (seen in the road's reference direction); the leftmost `oncoming_lanes` run the other
/// way. Distances along a lane (s) grow in the lane's direction of travel.

#include <optional>
#include <variant>
#include <vector>

#include "common/scenario/scenario.hpp"

namespace tb::map {

struct Point {
  double x = 0.0;  ///< east, m
  double y = 0.0;  ///< north, m
};

/// A straight centre line from `start`, `length` metres along the unit vector `dir`.
struct Segment {
  Point start;
  Point dir;
  double length = 0.0;
};
/// A closed circular centre line, run counter-clockwise or clockwise.
struct Circle {
  Point centre;
  double radius = 0.0;
  bool ccw = true;
};
using CentreLine = std::variant<Segment, Circle>;

struct Pose {
  Point p;
  double yaw = 0.0;  ///< rad, counter-clockwise from east (see common/geodesy for ETSI heading)
};

/// Where a point lies relative to a centre line.
struct Projection {
  double s = 0.0;        ///< along the line, in its direction
  double lateral = 0.0;  ///< to the left of the direction of travel, m
  bool within = false;   ///< s inside the line's extent (always true on circles)
};

double length(const CentreLine& line);
bool is_closed(const CentreLine& line);
Pose pose_at(const CentreLine& line, double s);
Projection project(const CentreLine& line, Point p);

struct Lane {
  int road = 0;
  int index = 0;
  double width = 0.0;
  bool oncoming = false;  ///< runs against its road's reference direction
  CentreLine centre;
};

struct Road {
  CentreLine reference;  ///< the road's middle, in its reference direction
  double width = 0.0;
  std::vector<Lane> lanes;
};

/// A line painted on the road, for drivers' views.
struct Marking {
  enum class Style { kEdge, kDashed, kSolid };
  Style style = Style::kEdge;
  CentreLine line;
};

struct LaneMatch {
  int road = 0;
  int lane = 0;
  Projection where;
};

class RoadMap {
 public:
  /// @throws std::invalid_argument for a spec no layout can be built from.
  explicit RoadMap(const scenario::MapSpec& spec);

  const scenario::MapSpec& spec() const { return spec_; }
  const std::vector<Road>& roads() const { return roads_; }
  /// @throws std::out_of_range for a road or lane that does not exist.
  const Lane& lane(int road, int lane) const;

  /// Pose on a lane's centre line; s wraps on closed lanes and is clamped on open ones.
  Pose lane_pose(int road, int lane, double s) const;
  /// The lane whose area contains @p p and whose direction is closest to @p yaw (rad); empty
  /// when the point is off every road.
  std::optional<LaneMatch> find_lane(Point p, double yaw) const;
  bool on_road(Point p) const;
  std::vector<Marking> markings() const;

 private:
  scenario::MapSpec spec_;
  std::vector<Road> roads_;
};

}  // namespace tb::map
