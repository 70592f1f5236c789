#pragma once
/// @file Which lanes a lane-following vehicle drives: the lane it starts on, and the plan of lane
/// nodes (common/map/opendrive/lane_graph.hpp) for the scenario's route — its own lane, a random
/// successor at every fork, a list of roads, or the shortest path to a goal. The scenario loader
/// builds a plan to name a route the network cannot give; the scripted drivers drive it.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/map/opendrive/lane_graph.hpp"
#include "common/map/opendrive/queries.hpp"
#include "common/map/scenario_map.hpp"
#include "common/scenario/scenario.hpp"

namespace tb::map {

/// A vehicle on a lane: road index, OpenDRIVE lane id, s, and whether it drives against the
/// lane's direction of travel (the head-on cases of the built-in layouts).
struct LaneStart {
  int road = -1;
  int lane = 0;
  double s = 0.0;
  bool against = false;
};

/// The drivable lane under (x, y) whose direction of travel is closest to @p yaw (rad, ccw from
/// east), driven against when the heading is opposite. Where lanes overlap (junctions) the one
/// whose direction fits best wins, then the one whose centre is nearest. Empty off every
/// drivable lane.
std::optional<LaneStart> lane_start(const odr::RoadNetwork& net, const odr::LaneLocator& locator,
                                    double x, double y, double yaw);

/// Where a vehicle of the scenario starts: the lane of its lane spawn (OpenDRIVE ids, or a
/// built-in layout's lane in the generated network's terms), or lane_start() at its pose spawn.
/// Empty when the spawn is on no drivable lane.
std::optional<LaneStart> vehicle_start(const scenario::Vehicle& vehicle, const ScenarioMap& map);

/// A route the network cannot give. field() is the JSON pointer below the driver object
/// (`route/2`, `to/road`, `to`), so that the loader can name the scenario field.
class RouteError : public std::runtime_error {
 public:
  RouteError(std::string field, const std::string& reason)
      : std::runtime_error(reason), field_(std::move(field)) {}
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

/// The seed of one vehicle's random choices: the scenario's seed mixed with its station id, so
/// that vehicles differ and a run repeats.
std::uint64_t vehicle_seed(std::uint64_t scenario_seed, std::uint32_t station_id);

/// One node of a plan, and whether the vehicle reaches it by a lane change (a neighbour in the
/// same lane section) rather than by driving on.
struct PlanStep {
  std::size_t node = 0;
  bool lane_change = false;
};

/// The lane nodes a vehicle drives, handed out one at a time in driving order.
///
/// - kLane: at every fork the straightest successor (least heading change over it).
/// - kRandom: a successor drawn uniformly at every fork (splitmix64 from the seed: the same on
///   every platform and run).
/// - kRoads: the shortest lane path through the listed roads in order (the spawn road first
///   when the list does not start with it; junction connecting roads in between may be left
///   out), then on along the last road to its end.
/// - kTo: LaneGraph::route() to the goal.
///
/// Where a lane ends and a neighbour of the same direction continues (a merge) the kLane and
/// kRandom plans change into it; kRoads and kTo change lanes where the shortest path does.
/// A vehicle driving against its lane (LaneStart::against) follows it backwards through unique
/// predecessors only (no route may be given then).
class RoutePlan {
 public:
  /// @throws RouteError for a route naming a road the network lacks, a list of roads no lane
  /// path connects in order, a goal that does not exist, is not drivable or cannot be reached,
  /// a route given to a vehicle driving against its lane, or a start lane that is not drivable.
  RoutePlan(const odr::RoadNetwork& net, const odr::LaneGraph& graph,
            const scenario::DriveRoute& route, const LaneStart& start, std::uint64_t seed);

  std::size_t start_node() const { return start_; }
  const LaneStart& start() const { return start_pos_; }
  /// The next node after the last one handed out (after the start node at first); empty once
  /// the route ends (a lane with no drivable continuation, the goal, the last listed road).
  std::optional<PlanStep> next();
  /// kTo: s of the goal on the plan's last node.
  std::optional<double> goal_s() const { return goal_s_; }

 private:
  std::optional<PlanStep> choose();
  std::vector<std::size_t> onward(std::size_t node) const;  ///< drivable next nodes
  std::size_t straightest(const std::vector<std::size_t>& nodes) const;
  void plan_roads(const scenario::DriveRoute& route);
  void plan_to(const scenario::DriveRoute& route);

  const odr::RoadNetwork& net_;
  const odr::LaneGraph& graph_;
  scenario::DriveRoute::Kind kind_;
  LaneStart start_pos_;
  std::size_t start_ = 0;
  std::size_t current_ = 0;
  std::vector<PlanStep> fixed_;  ///< kRoads, kTo: the whole path after the start node
  std::size_t fixed_next_ = 0;
  int last_road_ = -1;  ///< kRoads: keep on this road after the list
  std::optional<double> goal_s_;
  std::uint64_t rng_;
};

}  // namespace tb::map
