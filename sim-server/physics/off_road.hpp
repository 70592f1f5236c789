#pragma once
/// @file Which vehicles have left every drivable lane of the map, for the server's log and
/// status.
///
/// A vehicle is on the road while the point under the centre of its bounding box lies on a
/// drivable lane (odr::LaneLocator, preferring the lane it was last on, so that junction
/// overlaps resolve). Each vehicle is looked at once every `period` steps, a share of them in
/// every step, so that the cost per step stays flat (100 cars, every 10 steps: 10 lane queries
/// of ~1.5 µs per step).

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/map/scenario_map.hpp"
#include "common/wire/vehicle_state.hpp"

namespace tb::server::physics {

/// A vehicle left the drivable lanes, or came back onto them.
struct OffRoadEvent {
  std::size_t vehicle = 0;  ///< index in the world
  std::uint32_t station_id = 0;
  bool left = true;  ///< true: left the lanes; false: back on a drivable lane
  std::uint64_t tick = 0;
  double x = 0, y = 0, z = 0;  ///< where (map frame)
  /// The drivable lane it was last on (road id, lane id, s), empty if it never was on one.
  std::string last_road;
  int last_lane = 0;
  double last_s = 0;
};

class OffRoadMonitor {
 public:
  explicit OffRoadMonitor(const map::ScenarioMap& map, std::uint64_t period = 10);

  /// Looks at the vehicles due at @p tick (vehicle i when (i + tick) % period == 0) and
  /// appends what changed to the events.
  void update(std::uint64_t tick, std::span<const wire::VehicleState> states);
  /// Events since the last call (the server logs them).
  std::vector<OffRoadEvent> take_events();

  /// Vehicles off every drivable lane now.
  std::size_t off_now() const { return off_now_; }
  /// Times any vehicle left the drivable lanes since the start.
  std::uint64_t departures() const { return departures_; }
  bool off(std::size_t vehicle) const { return vehicle < status_.size() && status_[vehicle].off; }
  /// The last place a vehicle was seen off the road (valid while off(vehicle)).
  const OffRoadEvent& where(std::size_t vehicle) const { return status_[vehicle].last_event; }

 private:
  struct Status {
    bool off = false;
    bool seen = false;
    map::odr::LaneRef lane;  ///< last drivable lane, road < 0 if none yet
    double s = 0.0;
    OffRoadEvent last_event;
  };
  void check(std::size_t i, std::uint64_t tick, const wire::VehicleState& s);

  const map::ScenarioMap& map_;
  std::uint64_t period_;
  std::vector<Status> status_;
  std::vector<OffRoadEvent> events_;
  std::size_t off_now_ = 0;
  std::uint64_t departures_ = 0;
};

}  // namespace tb::server::physics
