#pragma once
/// @file Scripted drivers: controls computed from the vehicle's own state, so that a scenario
/// runs with no human at the wheel (scenario field `driver`).

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "common/map/road_map.hpp"
#include "common/scenario/scenario.hpp"
#include "common/wire/vehicle_state.hpp"

namespace tb::client {

/// Computes the controls for the next tick from the latest state of its vehicle. Time is the
/// state's sim time, so a driver runs the same in real time and as fast as possible. A script
/// starts at sim time 0: during the warm-up before it (negative sim time, sim-server holds the
/// car) its controls are released and nothing of its own state moves on.
class ScriptedDriver {
 public:
  virtual ~ScriptedDriver() = default;
  virtual wire::Controls update(const wire::VehicleState& state) = 0;
};

/// A control timeline: each step holds from its time until the next step's.
class TimelineDriver final : public ScriptedDriver {
 public:
  explicit TimelineDriver(scenario::TimelineDriver spec);
  wire::Controls update(const wire::VehicleState& state) override;
  /// The controls in effect at @p sim_time_s (all released before the first step).
  wire::Controls at(double sim_time_s) const;

 private:
  std::vector<scenario::ControlStep> steps_;
};

/// The lane a lane-following driver keeps to.
struct LaneRef {
  int road = 0;
  int lane = 0;
  bool against = false;  ///< drives against the lane's direction (s decreasing)
};

/// What the lane-following driver computed in its last update, for tests and the view.
struct LaneFollowStatus {
  double profile_speed = 0.0;    ///< m/s, from the target-speed profile
  double reference_speed = 0.0;  ///< m/s, the profile limited to max_accel / max_decel
  double distance = 0.0;         ///< m travelled since the first update
  double lateral = 0.0;          ///< m left of the lane's centre, in the direction of travel
  double remaining = 0.0;        ///< m to the end of an open lane (infinity on closed ones)
};

/// Pure pursuit on the lane's centre line for steering and a speed controller (feed-forward
/// from the vehicle model plus PI) following the target-speed profile.
class LaneFollowDriver final : public ScriptedDriver {
 public:
  /// @throws std::invalid_argument for an empty profile or a lane the map lacks.
  LaneFollowDriver(scenario::LaneFollowDriver spec, scenario::VehicleModel model,
                   const map::RoadMap& road_map, LaneRef lane);
  wire::Controls update(const wire::VehicleState& state) override;
  const LaneFollowStatus& status() const { return status_; }

  /// Target speed of the profile at @p at (s or m), linear between points, held at the ends.
  static double profile_speed(const std::vector<scenario::SpeedPoint>& profile, double at);

 private:
  /// @p backward: the car moves tail first (the rear axle leads along the lane).
  double steer_for(const wire::VehicleState& s, const map::Projection& pr, bool backward);
  double drive_accel_max(double speed) const;
  double resistance_accel(double speed) const;

  scenario::LaneFollowDriver spec_;
  scenario::VehicleModel model_;
  const map::Lane* lane_;
  bool against_;
  double max_steer_rad_;
  bool started_ = false;
  std::int64_t last_ns_ = 0;
  double reference_ = 0.0;
  double integral_ = 0.0;
  LaneFollowStatus status_;
};

/// The lane a vehicle of the scenario starts in: its lane spawn, or the lane at its pose spawn
/// whose direction is closest to its heading. @throws std::invalid_argument when off every lane.
LaneRef start_lane(const scenario::Vehicle& vehicle, const map::RoadMap& road_map);

/// The scripted driver named by the vehicle's `driver` field; empty for a human driver.
std::unique_ptr<ScriptedDriver> make_scripted_driver(const scenario::Vehicle& vehicle,
                                                     const map::RoadMap& road_map);

}  // namespace tb::client
