#pragma once
/// @file Scripted drivers: controls computed from the vehicle's own state and what it sees of the
/// others, so that a scenario runs with no human at the wheel (scenario field `driver`).

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "common/map/route_plan.hpp"
#include "common/scenario/scenario.hpp"
#include "common/wire/vehicle_state.hpp"
#include "sim-client/driver/drive_map.hpp"
#include "sim-client/driver/lane_path.hpp"

namespace tb::client {

/// Computes the controls for the next tick from the latest state of its vehicle and what it
/// sees of the others. Time is the state's sim time, so a driver runs the same in real time and
/// as fast as possible. A script starts at sim time 0: during the warm-up before it (negative
/// sim time, sim-server holds the car) its controls are released and nothing of its own state
/// moves on.
class ScriptedDriver {
 public:
  virtual ~ScriptedDriver() = default;
  /// @p traffic: every vehicle of the state frame (the own one too), located on the map.
  virtual wire::Controls update(const wire::VehicleState& state, const Traffic& traffic) = 0;
  wire::Controls update(const wire::VehicleState& state) { return update(state, Traffic{}); }
};

/// A control timeline: each step holds from its time until the next step's.
class TimelineDriver final : public ScriptedDriver {
 public:
  explicit TimelineDriver(scenario::TimelineDriver spec);
  wire::Controls update(const wire::VehicleState& state, const Traffic& traffic) override;
  using ScriptedDriver::update;
  /// The controls in effect at @p sim_time_s (all released before the first step).
  wire::Controls at(double sim_time_s) const;

 private:
  std::vector<scenario::ControlStep> steps_;
};

/// What bounds the lane follower's target speed.
enum class SpeedLimit { kProfile, kCurve, kEnd, kLeader, kJunction, kLaneChange, kSignal };

/// What the lane-following driver computed in its last update, for tests and the view.
struct LaneFollowStatus {
  double profile_speed = 0.0;    ///< m/s, from the target-speed profile
  double target_speed = 0.0;     ///< m/s, the profile bounded by curves, ends and traffic
  double reference_speed = 0.0;  ///< m/s, the target limited to max_accel / max_decel
  SpeedLimit limit = SpeedLimit::kProfile;
  double distance = 0.0;   ///< m travelled since the first update
  double lateral = 0.0;    ///< m left of the path's centre line, in the direction of travel
  double curvature = 0.0;  ///< 1/m of the path where the vehicle is (positive: turning left)
  double remaining = std::numeric_limits<double>::infinity();   ///< m to where the path ends
  double leader_gap = std::numeric_limits<double>::infinity();  ///< m, bumper to bumper
  int road = -1;  ///< road index and lane id of the path where the vehicle is
  int lane = 0;
  /// The next traffic light on the path (issue 34): what it shows as this driver reads it, the
  /// distance from the front bumper to its stop line (infinite: no light ahead within the
  /// junction horizon), and whether the driver goes on over it whatever it shows (it decided
  /// to pass an amber, or can no longer stop before a red).
  LightAspect light = LightAspect::kNone;
  double stop_line_gap = std::numeric_limits<double>::infinity();
  bool passing_light = false;
};

/// Pure pursuit on the route's lane centres for steering and a speed controller (feed-forward
/// from the vehicle model plus PI) following the target-speed profile, slowed for curves, the
/// end of the route and, when it yields to traffic, the vehicle ahead, junctions and gaps for
/// lane changes (sim-client/README.md, "Scripted drivers").
class LaneFollowDriver final : public ScriptedDriver {
 public:
  /// @throws std::invalid_argument for an empty profile or bad limits.
  LaneFollowDriver(scenario::LaneFollowDriver spec, scenario::VehicleModel model,
                   const DriveMap& map, map::RoutePlan plan);
  wire::Controls update(const wire::VehicleState& state, const Traffic& traffic) override;
  using ScriptedDriver::update;
  const LaneFollowStatus& status() const { return status_; }
  const LanePath& path() const { return path_; }

  /// Target speed of the profile at @p at (s or m), linear between points, held at the ends.
  static double profile_speed(const std::vector<scenario::SpeedPoint>& profile, double at);

 private:
  double steer_for(const wire::VehicleState& s, bool backward) const;
  double steer_forward(const wire::VehicleState& s, double rx, double ry, double length) const;
  double drive_accel_max(double speed) const;
  double resistance_accel(double speed) const;
  double brake_accel() const;
  /// Bounds of the forward target speed; each lowers @p target and says why.
  void limit_curves(double& target);
  void limit_traffic(const wire::VehicleState& s, const Traffic& traffic, double& target);
  void limit_signals(const wire::VehicleState& s, const Traffic& traffic, double& target);
  double follow_speed(const wire::VehicleState& s, const Traffic& traffic, const Observed* me);
  /// Whether @p o waits at a light that shows it red (or red + amber).
  bool held_by_light(const Traffic& traffic, const Observed& o, std::int64_t sim_time_ns) const;
  bool must_yield(const Traffic& traffic, const Observed* me, std::size_t first_step,
                  std::int64_t sim_time_ns) const;
  bool gap_free(const wire::VehicleState& s, const Traffic& traffic, const Observed* me,
                const LanePath::Step& change) const;

  scenario::LaneFollowDriver spec_;
  scenario::VehicleModel model_;
  const DriveMap* map_;
  LanePath path_;
  double max_steer_rad_;
  bool started_ = false;
  std::int64_t last_ns_ = 0;
  double d_ = 0.0;  ///< where the vehicle is along the path
  double reference_ = 0.0;
  double integral_ = 0.0;
  /// What the driver decided for the light it approaches, kept until that light shows go again
  /// (a decision to stop is not undone by braking having made it harder, nor one to go on).
  struct LightDecision {
    std::uint16_t intersection_id = 0;
    int signal_group = 0;
    bool go_on = false;
    double decel = 0.0;  ///< m/s², the planned stop's deceleration
  };
  std::optional<LightDecision> decision_;
  LaneFollowStatus status_;
};

/// The scripted driver named by the vehicle's `driver` field; empty for a human driver.
/// @throws std::invalid_argument when a lane_follow vehicle starts on no drivable lane, or
/// map::RouteError for a route the map cannot give.
std::unique_ptr<ScriptedDriver> make_scripted_driver(const scenario::Vehicle& vehicle,
                                                     const scenario::Scenario& scenario,
                                                     const DriveMap& map);

}  // namespace tb::client
