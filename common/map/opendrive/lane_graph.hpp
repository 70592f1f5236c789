#pragma once
/// @file The lane graph of a RoadNetwork: one node per lane per lane section, edges in the
/// direction of travel (within a road, to linked roads, through junctions) and lane changes to
/// the neighbouring lanes of the same direction; shortest routes over it.

#include <cstddef>
#include <optional>
#include <vector>

#include "common/map/opendrive/queries.hpp"

namespace tb::map::odr {

struct LaneNode {
  int road = -1;
  std::size_t section = 0;
  int lane = 0;
  double length = 0.0;  ///< the section's length along the reference line
  bool forward = true;  ///< travel runs along s
  bool drivable = false;
};

/// A route: the nodes in driving order, from the start lane position to the goal.
struct Route {
  std::vector<std::size_t> nodes;
  double length = 0.0;  ///< metres driven, measured along the reference lines
  std::size_t lane_changes = 0;
};

class LaneGraph {
 public:
  explicit LaneGraph(const RoadNetwork& net);

  std::size_t size() const { return nodes_.size(); }
  const LaneNode& node(std::size_t i) const { return nodes_[i]; }
  /// The node of lane @p lane on road @p road in the section holding s; empty if none.
  std::optional<std::size_t> find(int road, int lane, double s) const;
  std::optional<std::size_t> find_in_section(int road, std::size_t section, int lane) const;
  /// Lanes a vehicle continues into at the end of node @p i (in its direction of travel).
  const std::vector<std::size_t>& successors(std::size_t i) const { return next_[i]; }
  const std::vector<std::size_t>& predecessors(std::size_t i) const { return prev_[i]; }
  /// Neighbouring lanes of the same direction in the same section (lane changes).
  const std::vector<std::size_t>& neighbours(std::size_t i) const { return side_[i]; }

  /// Shortest route over drivable lanes from (road, lane, s) to (road, lane, s); a lane change
  /// costs `lane_change_cost` metres on top of the distance. Empty when the goal is not
  /// reachable (also a goal behind the start on the start's own lane section). @throws MapError for
  /// a lane position that does not exist.
  std::optional<Route> route(LaneRef from, double from_s, LaneRef to, double to_s,
                             double lane_change_cost = 20.0) const;

 private:
  void add_edge(std::size_t from, std::size_t to);
  void link_roads();
  void link_junctions();
  /// The node of @p lane at the end @p end of road @p road.
  std::optional<std::size_t> at_end(int road, ContactPoint end, int lane) const;

  const RoadNetwork& net_;
  std::vector<LaneNode> nodes_;
  std::vector<std::vector<std::size_t>> first_;  ///< [road][section] -> first node index
  std::vector<std::vector<std::size_t>> next_, prev_, side_;
};

}  // namespace tb::map::odr
