#include "sim-client/driver/scripted_driver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "common/geodesy/local_frame.hpp"

namespace tb::client {
namespace {

constexpr double kGravity = 9.81;
constexpr double kAirDensity = 1.2;
// Pure pursuit look-ahead: a time gap with a floor, so that the path stays smooth at low speed
// and the car does not cut corners at high speed.
constexpr double kLookaheadTime = 0.8;  // s
constexpr double kLookaheadMin = 4.0;   // m
constexpr double kLookaheadMax = 40.0;  // m
// Speed controller gains on top of the model feed-forward (acceleration per m/s of error).
constexpr double kSpeedP = 1.5;
constexpr double kSpeedI = 0.3;
constexpr double kIntegralLimit = 4.0;  // m/s·s, anti-windup
// Keeps the car still once the profile asks for 0: a light pedal, as a driver holds at a stop.
constexpr double kHoldBrake = 0.3;
constexpr double kStandstill = 0.2;  // m/s
// Stop short of the end of an open lane rather than run off the road.
constexpr double kEndMargin = 5.0;     // m
constexpr double kStopPlanning = 0.7;  // fraction of max_decel a planned stop uses

wire::Controls to_controls(const scenario::ControlStep& c) {
  wire::Controls out;
  out.throttle = static_cast<float>(c.throttle);
  out.brake = static_cast<float>(c.brake);
  out.steer = static_cast<float>(c.steer);
  out.reverse = c.reverse;
  out.handbrake = c.handbrake;
  return out;
}

double sim_seconds(const wire::VehicleState& s) {
  return static_cast<double>(s.sim_time_ns) * 1e-9;
}

}  // namespace

TimelineDriver::TimelineDriver(scenario::TimelineDriver spec) : steps_(std::move(spec.steps)) {
  std::stable_sort(steps_.begin(), steps_.end(),
                   [](const auto& a, const auto& b) { return a.t < b.t; });
}

wire::Controls TimelineDriver::at(double t) const {
  const auto it =
      std::upper_bound(steps_.begin(), steps_.end(), t,
                       [](double v, const scenario::ControlStep& c) { return v < c.t; });
  if (it == steps_.begin())
    return {};
  return to_controls(*std::prev(it));
}

wire::Controls TimelineDriver::update(const wire::VehicleState& state) {
  return at(sim_seconds(state));
}

LaneFollowDriver::LaneFollowDriver(scenario::LaneFollowDriver spec, scenario::VehicleModel model,
                                   const map::RoadMap& road_map, LaneRef lane)
    : spec_(std::move(spec)),
      model_(std::move(model)),
      lane_(&road_map.lane(lane.road, lane.lane)),
      against_(lane.against),
      max_steer_rad_(model_.max_steer_deg * std::numbers::pi / 180.0) {
  if (spec_.profile.empty())
    throw std::invalid_argument("lane_follow driver needs at least one profile point");
  if (spec_.max_accel <= 0.0 || spec_.max_decel <= 0.0)
    throw std::invalid_argument("lane_follow driver needs max_accel and max_decel > 0");
  if (max_steer_rad_ <= 0.0 || model_.wheelbase_m <= 0.0 || model_.mass_kg <= 0.0)
    throw std::invalid_argument("vehicle model needs max_steer_deg, wheelbase and mass > 0");
}

double LaneFollowDriver::profile_speed(const std::vector<scenario::SpeedPoint>& profile,
                                       double at) {
  if (profile.empty())
    return 0.0;
  if (at <= profile.front().at)
    return profile.front().speed;
  for (std::size_t i = 1; i < profile.size(); ++i) {
    const auto& a = profile[i - 1];
    const auto& b = profile[i];
    if (at <= b.at) {
      if (b.at <= a.at)
        return b.speed;
      return a.speed + (b.speed - a.speed) * (at - a.at) / (b.at - a.at);
    }
  }
  return profile.back().speed;
}

// Peak drive force over the wheels: torque-limited in first gear, power-limited above.
double LaneFollowDriver::drive_accel_max(double speed) const {
  double peak_torque = 0.0, peak_power = 0.0;
  for (const auto& p : model_.torque_curve) {
    peak_torque = std::max(peak_torque, p.torque_nm);
    peak_power = std::max(peak_power, p.torque_nm * p.rpm * 2.0 * std::numbers::pi / 60.0);
  }
  const double first = model_.gear_ratios.empty() ? 1.0 : model_.gear_ratios.front();
  const double force_low = peak_torque * first * model_.final_drive * model_.drivetrain_efficiency /
                           model_.wheel_radius_m;
  const double force_power =
      peak_power * model_.drivetrain_efficiency / std::max(std::abs(speed), 1.0);
  return std::max(std::min(force_low, force_power) / model_.mass_kg, 0.5);
}

double LaneFollowDriver::resistance_accel(double speed) const {
  const double drag =
      0.5 * kAirDensity * model_.drag_coefficient * model_.frontal_area_m2 * speed * speed;
  const double rolling = speed > 0.05 ? model_.rolling_resistance * model_.mass_kg * kGravity : 0;
  return (drag + rolling) / model_.mass_kg;
}

double LaneFollowDriver::steer_for(const wire::VehicleState& s, const map::Projection& pr,
                                   bool backward) {
  // Pure pursuit works from the rear axle; the state's position is the vehicle's centre.
  const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
  const double rx = s.position[0] - c * model_.wheelbase_m / 2.0;
  const double ry = s.position[1] - sn * model_.wheelbase_m / 2.0;
  const double lookahead =
      std::clamp(kLookaheadTime * std::abs(s.speed), kLookaheadMin, kLookaheadMax);
  // Along the lane in the direction of travel: reversing, the target lies behind the rear axle.
  const double dir = (against_ ? -1.0 : 1.0) * (backward ? -1.0 : 1.0);
  double target_s = pr.s + dir * (backward ? lookahead - model_.wheelbase_m / 2.0
                                           : lookahead + model_.wheelbase_m / 2.0);
  // Past the end of an open lane, aim along its extension instead of at its clamped end.
  const double len = map::length(lane_->centre);
  double beyond = 0.0;
  if (!map::is_closed(lane_->centre)) {
    if (target_s > len) {
      beyond = target_s - len;
      target_s = len;
    } else if (target_s < 0.0) {
      beyond = target_s;
      target_s = 0.0;
    }
  }
  const map::Pose tp = map::pose_at(lane_->centre, target_s);
  const double tx = tp.p.x + std::cos(tp.yaw) * beyond;
  const double ty = tp.p.y + std::sin(tp.yaw) * beyond;
  const double dx = tx - rx, dy = ty - ry;
  const double ld = std::max(std::hypot(dx, dy), 1e-3);
  if (backward) {
    // The rear axle leads: the target's angle from the backward direction gives the arc the
    // rear axle must run (positive = left of the direction of travel); backward, a road-wheel
    // angle to the left swings the travel direction to the right, so the sign turns over.
    const double alpha = std::atan2(sn * dx - c * dy, -c * dx - sn * dy);
    const double delta = -std::atan2(2.0 * model_.wheelbase_m * std::sin(alpha), ld);
    return std::clamp(-delta / max_steer_rad_, -1.0, 1.0);
  }
  const double alpha = std::atan2(-sn * dx + c * dy, c * dx + sn * dy);
  // Road-wheel angle of the arc through the target (positive = left); controls steer right.
  const double delta = std::atan2(2.0 * model_.wheelbase_m * std::sin(alpha), ld);
  return std::clamp(-delta / max_steer_rad_, -1.0, 1.0);
}

wire::Controls LaneFollowDriver::update(const wire::VehicleState& s) {
  // The warm-up holds the car on its run-up (sim-server): the script, and the distance its
  // profile counts, start at sim time 0.
  if (s.sim_time_ns < 0)
    return {};
  const double speed = s.speed;
  double dt = 0.0;
  if (!started_) {
    started_ = true;
    reference_ = speed;
  } else {
    dt = std::max(static_cast<double>(s.sim_time_ns - last_ns_) * 1e-9, 0.0);
  }
  last_ns_ = s.sim_time_ns;
  status_.distance += std::abs(speed) * dt;

  const map::Projection pr = map::project(lane_->centre, {s.position[0], s.position[1]});
  status_.lateral = against_ ? -pr.lateral : pr.lateral;
  status_.remaining = std::numeric_limits<double>::infinity();
  double target =
      profile_speed(spec_.profile, spec_.by_distance ? status_.distance : sim_seconds(s));
  status_.profile_speed = target;
  if (!map::is_closed(lane_->centre)) {
    const double len = map::length(lane_->centre);
    // Negative profile speeds reverse (issue 22): the end that matters is then the lane's start.
    const bool back = target < 0.0;
    status_.remaining = (against_ != back) ? pr.s : len - pr.s;
    // The speed from which a stop ends kEndMargin before the end of the lane, planned below
    // max_decel so that the speed controller's lag does not eat the margin.
    const double room = std::max(status_.remaining - kEndMargin, 0.0);
    const double limit = std::sqrt(2.0 * kStopPlanning * spec_.max_decel * room);
    target = back ? std::max(target, -limit) : std::min(target, limit);
  }

  const double previous = reference_;
  if (target > reference_) {
    reference_ = std::min(target, reference_ + spec_.max_accel * dt);
  } else {
    reference_ = std::max(target, reference_ - spec_.max_decel * dt);
  }
  status_.reference_speed = reference_;
  const double feed_forward = dt > 0.0 ? (reference_ - previous) / dt : 0.0;
  const double error = reference_ - speed;
  integral_ = std::clamp(integral_ + error * dt, -kIntegralLimit, kIntegralLimit);
  const double accel = feed_forward + kSpeedP * error + kSpeedI * integral_;
  // Reverse gear while the reference asks for backward motion. The controller works on the
  // speed along the direction of travel; the gearbox engages reverse only near standstill, so
  // a car still rolling the other way brakes and does not press the pedal.
  const bool backward = reference_ < 0.0 || (reference_ == 0.0 && target < 0.0);
  const double dir = backward ? -1.0 : 1.0;
  const double need = dir * accel + resistance_accel(std::abs(speed));

  wire::Controls out;
  out.reverse = backward;
  out.steer = static_cast<float>(steer_for(s, pr, backward && speed < kStandstill));
  if (target * dir <= 0.0 && reference_ * dir <= 0.0 && std::abs(speed) < kStandstill) {
    integral_ = 0.0;
    out.brake = static_cast<float>(kHoldBrake);
    return out;
  }
  const double brake_accel = model_.brake_torque_nm / (model_.wheel_radius_m * model_.mass_kg);
  if (speed * dir < -kStandstill) {
    // Still rolling against the wanted direction: brake it to a stop first.
    out.brake = static_cast<float>(std::clamp(std::abs(accel) / brake_accel, kHoldBrake, 1.0));
    return out;
  }
  if (need >= 0.0) {
    out.throttle = static_cast<float>(std::clamp(need / drive_accel_max(speed), 0.0, 1.0));
  } else {
    out.brake = static_cast<float>(std::clamp(-need / brake_accel, 0.0, 1.0));
  }
  return out;
}

LaneRef start_lane(const scenario::Vehicle& v, const map::RoadMap& road_map) {
  if (const auto* l = std::get_if<scenario::LaneSpawn>(&v.spawn.where))
    return LaneRef{l->road, l->lane, l->against};
  const auto& p = std::get<scenario::PoseSpawn>(v.spawn.where);
  const double yaw = geodesy::heading_deg_to_yaw(p.heading_deg);
  const auto match = road_map.find_lane({p.x, p.y}, yaw);
  if (!match) {
    throw std::invalid_argument("vehicle \"" + v.id + "\": spawn pose is in no lane, so " +
                                "a lane_follow driver has no lane to follow");
  }
  const map::Pose lp = road_map.lane_pose(match->road, match->lane, match->where.s);
  return LaneRef{match->road, match->lane, std::cos(yaw - lp.yaw) < 0.0};
}

std::unique_ptr<ScriptedDriver> make_scripted_driver(const scenario::Vehicle& v,
                                                     const map::RoadMap& road_map) {
  if (const auto* t = std::get_if<scenario::TimelineDriver>(&v.driver))
    return std::make_unique<TimelineDriver>(*t);
  if (const auto* l = std::get_if<scenario::LaneFollowDriver>(&v.driver))
    return std::make_unique<LaneFollowDriver>(*l, v.model, road_map, start_lane(v, road_map));
  return nullptr;
}

}  // namespace tb::client
