#include "its-station/apps/lcrw/lcrw.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <set>

namespace tb::its::apps {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;
constexpr double kEps = 1e-9;

double deg2rad(double d) {
  return d * kPi / 180.0;
}

double seconds_between(clock::WallTime from, clock::WallTime to) {
  return std::chrono::duration<double>(to - from).count();
}

/// A body on a line: position, speed and acceleration along it. Braking ends at standstill
/// instead of turning into reversing, which a plain constant-acceleration model would predict.
struct Motion {
  double speed = 0.0;
  double accel = 0.0;
  /// When the speed reaches zero under braking; infinity if it never does.
  double stop_time() const {
    if (speed * accel < 0.0) {
      return -speed / accel;
    }
    return kInf;
  }
  double distance_at(double t) const {
    const double ts = std::min(t, stop_time());
    return speed * ts + 0.5 * accel * ts * ts;
  }
  double speed_at(double t) const { return t >= stop_time() ? 0.0 : speed + accel * t; }
  double accel_at(double t) const { return t >= stop_time() ? 0.0 : accel; }
};

/// Smallest root of c + b·τ + a·τ² = 0 in [0, limit], or infinity.
double first_root(double a, double b, double c, double limit) {
  if (c <= 0.0) {
    return 0.0;
  }
  double best = kInf;
  if (std::abs(a) < kEps) {
    if (b < 0.0) {
      best = -c / b;
    }
  } else {
    const double disc = b * b - 4.0 * a * c;
    if (disc >= 0.0) {
      // Numerically stable pair of roots (no cancellation between b and the square root).
      const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
      for (const double r : {q / a, std::abs(q) > kEps ? c / q : kInf}) {
        if (r >= 0.0 && r < best) {
          best = r;
        }
      }
    }
  }
  return best <= limit ? best : kInf;
}

}  // namespace

std::string_view to_string(CollisionCase c) {
  switch (c) {
    case CollisionCase::kFrontal:
      return "frontal";
    case CollisionCase::kForward:
      return "forward";
  }
  return "unknown";
}

std::string_view to_string(Severity s) {
  switch (s) {
    case Severity::kWarning:
      return "warning";
    case Severity::kCritical:
      return "critical";
  }
  return "unknown";
}

std::string_view to_string(WarningEvent e) {
  switch (e) {
    case WarningEvent::kRaised:
      return "raised";
    case WarningEvent::kUpdated:
      return "updated";
    case WarningEvent::kCleared:
      return "cleared";
  }
  return "unknown";
}

std::string_view to_string(ClearReason r) {
  switch (r) {
    case ClearReason::kNone:
      return "none";
    case ClearReason::kRiskEnded:
      return "risk_ended";
    case ClearReason::kMovingApart:
      return "moving_apart";
    case ClearReason::kLeftPath:
      return "left_path";
    case ClearReason::kNeighbourLost:
      return "neighbour_lost";
  }
  return "unknown";
}

VehicleKinematics centre_from_front_reference(VehicleKinematics v) {
  const double h = deg2rad(v.heading_deg);
  v.x -= 0.5 * v.length_m * std::sin(h);
  v.y -= 0.5 * v.length_m * std::cos(h);
  return v;
}

VehicleKinematics with_geodetic_position(VehicleKinematics v, const geodesy::LocalFrame& frame,
                                         double latitude_deg, double longitude_deg) {
  geodesy::Geodetic g{};
  g.latitude_deg = latitude_deg;
  g.longitude_deg = longitude_deg;
  g.altitude_m = frame.origin().altitude_m;
  const geodesy::Enu p = frame.to_enu(g);
  v.x = p.east;
  v.y = p.north;
  return v;
}

double time_to_close(double gap_m, double lead_speed, double lead_accel, double follow_speed,
                     double follow_accel, double horizon_s) {
  if (gap_m <= 0.0) {
    return 0.0;
  }
  const Motion lead{lead_speed, lead_accel};
  const Motion follow{follow_speed, follow_accel};
  // Between the instants where either body stops, the gap is a quadratic in time.
  std::array<double, 4> cuts{0.0, lead.stop_time(), follow.stop_time(), horizon_s};
  std::sort(cuts.begin(), cuts.end());
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double t0 = cuts[i];
    const double t1 = std::min(cuts[i + 1], horizon_s);
    if (t0 >= horizon_s) {
      break;
    }
    if (t1 <= t0) {
      continue;
    }
    const double g0 = gap_m + lead.distance_at(t0) - follow.distance_at(t0);
    const double b = lead.speed_at(t0) - follow.speed_at(t0);
    const double a = 0.5 * (lead.accel_at(t0) - follow.accel_at(t0));
    const double tau = first_root(a, b, g0, t1 - t0);
    if (std::isfinite(tau)) {
      return t0 + tau;
    }
  }
  return kInf;
}

PredictedPath::PredictedPath(double x, double y, double heading_deg, double curvature_per_m)
    : x0_(x), y0_(y), h0_(deg2rad(heading_deg)), k_(curvature_per_m) {}

PredictedPath::Point PredictedPath::at(double s) const {
  // Forward is (sin h, cos h) in (east, north), left of it (-cos h, sin h).
  const double fx = std::sin(h0_), fy = std::cos(h0_);
  const double lx = -fy, ly = fx;
  double along = s, across = 0.0;  // along the initial orientation, to its left
  if (k_ != 0.0) {
    along = std::sin(k_ * s) / k_;
    across = (1.0 - std::cos(k_ * s)) / k_;
  }
  return {x0_ + along * fx + across * lx, y0_ + along * fy + across * ly};
}

double PredictedPath::heading_at_deg(double s) const {
  // Heading grows clockwise, a left bend (k > 0) turns the tangent counter-clockwise.
  return geodesy::wrap_360((h0_ - k_ * s) * 180.0 / kPi);
}

PredictedPath::Projection PredictedPath::project(double x, double y) const {
  const double fx = std::sin(h0_), fy = std::cos(h0_);
  const double rx = fy, ry = -fx;  // right of the orientation
  const double dx = x - x0_, dy = y - y0_;
  if (k_ == 0.0) {
    return {dx * fx + dy * fy, dx * rx + dy * ry};
  }
  // The centre lies 1/k to the left (to the right for k < 0, where 1/k is negative).
  const double cx = x0_ - rx / k_, cy = y0_ - ry / k_;
  const double ax = x0_ - cx, ay = y0_ - cy;  // centre -> start
  const double wx = x - cx, wy = y - cy;      // centre -> point
  const double radius = 1.0 / std::abs(k_);
  const double dist = std::hypot(wx, wy);
  // Angle swept from the start to the point, counter-clockwise positive; the path runs
  // counter-clockwise round the centre for k > 0, clockwise for k < 0, so s = angle / k.
  const double angle = std::atan2(ax * wy - ay * wx, ax * wx + ay * wy);
  // Outside the circle is right of a left bend and left of a right bend.
  return {angle / k_, (k_ > 0.0 ? 1.0 : -1.0) * (dist - radius)};
}

double path_curvature(const VehicleKinematics& v, const LcrwConfig& cfg) {
  if (!cfg.use_curvature) {
    return 0.0;
  }
  double k = 0.0;
  const double u = v.reversing ? -v.speed_mps : v.speed_mps;  // along the orientation
  if (v.yaw_rate_dps && std::abs(u) >= cfg.min_speed_for_curvature_mps) {
    k = deg2rad(*v.yaw_rate_dps) / u;
  } else if (v.curvature_per_m) {
    k = *v.curvature_per_m;
  }
  if (!std::isfinite(k)) {
    return 0.0;
  }
  const double k_max = 1.0 / std::max(cfg.min_path_radius_m, 0.1);
  return std::clamp(k, -k_max, k_max);
}

VehicleKinematics extrapolate(const VehicleKinematics& v, clock::WallTime now, bool use_accel,
                              double curvature_per_m) {
  const double dt = seconds_between(v.time, now);
  if (dt <= 0.0) {
    return v;
  }
  const double u = v.reversing ? -v.speed_mps : v.speed_mps;
  const double a = use_accel ? v.longitudinal_accel_mps2.value_or(0.0) : 0.0;
  const Motion m{u, a};
  const double s = m.distance_at(dt);
  const double u1 = m.speed_at(dt);
  VehicleKinematics out = v;
  const PredictedPath path(v.x, v.y, v.heading_deg, curvature_per_m);
  const PredictedPath::Point p = path.at(s);
  out.x = p.x;
  out.y = p.y;
  out.heading_deg = path.heading_at_deg(s);
  out.speed_mps = std::abs(u1);
  out.reversing = u1 < 0.0 || (u1 == 0.0 && v.reversing);
  if (m.accel_at(dt) == 0.0 && out.longitudinal_accel_mps2) {
    out.longitudinal_accel_mps2 = 0.0;
  }
  out.time = now;
  return out;
}

PairAssessment assess(const VehicleKinematics& own_in, const VehicleKinematics& other_in,
                      clock::WallTime now, const LcrwConfig& cfg, bool was_in_path) {
  const VehicleKinematics own =
      extrapolate(own_in, now, cfg.use_acceleration, path_curvature(own_in, cfg));
  const double k_other = path_curvature(other_in, cfg);
  const VehicleKinematics other = extrapolate(other_in, now, cfg.use_acceleration, k_other);
  PairAssessment r;

  // Where the neighbour is relative to the own predicted path, and how it moves relative to
  // the path's tangent at that place (on a bend the tangent there, not the own heading, is the
  // direction of the road).
  const double k_own = path_curvature(own, cfg);
  r.own_curvature_per_m = k_own;
  const PredictedPath own_path(own.x, own.y, own.heading_deg, k_own);
  const PredictedPath::Projection where = own_path.project(other.x, other.y);
  r.longitudinal_offset_m = where.s;
  r.lateral_offset_m = where.lateral;

  const double dh =
      geodesy::heading_difference_deg(other.heading_deg, own_path.heading_at_deg(where.s));
  if (std::abs(dh) <= cfg.max_heading_difference_deg) {
    r.collision_case = CollisionCase::kForward;
  } else if (std::abs(dh) >= 180.0 - cfg.max_heading_difference_deg) {
    r.collision_case = CollisionCase::kFrontal;
  }

  const double own_dir = own.reversing ? -1.0 : 1.0;
  r.ahead = r.longitudinal_offset_m * own_dir > 0.0;

  // Everything along the own path, signed along the own orientation.
  const double u_own = own_dir * own.speed_mps;
  const double a_own = cfg.use_acceleration ? own.longitudinal_accel_mps2.value_or(0.0) : 0.0;
  const double cos_dh = std::cos(deg2rad(dh));
  const double u_other_own = (other.reversing ? -1.0 : 1.0) * other.speed_mps;
  const double a_other_own =
      cfg.use_acceleration ? other.longitudinal_accel_mps2.value_or(0.0) : 0.0;
  const double u_other = u_other_own * cos_dh;
  const double a_other = a_other_own * cos_dh;

  r.gap_m = std::abs(r.longitudinal_offset_m) - 0.5 * (own.length_m + other.length_m);
  const bool other_in_front = r.longitudinal_offset_m >= 0.0;
  if (other_in_front) {
    r.closing_speed_mps = u_own - u_other;
    r.closing_accel_mps2 = a_own - a_other;
  } else {
    r.closing_speed_mps = u_other - u_own;
    r.closing_accel_mps2 = a_other - a_own;
  }

  // Overlapping along the path means side by side (or already in contact): no longitudinal
  // collision lies ahead of them.
  r.lateral_at_contact_m = r.lateral_offset_m;
  if (!r.collision_case || r.gap_m <= 0.0) {
    r.ttc_s = kInf;
    return r;
  }
  r.ttc_s = other_in_front ? time_to_close(r.gap_m, u_other, a_other, u_own, a_own, cfg.horizon_s)
                           : time_to_close(r.gap_m, u_own, a_own, u_other, a_other, cfg.horizon_s);

  // The vehicles can touch only if their bodies overlap across the path; the margin covers
  // positioning error, the lane width caps it so that the next lane is never in path. The
  // offset must hold now and where the vehicles meet (the neighbour moved along its own
  // predicted path to that instant), so that heading noise over a long gap does not pull an
  // oncoming car in the next lane into the path. A neighbour already in path keeps a wider
  // limit (hysteresis), so that noise at the edge does not flicker the warning.
  double limit =
      std::min(0.5 * (own.width_m + other.width_m) + cfg.lateral_margin_m, cfg.lane_width_m);
  if (was_in_path) {
    limit = std::min(limit + cfg.lateral_hysteresis_m, cfg.lane_width_m);
  }
  if (std::isfinite(r.ttc_s)) {
    const auto contact = std::chrono::duration_cast<clock::WallTime::duration>(
        std::chrono::duration<double>(r.ttc_s));
    const VehicleKinematics other_then =
        extrapolate(other, now + contact, cfg.use_acceleration, k_other);
    r.lateral_at_contact_m = own_path.project(other_then.x, other_then.y).lateral;
  }
  r.in_path = std::abs(r.lateral_offset_m) <= limit && std::abs(r.lateral_at_contact_m) <= limit;
  return r;
}

Lcrw::Lcrw(const clock::Clock& clock, LcrwConfig cfg) : clock_(clock), cfg_(cfg) {
  cfg_.ttc_clear_s = std::max(cfg_.ttc_clear_s, cfg_.ttc_warning_s);
}

std::vector<LcrwWarning> Lcrw::evaluate(const VehicleKinematics& own,
                                        std::span<const VehicleKinematics> neighbours) {
  const clock::WallTime now = clock_.wall_now();
  std::vector<LcrwWarning> events;
  assessed_.clear();  // afterwards: the neighbours seen, fresh enough to assess

  auto clear = [&](LcrwWarning w, ClearReason why) {
    w.event = WarningEvent::kCleared;
    w.clear_reason = why;
    w.updated_at = now;
    events.push_back(w);
    active_.erase(w.other_station_id);
  };

  for (const VehicleKinematics& n : neighbours) {
    if (n.station_id == own.station_id) {
      continue;
    }
    if (seconds_between(n.time, now) > cfg_.max_neighbour_age_s) {
      continue;  // lost: cleared below with the absent ones
    }
    const PairAssessment a = assess(own, n, now, cfg_, active_.contains(n.station_id));
    assessed_[n.station_id] = a;
    const bool relevant = a.in_path && (a.ahead || cfg_.include_vehicles_behind);
    const bool moving_apart = a.closing_speed_mps < 0.0;

    LcrwWarning w;
    w.station_id = own.station_id;
    w.other_station_id = n.station_id;
    w.collision_case = a.collision_case.value_or(CollisionCase::kForward);
    w.ttc_s = a.ttc_s;
    w.distance_m = a.gap_m;
    w.relative_speed_mps = a.closing_speed_mps;
    w.lateral_offset_m = a.lateral_offset_m;
    w.severity = a.ttc_s < cfg_.ttc_critical_s ? Severity::kCritical : Severity::kWarning;
    w.updated_at = now;
    w.own_state_time = own.time;
    w.other_state_time = n.time;

    const auto it = active_.find(n.station_id);
    if (it != active_.end()) {
      w.raised_at = it->second.raised_at;
      if (!relevant) {
        clear(w, ClearReason::kLeftPath);
      } else if (moving_apart) {
        clear(w, ClearReason::kMovingApart);
      } else if (!(a.ttc_s < cfg_.ttc_clear_s)) {
        clear(w, ClearReason::kRiskEnded);
      } else {
        w.event = WarningEvent::kUpdated;
        it->second = w;
        events.push_back(w);
      }
    } else if (relevant && !moving_apart && a.ttc_s < cfg_.ttc_warning_s) {
      w.event = WarningEvent::kRaised;
      w.raised_at = now;
      active_.emplace(n.station_id, w);
      events.push_back(w);
    }
  }

  std::vector<std::uint32_t> lost;
  for (const auto& [id, w] : active_) {
    if (!assessed_.contains(id)) {
      lost.push_back(id);
    }
  }
  for (const std::uint32_t id : lost) {
    clear(active_.at(id), ClearReason::kNeighbourLost);
  }
  return events;
}

std::optional<double> Lcrw::time_to_onset_s() const {
  std::optional<double> first;
  for (const auto& [id, a] : assessed_) {
    const bool relevant = a.in_path && (a.ahead || cfg_.include_vehicles_behind);
    if (active_.contains(id) || !relevant || !(a.closing_speed_mps > 0.0) ||
        !std::isfinite(a.ttc_s) || a.ttc_s < cfg_.ttc_warning_s) {
      continue;
    }
    const double t = a.ttc_s - cfg_.ttc_warning_s;
    if (!first || t < *first) {
      first = t;
    }
  }
  return first;
}

}  // namespace tb::its::apps
