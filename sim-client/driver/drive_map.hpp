#pragma once
/// @file What the scripted drivers of one client share about the road network: the OpenDRIVE
/// model with its lane graph and lane locator, which junction lanes cross or merge, which lanes
/// lead into which junction, and per state frame where every vehicle is on it (Traffic).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "common/map/opendrive/lane_graph.hpp"
#include "common/map/opendrive/queries.hpp"
#include "common/map/scenario_map.hpp"
#include "common/wire/vehicle_state.hpp"
#include "sim-client/driver/traffic_lights.hpp"

namespace tb::client {

/// A vehicle as another driver sees it: its state, its size, and where it is on the network.
struct Observed {
  wire::VehicleState state;
  double length = 4.5;
  double width = 1.8;
  /// The lane it drives on (direction of travel within 60° of its heading), if any.
  std::optional<map::odr::LanePosition> lane;
  /// The junction it is in or approaching (-1: neither), the junction lanes it is on (inside)
  /// or may take (approaching: every way on from its lane), and how far it is from the entry.
  int junction = -1;
  bool inside = false;
  double to_entry = 0.0;
  std::vector<std::size_t> junction_lanes;
};

/// Size of a vehicle for Traffic (from the scenario's model).
struct VehicleSize {
  std::uint32_t station_id = 0;
  double length = 4.5;
  double width = 1.8;
};

/// Every vehicle of one state frame, located once for all drivers.
///
/// With 1000 vehicles every driver looking at every other is 10^6 pairs a frame, 10^8 a second:
/// index() sorts the vehicles into a grid and by station id once a frame (DriveMap::observe
/// does), so that find() and near() look only where it matters. Without index() (a Traffic
/// built by hand) both scan every vehicle, with the same results.
struct Traffic {
  std::vector<Observed> vehicles;
  /// The traffic lights as of this frame (the session's latest SignalStates); null: the client
  /// knows of none, and every junction runs on its priority rules.
  const TrafficLights* lights = nullptr;
  const Observed* find(std::uint32_t station_id) const;
  /// Every vehicle whose position is within @p radius of (x, y) (and maybe some a little
  /// farther), in the order of `vehicles`.
  std::vector<const Observed*> near(double x, double y, double radius) const;
  /// The longest vehicle, m: a search for vehicles whose footprint reaches a point widens by it.
  double max_length() const { return max_length_; }
  /// Builds the lookups of find() and near(); call again after changing `vehicles`.
  void index();

  /// Side of a grid cell, m: about the longest look ahead of a driver (150 m) a few cells wide.
  static constexpr double kCell = 50.0;

 private:
  std::vector<std::pair<std::uint64_t, std::size_t>> cells_;     ///< (cell, vehicle) sorted
  std::vector<std::pair<std::uint32_t, std::size_t>> stations_;  ///< (station id, vehicle) sorted
  double max_length_ = 0.0;
  bool indexed_ = false;
  std::size_t indexed_size_ = 0;
};

/// Junction priority, the same rule for every driver on the same data, so that exactly one of
/// two conflicting vehicles goes: a vehicle inside the junction before one outside; then the
/// one that reaches the entry first at its present speed (distance / max(speed, 1 m/s)); then
/// the lower station id.
bool goes_before(const Observed& a, const Observed& b);

class DriveMap {
 public:
  explicit DriveMap(std::shared_ptr<const map::ScenarioMap> map);

  const map::ScenarioMap& scenario_map() const { return *map_; }
  const map::odr::RoadNetwork& network() const { return map_->network(); }
  const map::odr::LaneGraph& graph() const { return graph_; }
  const map::odr::LaneLocator& locator() const { return locator_; }

  /// Junction index of a lane node's road; -1 outside junctions.
  int junction_of(std::size_t node) const;
  /// Whether vehicles on two junction lanes can meet: their centre lines come within 3 m of
  /// each other (they cross or merge), and they do not split from one lane (those follow).
  bool conflict(std::size_t a, std::size_t b) const;

  /// A lane leading into a junction: which junction, metres from the lane's end to the entry
  /// (through lanes that have one way on), and the junction lanes a vehicle on it may take.
  struct Approach {
    int junction = -1;
    double after = 0.0;
    std::vector<std::size_t> entries;
  };
  const Approach* approach(std::size_t node) const;

  /// How far before a junction a vehicle at @p speed counts as approaching it: its comfortable
  /// stopping distance (2 m/s²) plus 25 m, at least 40 m.
  static double approach_horizon(double speed);

  /// Locates every vehicle of a frame (sizes by station id; unknown ones 4.5 m × 1.8 m).
  Traffic observe(std::span<const wire::VehicleState> states,
                  std::span<const VehicleSize> sizes) const;

 private:
  void find_conflicts();
  void find_approaches();
  void observe_one(Observed& o) const;

  std::shared_ptr<const map::ScenarioMap> map_;
  const map::odr::RoadNetwork* net_;
  const map::odr::LaneGraph& graph_;
  const map::odr::LaneLocator& locator_;
  std::vector<int> junction_;                       ///< per node
  std::vector<std::vector<std::size_t>> conflict_;  ///< per node: conflicting nodes, sorted
  std::vector<std::optional<Approach>> approach_;   ///< per node
};

}  // namespace tb::client
