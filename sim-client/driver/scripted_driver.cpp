#include "sim-client/driver/scripted_driver.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace tb::client {
namespace {

constexpr double kGravity = 9.81;
constexpr double kAirDensity = 1.2;
// Pure pursuit look-ahead: a time gap with a floor, so that the path stays smooth at low speed
// and the car does not cut corners at high speed.
constexpr double kLookaheadTime = 0.8;  // s
constexpr double kLookaheadMin = 4.0;   // m
constexpr double kLookaheadMax = 40.0;  // m
constexpr double kSteerLead = 0.25;     // s of travel: where the fed-forward curvature is read
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
// Following (a simple model, sim-client/README.md): keep kMinGap + kTimeGap x speed to the
// vehicle ahead, approaching it at the comfortable deceleration; closer than that, fall back
// to its speed within kRelaxTime. kSideMargin widens this car's path to find what is on it.
constexpr double kMinGap = 2.5;      // m, bumper to bumper at a stop
constexpr double kTimeGap = 1.2;     // s
constexpr double kRelaxTime = 2.0;   // s
constexpr double kSideMargin = 0.3;  // m
// Traffic may demand more than the comfortable deceleration, up to full braking on a dry road
// (or the brakes' limit); a car that cannot stop before a stop line even so goes on.
constexpr double kFullBrake = 8.0;       // m/s²
constexpr double kStopLineMargin = 1.0;  // m between the bumper and a junction's entry
// Lane changes: a free gap of kChangeGap plus what the speeds need, ahead and behind.
constexpr double kChangeGap = 4.0;      // m
constexpr double kChangeClosing = 1.5;  // s per m/s of closing speed
constexpr double kChangeFollow = 0.8;   // s of the follower's speed behind
// Traffic lights (issue 34). An amber is stopped for when the stop needs no more than the
// comfortable deceleration of the red-light warning rule (3 m/s², the RLVW of
// TS 103 301), so that a scripted car and a vehicle station's RLVW judge one amber alike; a
// red is stopped for with up to full braking, and run only by a car that cannot stop before
// its line even so (it would otherwise stand in the junction). The front bumper stops
// kSignalMargin before the stop line.
constexpr double kAmberDecel = 3.0;    // m/s²
constexpr double kSignalMargin = 0.4;  // m
// A stop for a light is begun by the time a driver with kLightReaction of reaction still has
// the comfortable stopping distance left (v·t + v²/(2·kAmberDecel)), as the RLVW rule expects of
// a driver who stops: a scripted car that stopped later, if harder, would be warned by it.
constexpr double kLightReaction = 1.5;  // s (the rule's 1 s, and half a second to show braking)
constexpr double kSignalLagTime = 0.4;  // s

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

wire::Controls TimelineDriver::update(const wire::VehicleState& state, const Traffic&) {
  return at(sim_seconds(state));
}

namespace {
double max_profile_speed(const std::vector<scenario::SpeedPoint>& profile) {
  double v = 0.0;
  for (const auto& p : profile)
    v = std::max(v, std::abs(p.speed));
  return v;
}
}  // namespace

LaneFollowDriver::LaneFollowDriver(scenario::LaneFollowDriver spec, scenario::VehicleModel model,
                                   const DriveMap& map, map::RoutePlan plan)
    : spec_(std::move(spec)),
      model_(std::move(model)),
      map_(&map),
      path_(map, std::move(plan), max_profile_speed(spec_.profile)),
      max_steer_rad_(model_.max_steer_deg * std::numbers::pi / 180.0) {
  if (spec_.profile.empty())
    throw std::invalid_argument("lane_follow driver needs at least one profile point");
  if (spec_.max_accel <= 0.0 || spec_.max_decel <= 0.0 || spec_.max_lateral_accel <= 0.0)
    throw std::invalid_argument(
        "lane_follow driver needs max_accel, max_decel and max_lateral_accel > 0");
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

double LaneFollowDriver::brake_accel() const {
  return model_.brake_torque_nm / (model_.wheel_radius_m * model_.mass_kg);
}

double LaneFollowDriver::steer_for(const wire::VehicleState& s, bool backward) const {
  // Steering works from the rear axle; the state's position is the vehicle's centre.
  const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
  const double rx = s.position[0] - c * model_.wheelbase_m / 2.0;
  const double ry = s.position[1] - sn * model_.wheelbase_m / 2.0;
  const double lookahead =
      std::clamp(kLookaheadTime * std::abs(s.speed), kLookaheadMin, kLookaheadMax);
  if (!backward)
    return steer_forward(s, rx, ry, lookahead);
  // Reversing: pure pursuit to a point on the path behind the rear axle (beyond the path's
  // start, on its first segment extended).
  const double target = d_ - (lookahead - model_.wheelbase_m / 2.0);
  double tx = 0.0, ty = 0.0;
  path_.at(target, tx, ty);
  const double dx = tx - rx, dy = ty - ry;
  const double ld = std::max(std::hypot(dx, dy), 1e-3);
  // The rear axle leads: the target's angle from the backward direction gives the arc the rear
  // axle must run (positive = left of the direction of travel); backward, a road-wheel angle to
  // the left swings the travel direction to the right, so the sign turns over.
  const double alpha = std::atan2(sn * dx - c * dy, -c * dx - sn * dy);
  const double delta = -std::atan2(2.0 * model_.wheelbase_m * std::sin(alpha), ld);
  return std::clamp(-delta / max_steer_rad_, -1.0, 1.0);
}

double LaneFollowDriver::steer_forward(const wire::VehicleState& s, double rx, double ry,
                                       double length) const {
  // Rear-wheel feedback (Samson): the rear axle follows the path with the path's curvature fed
  // forward, so that it keeps to the lane's centre in a curve where pure pursuit would cut the
  // corner (a turn of 6 m radius puts a wheel off a 3 m lane). The gains make the error decay
  // like pure pursuit's with look-ahead @p length: k_e = 2/l², k_theta = 2/l.
  const LanePath::Projection pr = path_.project(rx, ry, d_ - model_.wheelbase_m / 2.0);
  double tx = 1.0, ty = 0.0;
  path_.tangent(pr.d, tx, ty);
  const double theta = std::remainder(s.yaw - std::atan2(ty, tx), 2.0 * std::numbers::pi);
  // Curvature a little ahead: the steering takes a moment to get there.
  const double kappa = path_.curvature(pr.d + std::abs(s.speed) * kSteerLead);
  const double e = pr.lateral;
  const double ke = 2.0 / (length * length), kt = 2.0 / length;
  const double sinc = std::abs(theta) < 1e-6 ? 1.0 : std::sin(theta) / theta;
  const double denom = std::max(1.0 - kappa * e, 0.2);
  const double curvature = kappa * std::cos(theta) / denom - kt * theta - ke * sinc * e;
  // Road-wheel angle of that curvature (positive = left); controls steer right.
  const double delta = std::atan(model_.wheelbase_m * curvature);
  return std::clamp(-delta / max_steer_rad_, -1.0, 1.0);
}

void LaneFollowDriver::limit_curves(double& target) {
  // The speed from which a comfortable deceleration reaches each point ahead no faster than
  // its curvature allows.
  const double b = kStopPlanning * spec_.max_decel;
  const double v = std::max(target, reference_);
  const double horizon = v * v / (2.0 * b) + 10.0;
  const auto& pts = path_.points();
  // Where the vehicle is, then the points ahead.
  const double here = std::abs(path_.curvature(d_));
  if (here > 1e-6 && std::sqrt(spec_.max_lateral_accel / here) < target) {
    target = std::sqrt(spec_.max_lateral_accel / here);
    status_.limit = SpeedLimit::kCurve;
  }
  const std::size_t first = path_.index_at(d_);
  for (std::size_t i = first; i < pts.size() && pts[i].d - d_ <= horizon; ++i) {
    const double k = std::abs(pts[i].curvature);
    if (k < 1e-6)
      continue;
    const double v_curve = std::sqrt(spec_.max_lateral_accel / k);
    const double allowed = std::sqrt(v_curve * v_curve + 2.0 * b * std::max(pts[i].d - d_, 0.0));
    if (allowed < target) {
      target = allowed;
      status_.limit = SpeedLimit::kCurve;
    }
  }
}

double LaneFollowDriver::follow_speed(const wire::VehicleState& s, const Traffic& traffic,
                                      const Observed* me) {
  // The vehicle ahead: the first point of the path ahead where this car's centre would bring
  // it against another vehicle (the other's footprint grown by half this car's width and a
  // margin), found on the path's points and refined between two of them.
  const double v = std::max<double>(s.speed, 0.0);
  const double half_w = model_.width_m / 2.0 + kSideMargin;
  const double half_l = model_.length_m / 2.0;
  const double horizon =
      std::min(150.0, std::max(30.0, v * kTimeGap + v * v / (2.0 * spec_.max_decel) + 30.0));
  const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
  const auto& pts = path_.points();
  const std::size_t i0 = path_.index_at(d_);
  double gap = std::numeric_limits<double>::infinity();
  double lead_speed = 0.0;
  for (const Observed* po :
       traffic.near(s.position[0], s.position[1], horizon + traffic.max_length())) {
    const Observed& o = *po;
    if (&o == me || o.state.station_id == s.station_id)
      continue;
    const double ox = o.state.position[0], oy = o.state.position[1];
    const double dx = ox - s.position[0], dy = oy - s.position[1];
    const double reach = horizon + o.length;
    if (dx * dx + dy * dy > reach * reach)
      continue;
    if (dx * c + dy * sn < -half_l)
      continue;  // behind this car: it is the one to follow
    const double oc = std::cos(o.state.yaw), os = std::sin(o.state.yaw);
    const double ex = o.length / 2.0 + half_w, ey = o.width / 2.0 + half_w;
    const auto hits = [&](double px, double py) {
      const double rx = px - ox, ry = py - oy;
      return std::abs(rx * oc + ry * os) <= ex && std::abs(-rx * os + ry * oc) <= ey;
    };
    for (std::size_t i = i0; i < pts.size() && pts[i].d - d_ <= horizon; ++i) {
      if (!hits(pts[i].x, pts[i].y))
        continue;
      double lo = i > i0 ? pts[i - 1].d : d_, hi = pts[i].d;
      for (int k = 0; k < 8 && hi - lo > 0.05; ++k) {
        const double mid = (lo + hi) / 2.0;
        double mx = 0.0, my = 0.0;
        path_.at(mid, mx, my);
        (hits(mx, my) ? hi : lo) = mid;
      }
      const double g = hi - d_ - half_l;
      if (g < gap) {
        double tx = 0.0, ty = 0.0;
        path_.tangent(hi, tx, ty);
        gap = g;
        lead_speed = std::max(0.0, o.state.velocity[0] * tx + o.state.velocity[1] * ty);
      }
      break;
    }
  }
  status_.leader_gap = gap;
  if (!std::isfinite(gap))
    return std::numeric_limits<double>::infinity();
  if (gap <= kMinGap)
    return 0.0;
  // Keep kMinGap + kTimeGap * speed: approach it braking comfortably, fall back when closer.
  const double excess = gap - kMinGap - kTimeGap * v;
  if (excess >= 0.0)
    return std::sqrt(lead_speed * lead_speed + 2.0 * spec_.max_decel * excess);
  return std::max(0.0, lead_speed + excess / kRelaxTime);
}

bool LaneFollowDriver::held_by_light(const Traffic& traffic, const Observed& o,
                                     std::int64_t sim_time_ns) const {
  if (traffic.lights == nullptr || !o.lane)
    return false;
  const map::odr::SignalApproach* ap =
      map_->scenario_map().signals().approach(o.lane->ref.road, o.lane->ref.lane);
  return ap != nullptr && static_cast<int>(ap->junction) == o.junction &&
         traffic.lights->aspect_of(ap->intersection_id, ap->signal_group, sim_time_ns) ==
             LightAspect::kStop;
}

bool LaneFollowDriver::must_yield(const Traffic& traffic, const Observed* me, std::size_t first,
                                  std::int64_t sim_time_ns) const {
  const auto& steps = path_.steps();
  const int junction = steps[first].junction;
  std::vector<std::size_t> mine;
  for (std::size_t k = first; k < steps.size() && steps[k].junction == junction; ++k)
    mine.push_back(steps[k].node);
  // Seen approaching this junction by the others too: the common priority rule decides.
  // Otherwise (not yet on a lane the others know leads here) this car gives way to everyone.
  const bool seen = me != nullptr && me->junction == junction && !me->inside;
  for (const Observed& o : traffic.vehicles) {
    if (&o == me || o.junction != junction)
      continue;
    bool crosses = false;
    for (std::size_t a : mine) {
      for (std::size_t b : o.junction_lanes)
        crosses = crosses || map_->conflict(a, b);
    }
    if (!crosses)
      continue;
    // One waiting at a red light (red + amber too) does not come: a driver with green counts
    // on that, as at a real junction. Once inside, whoever it is, it is given way to.
    if (!o.inside && held_by_light(traffic, o, sim_time_ns))
      continue;
    if (o.inside || !seen || goes_before(o, *me))
      return true;
  }
  return false;
}

bool LaneFollowDriver::gap_free(const wire::VehicleState& s, const Traffic& traffic,
                                const Observed* me, const LanePath::Step& change) const {
  const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
  const double v = s.speed;
  for (const Observed& o : traffic.vehicles) {
    if (&o == me || !o.lane || o.lane->ref.road != change.road || o.lane->ref.lane != change.lane)
      continue;
    const double along =
        (o.state.position[0] - s.position[0]) * c + (o.state.position[1] - s.position[1]) * sn;
    const double half = (model_.length_m + o.length) / 2.0;
    const double vo = o.state.speed;
    if (along >= 0.0) {
      if (along - half < kChangeGap + std::max(0.0, v - vo) * kChangeClosing)
        return false;
    } else if (-along - half <
               kChangeGap + vo * kChangeFollow + std::max(0.0, vo - v) * kChangeClosing) {
      return false;
    }
  }
  return true;
}

void LaneFollowDriver::limit_traffic(const wire::VehicleState& s, const Traffic& traffic,
                                     double& target) {
  const Observed* me = traffic.find(s.station_id);
  const double b = kStopPlanning * spec_.max_decel;
  const double v = std::max<double>(s.speed, 0.0);
  const double half_l = model_.length_m / 2.0;
  const double follow = follow_speed(s, traffic, me);
  if (follow < target) {
    target = follow;
    status_.limit = SpeedLimit::kLeader;
  }
  // A stop line ahead (the junction entry, the start of a lane change) this car may not pass
  // yet. A car too fast to stop before it brakes all the same (the reference may fall at full
  // braking): it stops a little beyond, or is in the junction by then, where the others can
  // see it and give way. Going on regardless would be a decision the others cannot see.
  const auto stop_at = [&](double line, SpeedLimit why) {
    const double allowed = std::sqrt(2.0 * b * std::max(line - d_, 0.0));
    if (allowed < target) {
      target = allowed;
      status_.limit = why;
    }
  };
  const auto& steps = path_.steps();
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const LanePath::Step& st = steps[k];
    if (st.d1 <= d_)
      continue;
    if (st.d0 - d_ > DriveMap::approach_horizon(v))
      break;
    if (st.junction >= 0) {
      // In the junction (centre past its entry, as the others see it): on through it.
      if (st.d0 <= d_ || (k > 0 && steps[k - 1].junction == st.junction))
        continue;
      if (must_yield(traffic, me, k, s.sim_time_ns))
        stop_at(st.d0 - half_l - kStopLineMargin, SpeedLimit::kJunction);
      break;
    }
    if (st.lane_change() && st.d0 > d_ + 0.5 && !gap_free(s, traffic, me, st)) {
      stop_at(st.d0 - 0.5, SpeedLimit::kLaneChange);
      break;
    }
  }
}

void LaneFollowDriver::limit_signals(const wire::VehicleState& s, const Traffic& traffic,
                                     double& target) {
  status_.light = LightAspect::kNone;
  status_.stop_line_gap = std::numeric_limits<double>::infinity();
  status_.passing_light = false;
  if (!spec_.obey_signals || traffic.lights == nullptr) {
    decision_.reset();
    return;
  }
  const map::odr::SignalLayout& layout = map_->scenario_map().signals();
  if (layout.approaches().empty())
    return;
  const double v = std::max<double>(s.speed, 0.0);
  const double half_l = model_.length_m / 2.0;
  // The next junction entry on the path, and the light over the lane that leads into it.
  const map::odr::SignalApproach* ap = nullptr;
  double line = 0.0;
  const auto& steps = path_.steps();
  for (std::size_t k = 1; k < steps.size(); ++k) {
    const LanePath::Step& st = steps[k];
    const LanePath::Step& in = steps[k - 1];
    if (st.junction < 0 || in.junction == st.junction || st.d1 <= d_)
      continue;
    if (in.d0 - d_ > DriveMap::approach_horizon(v))
      break;
    ap = layout.approach(in.road, in.lane);
    if (ap == nullptr)
      break;  // no light: the junction's priority rules
    // The stop line's d: road s mapped linearly over the step, then the path's nearest point
    // to the line's pose (exact where the lane is curved or offset).
    const double ds = in.s1 - in.s0;
    const double guess =
        std::abs(ds) > 1e-9 ? in.d0 + (ap->stop_s - in.s0) / ds * (in.d1 - in.d0) : in.d1;
    line = path_.project(ap->stop.x, ap->stop.y, guess).d;
    break;
  }
  // Beyond the line with the car's centre: it is in the junction, the light is behind it.
  if (ap == nullptr || line <= d_) {
    decision_.reset();
    return;
  }
  const LightAspect light =
      traffic.lights->aspect_of(ap->intersection_id, ap->signal_group, s.sim_time_ns);
  status_.light = light;
  status_.stop_line_gap = line - d_ - half_l;
  if (decision_ && (decision_->intersection_id != ap->intersection_id ||
                    decision_->signal_group != ap->signal_group))
    decision_.reset();
  if (light == LightAspect::kGo || light == LightAspect::kNone) {
    decision_.reset();
    return;
  }
  const double room = status_.stop_line_gap - kSignalMargin;
  if (!decision_) {
    // The deceleration a stop at the line needs now; a standing car needs none.
    const double need = v < kStandstill ? 0.0
                        : room > 0.0    ? v * v / (2.0 * room)
                                        : std::numeric_limits<double>::infinity();
    const double limit =
        light == LightAspect::kAmber ? kAmberDecel : std::min(kFullBrake, brake_accel());
    LightDecision d;
    d.intersection_id = ap->intersection_id;
    d.signal_group = ap->signal_group;
    d.go_on = need > limit;
    // Planned a little harder than needed, so that the speed controller's lag still stops the
    // car before the line; as gentle as the RLVW rule's early start asks (kLightReaction), else
    // as any other planned stop.
    const double early = v < kStandstill
                             ? kStopPlanning * spec_.max_decel
                             : v * v / (2.0 * (v * kLightReaction + v * v / (2.0 * kAmberDecel)));
    d.decel = std::clamp(need * 1.1, std::min(kStopPlanning * spec_.max_decel, early), kFullBrake);
    decision_ = d;
  }
  if (decision_->go_on) {
    status_.passing_light = true;
    return;
  }
  // The speed controller trails a falling reference (by up to about 1 m/s when the car brakes
  // weaker than its model says): the stop is planned that much earlier, so that the car and
  // not only its reference stops at the line.
  const double lag = std::max(v - reference_, 0.0);
  const double late = lag * kSignalLagTime + lag * lag / (2.0 * decision_->decel);
  const double allowed = std::sqrt(2.0 * decision_->decel * std::max(room - late, 0.0));
  if (allowed < target) {
    target = allowed;
    status_.limit = SpeedLimit::kSignal;
  }
}

wire::Controls LaneFollowDriver::update(const wire::VehicleState& s, const Traffic& traffic) {
  // The warm-up holds the car on its run-up (sim-server): the script, and the distance its
  // profile counts, start at sim time 0.
  if (s.sim_time_ns < 0)
    return {};
  const double speed = s.speed;
  double dt = 0.0;
  if (!started_) {
    started_ = true;
    reference_ = speed;
    d_ = path_.start_d();
  } else {
    dt = std::max(static_cast<double>(s.sim_time_ns - last_ns_) * 1e-9, 0.0);
  }
  last_ns_ = s.sim_time_ns;
  status_.distance += std::abs(speed) * dt;

  const LanePath::Projection pr = path_.project(s.position[0], s.position[1], d_);
  d_ = pr.d;
  double target =
      profile_speed(spec_.profile, spec_.by_distance ? status_.distance : sim_seconds(s));
  status_.profile_speed = target;
  status_.limit = SpeedLimit::kProfile;
  status_.leader_gap = std::numeric_limits<double>::infinity();
  // Enough path ahead for the look-ahead, the stopping distance and the junction horizon;
  // some behind for reversing.
  const double v_max = std::max({std::abs(speed), std::abs(target), std::abs(reference_)});
  path_.extend_to(d_ + std::max(kLookaheadMax, v_max * v_max / spec_.max_decel) +
                  DriveMap::approach_horizon(v_max) + 20.0);
  path_.extend_back_to(d_ - kLookaheadMax - 20.0);
  path_.trim_before(d_ - 100.0);
  status_.lateral = pr.lateral;
  status_.curvature = path_.curvature(d_);
  for (const LanePath::Step& st : path_.steps()) {
    if (st.d1 >= d_) {
      status_.road = st.road;
      status_.lane = st.lane;
      break;
    }
  }

  // Negative profile speeds reverse (issue 22): the end that matters is then the path's start.
  const bool back = target < 0.0;
  status_.remaining = std::numeric_limits<double>::infinity();
  if (back) {
    if (path_.begin_d() > d_ - kLookaheadMax - 20.0)
      status_.remaining = d_ - path_.begin_d();
  } else if (path_.ended()) {
    status_.remaining = path_.end_d() - d_;
  }
  if (std::isfinite(status_.remaining)) {
    // The speed from which a stop ends kEndMargin before the end of a lane (at a goal: on it),
    // planned below max_decel so that the speed controller's lag does not eat the margin.
    const double margin = !back && path_.ends_at_goal() ? 0.0 : kEndMargin;
    const double room = std::max(status_.remaining - margin, 0.0);
    const double limit = std::sqrt(2.0 * kStopPlanning * spec_.max_decel * room);
    if (back) {
      target = std::max(target, -limit);
    } else if (limit < target) {
      target = limit;
      status_.limit = SpeedLimit::kEnd;
    }
  }
  if (!back) {
    limit_curves(target);
    limit_signals(s, traffic, target);
    if (spec_.yield_to_traffic)
      limit_traffic(s, traffic, target);
  }
  status_.target_speed = target;

  const double previous = reference_;
  if (target > reference_) {
    reference_ = std::min(target, reference_ + spec_.max_accel * dt);
  } else {
    // A profile slows at its own pace; a curve, the end of the path or traffic come when they
    // come (a car spawned fast just before a bend or a queue) and may need harder braking.
    const double decel = status_.limit != SpeedLimit::kProfile
                             ? std::max(spec_.max_decel, std::min(kFullBrake, brake_accel()))
                             : spec_.max_decel;
    reference_ = std::max(target, reference_ - decel * dt);
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
  out.steer = static_cast<float>(steer_for(s, backward && speed < kStandstill));
  if (target * dir <= 0.0 && reference_ * dir <= 0.0 && std::abs(speed) < kStandstill) {
    integral_ = 0.0;
    out.brake = static_cast<float>(kHoldBrake);
    return out;
  }
  if (speed * dir < -kStandstill) {
    // Still rolling against the wanted direction: brake it to a stop first.
    out.brake = static_cast<float>(std::clamp(std::abs(accel) / brake_accel(), kHoldBrake, 1.0));
    return out;
  }
  if (need >= 0.0) {
    out.throttle = static_cast<float>(std::clamp(need / drive_accel_max(speed), 0.0, 1.0));
  } else {
    out.brake = static_cast<float>(std::clamp(-need / brake_accel(), 0.0, 1.0));
  }
  return out;
}

std::unique_ptr<ScriptedDriver> make_scripted_driver(const scenario::Vehicle& v,
                                                     const scenario::Scenario& sc,
                                                     const DriveMap& map) {
  if (const auto* t = std::get_if<scenario::TimelineDriver>(&v.driver))
    return std::make_unique<TimelineDriver>(*t);
  const auto* l = std::get_if<scenario::LaneFollowDriver>(&v.driver);
  if (l == nullptr)
    return nullptr;
  const auto start = map::vehicle_start(v, map.scenario_map());
  if (!start) {
    throw std::invalid_argument("vehicle \"" + v.id + "\": spawn is on no drivable lane, so " +
                                "a lane_follow driver has no lane to follow");
  }
  map::RoutePlan plan(map.network(), map.graph(), l->route, *start,
                      map::vehicle_seed(sc.seed, v.station_id));
  return std::make_unique<LaneFollowDriver>(*l, v.model, map, std::move(plan));
}

}  // namespace tb::client
