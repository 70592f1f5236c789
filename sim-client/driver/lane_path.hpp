#pragma once
/// @file The line a lane-following vehicle drives: the centres of the lanes of its route plan,
/// sampled into one polyline with the distance along it (d), with lane changes as smooth
/// blends from one lane centre to the next. It grows ahead as the vehicle drives and is
/// trimmed behind it.

#include <cstddef>
#include <deque>
#include <optional>

#include "common/map/route_plan.hpp"
#include "sim-client/driver/drive_map.hpp"

namespace tb::client {

class LanePath {
 public:
  struct Point {
    double x = 0.0, y = 0.0;
    double d = 0.0;          ///< m along the path (any origin; grows in the direction of travel)
    double curvature = 0.0;  ///< 1/m, positive turning left in the direction of travel
  };
  /// One lane node on the path between d0 and d1; a lane change when from_lane != lane.
  struct Step {
    std::size_t node = 0;  ///< the lane driven (the target lane of a lane change)
    int road = -1;
    int lane = 0;
    int from_lane = 0;
    int junction = -1;
    double d0 = 0.0, d1 = 0.0;
    double s0 = 0.0, s1 = 0.0;  ///< road s at d0 and d1
    bool lane_change() const { return from_lane != lane; }
  };
  struct Projection {
    double d = 0.0;
    double lateral = 0.0;  ///< m left of the path, in the direction of travel
  };

  /// @p change_speed (m/s) sets the length of lane changes: a smoothstep blend whose lateral
  /// acceleration stays near 2 m/s² at that speed (15 – 80 m, within the lane section).
  LanePath(const DriveMap& map, map::RoutePlan plan, double change_speed);

  /// d of the vehicle's start position.
  double start_d() const { return start_d_; }
  /// Grows the path until it reaches @p d ahead, or the route ends.
  void extend_to(double d);
  /// Grows the path backwards (through single predecessors) until it starts at or before @p d.
  void extend_back_to(double d);
  /// Drops the steps that end before @p d.
  void trim_before(double d);
  /// The route has no more lanes: the path ends at end_d() (a lane end or the goal).
  bool ended() const { return ended_; }
  /// The route ends at a goal (`to`) rather than at the end of a lane.
  bool ends_at_goal() const { return ended_ && goal_; }
  double begin_d() const { return points_.front().d; }
  double end_d() const { return points_.back().d; }

  /// The nearest point of the path to (x, y), searched within 15 m behind and 40 m ahead of
  /// @p hint (a vehicle moves less than that between two states); beyond either end of the path
  /// the end segment is extended.
  Projection project(double x, double y, double hint) const;
  /// The point at @p d (extended along the end segments beyond the ends) and the unit tangent.
  void at(double d, double& x, double& y) const;
  void tangent(double d, double& tx, double& ty) const;
  /// Curvature at @p d (1/m, positive left), linear between points, 0 beyond the ends.
  double curvature(double d) const;
  /// Index of the first point at or after @p d.
  std::size_t index_at(double d) const;

  const std::deque<Point>& points() const { return points_; }
  const std::deque<Step>& steps() const { return steps_; }

 private:
  void grow();
  /// Samples road s from s_a to s_b on lane @p lane (blending from @p from_lane over the step
  /// when they differ), appended (or prepended) to the path.
  void emit(std::size_t node, int from_lane, double s_a, double s_b, bool front);
  int direction(std::size_t node) const;  ///< +1 driving along s, -1 against
  double entry_s(std::size_t node) const;
  double exit_s(std::size_t node) const;

  const DriveMap& map_;
  map::RoutePlan plan_;
  double change_speed_;
  std::deque<Point> points_;
  std::deque<Step> steps_;
  std::size_t node_ = 0;  ///< the node the path ends on
  double s_ = 0.0;        ///< road s where the path ends
  std::optional<map::PlanStep> pending_;
  std::optional<double> goal_;
  bool ended_ = false;
  double start_d_ = 0.0;
};

}  // namespace tb::client
