#include "its-station/apps/signal/rlvw.hpp"

#include <algorithm>
#include <cmath>

namespace tb::its::apps::signal {

double stopping_distance_m(double speed_mps, const RlvwConfig& cfg) {
  const double v = std::max(0.0, speed_mps);
  return v * cfg.reaction_time_s + v * v / (2.0 * cfg.comfortable_decel_mps2);
}

RlvwAssessment assess_rlvw(double distance_to_stop_line_m, double speed_mps,
                           const std::vector<PhaseInterval>& timeline, const RlvwConfig& cfg,
                           std::optional<double> longitudinal_accel_mps2) {
  RlvwAssessment a;
  a.distance_to_stop_line_m = distance_to_stop_line_m;
  a.speed_mps = speed_mps;
  a.stopping_distance_m = stopping_distance_m(speed_mps, cfg);
  // A driver braking already needs no reaction time: at the deceleration held, does the car
  // stand before the line? (Without this, every stop at a red line warned in its last
  // metres: the reaction term alone exceeds the distance left.)
  if (longitudinal_accel_mps2 && -*longitudinal_accel_mps2 >= cfg.min_braking_mps2) {
    const double b = -*longitudinal_accel_mps2;
    a.stopping = speed_mps * speed_mps / (2.0 * b) <= distance_to_stop_line_m;
  }
  a.can_stop = a.stopping_distance_m <= distance_to_stop_line_m || a.stopping;
  for (const PhaseInterval& p : timeline) {
    if (aspect(p.state) == Aspect::kStop && p.end_s > 0.0) {
      a.time_to_red_s = std::max(0.0, p.start_s);
      break;
    }
  }
  if (speed_mps < cfg.min_speed_mps || distance_to_stop_line_m < 0.0) {
    return a;  // standing, or already past the line
  }
  a.arrival_s = distance_to_stop_line_m / speed_mps;
  const PhaseInterval* on_arrival = phase_at(timeline, *a.arrival_s);
  if (on_arrival == nullptr) {
    return a;
  }
  a.state_on_arrival = on_arrival->state;
  switch (aspect(on_arrival->state)) {
    case Aspect::kStop:
      a.red_on_arrival = true;
      break;
    case Aspect::kClearance: {
      // Amber is red for a driver who could stop comfortably when it came on (at the same
      // speed, this far further back); an onset not known is taken as now.
      const double onset_s = std::isfinite(on_arrival->start_s) ? on_arrival->start_s : 0.0;
      const double distance_at_onset = distance_to_stop_line_m - speed_mps * onset_s;
      a.red_on_arrival = a.stopping_distance_m <= distance_at_onset;
      break;
    }
    case Aspect::kGo:
    case Aspect::kCaution:
    case Aspect::kUnknown:
      break;
  }
  a.warn = !a.can_stop && a.red_on_arrival;
  return a;
}

std::string_view to_string(RlvwEvent e) {
  switch (e) {
    case RlvwEvent::kRaised:
      return "raised";
    case RlvwEvent::kUpdated:
      return "updated";
    case RlvwEvent::kCleared:
      return "cleared";
  }
  return "raised";
}

std::string_view to_string(RlvwClearReason r) {
  switch (r) {
    case RlvwClearReason::kNone:
      return "none";
    case RlvwClearReason::kStopped:
      return "stopped";
    case RlvwClearReason::kPassed:
      return "passed";
    case RlvwClearReason::kGreen:
      return "green";
    case RlvwClearReason::kLeftLane:
      return "left_lane";
    case RlvwClearReason::kStale:
      return "stale";
  }
  return "none";
}

std::optional<RlvwWarning> Rlvw::evaluate(std::uint32_t station_id, const RlvwSituation* s) {
  const clock::WallTime now = clock_.wall_now();
  last_.reset();
  std::optional<RlvwAssessment> a;
  if (s != nullptr && s->signal_fresh) {
    a = assess_rlvw(s->distance_to_stop_line_m, s->speed_mps, s->timeline, cfg_,
                    s->longitudinal_accel_mps2);
    last_ = a;
  }

  // A situation on another lane says nothing about the warning's own lane.
  auto fill = [&](RlvwWarning& w, bool same_lane) {
    w.updated_at = now;
    if (same_lane) {
      w.distance_to_stop_line_m = s->distance_to_stop_line_m;
      w.speed_mps = s->speed_mps;
      w.stopping_distance_m = stopping_distance_m(s->speed_mps, cfg_);
    }
    if (same_lane && a) {
      w.time_to_red_s = a->time_to_red_s;
    }
  };

  if (active_) {
    RlvwWarning w = *active_;
    const bool same_lane = s != nullptr && s->intersection_id == w.intersection_id &&
                           s->lane_id == w.lane_id && s->signal_group == w.signal_group;
    fill(w, same_lane);
    RlvwClearReason why = RlvwClearReason::kNone;
    if (!same_lane) {
      why = RlvwClearReason::kLeftLane;
    } else if (s->distance_to_stop_line_m < 0.0) {
      why = RlvwClearReason::kPassed;
    } else if (!s->signal_fresh) {
      why = RlvwClearReason::kStale;
    } else if (s->speed_mps < cfg_.min_speed_mps) {
      why = RlvwClearReason::kStopped;
    } else if (!a->red_on_arrival) {
      why = RlvwClearReason::kGreen;
    }
    if (why != RlvwClearReason::kNone) {
      w.event = RlvwEvent::kCleared;
      w.clear_reason = why;
      active_.reset();
    } else {
      w.event = RlvwEvent::kUpdated;
      active_ = w;
    }
    return w;
  }

  if (a && a->warn) {
    RlvwWarning w;
    w.event = RlvwEvent::kRaised;
    w.station_id = station_id;
    w.intersection_id = s->intersection_id;
    w.signal_group = s->signal_group;
    w.lane_id = s->lane_id;
    w.raised_at = now;
    fill(w, true);
    active_ = w;
    return w;
  }
  return std::nullopt;
}

}  // namespace tb::its::apps::signal
