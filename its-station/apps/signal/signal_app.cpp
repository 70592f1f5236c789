#include "its-station/apps/signal/signal_app.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "its-station/apps/its_time.hpp"

namespace tb::its::apps::signal {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

double seconds_between(clock::WallTime from, clock::WallTime to) {
  return std::chrono::duration<double>(to - from).count();
}

double direction_deg(const LocalPoint& from, const LocalPoint& to) {
  return geodesy::wrap_360(std::atan2(to.x - from.x, to.y - from.y) / kDegToRad);
}

// An end already past (the next SPATEM is late) is a change due now, not a negative time.
std::optional<double> seconds_until(const std::optional<clock::WallTime>& t, clock::WallTime now) {
  if (!t) {
    return std::nullopt;
  }
  return std::max(0.0, seconds_between(now, *t));
}

}  // namespace

SignalApplication::SignalApplication(const clock::Clock& clock, SignalAppConfig cfg,
                                     StatusSink status, WarningSink warning, trace::Tracer* tracer)
    : clock_(clock),
      cfg_(cfg),
      status_sink_(std::move(status)),
      warning_sink_(std::move(warning)),
      tracer_(tracer),
      rlvw_(clock, cfg.rlvw) {}

Expected<MapUpdate, TopologyError> SignalApplication::on_map(IntersectionTopology t) {
  if (auto error = validate(t)) {
    return Unexpected{std::move(*error)};
  }
  if (t.received_at == clock::WallTime{}) {
    t.received_at = clock_.wall_now();  // the wiring gave no reception time: now
  }
  const geodesy::LocalFrame frame({t.ref_latitude_deg, t.ref_longitude_deg, 0.0});
  const auto it = maps_.find(t.intersection_id);
  if (it == maps_.end()) {
    const std::uint16_t id = t.intersection_id;
    maps_.emplace(id, Intersection{std::move(t), frame, IngressLaneMatcher(cfg_.matcher)});
    return MapUpdate::kAdded;
  }
  if (it->second.topology.revision == t.revision) {
    it->second.topology.received_at = t.received_at;
    return MapUpdate::kRefreshed;
  }
  // A new revision: the lanes may have changed, so the match starts afresh.
  it->second.topology = std::move(t);
  it->second.frame = frame;
  it->second.matcher.reset();
  return MapUpdate::kReplaced;
}

void SignalApplication::on_spat(std::uint16_t intersection_id,
                                std::span<const SignalPhase> groups) {
  bool own_group_changed = false;
  for (const SignalPhase& g : groups) {
    const auto key = std::make_pair(intersection_id, g.signal_group);
    SignalPhase p = g;
    if (p.received_at == clock::WallTime{}) {
      p.received_at = clock_.wall_now();
    }
    const auto prev = phases_.find(key);
    if (prev != phases_.end()) {
      const bool changed = prev->second.current.state != g.current.state;
      if (!p.current.start_time) {
        // The onset of a state seen changing is when it was first received; a state that
        // goes on keeps the start it had.
        p.current.start_time = changed ? p.received_at : prev->second.current.start_time;
      }
      if (changed && last_status_ && last_status_->on_lane &&
          last_status_->intersection_id == intersection_id &&
          last_status_->signal_group == g.signal_group) {
        own_group_changed = true;
      }
      prev->second = std::move(p);
    } else {
      phases_.emplace(key, std::move(p));
    }
  }
  if (own_group_changed && last_own_) {
    evaluate(*last_own_, true);
  }
}

void SignalApplication::update(const OwnKinematics& own) {
  if (!std::isfinite(own.latitude_deg) || !std::isfinite(own.longitude_deg) ||
      std::abs(own.latitude_deg) > 90.0 || !std::isfinite(own.heading_deg) ||
      !std::isfinite(own.speed_mps) || own.speed_mps < 0.0 ||
      (own.longitudinal_accel_mps2 && !std::isfinite(*own.longitudinal_accel_mps2))) {
    return;  // not a fix: the last situation stands until a usable one comes
  }
  OwnKinematics k = own;
  if (!k.longitudinal_accel_mps2 && last_own_) {
    // Two fixes 50..500 ms apart give the deceleration a braking driver holds; further apart
    // they say nothing about now.
    const double dt = seconds_between(last_own_->time, k.time);
    if (dt >= 0.05 && dt <= 0.5) {
      k.longitudinal_accel_mps2 = (k.speed_mps - last_own_->speed_mps) / dt;
    }
  }
  last_own_ = k;
  evaluate(k, false);
}

const SignalPhase* SignalApplication::phase(std::uint16_t intersection_id,
                                            std::uint8_t signal_group) const {
  const auto it = phases_.find({intersection_id, signal_group});
  return it == phases_.end() ? nullptr : &it->second;
}

bool SignalApplication::fresh(const SignalPhase* p, clock::WallTime now) const {
  return p != nullptr && seconds_between(p->received_at, now) <= cfg_.max_spat_age_s;
}

std::optional<std::uint8_t> SignalApplication::signal_group_for(const IntersectionTopology& t,
                                                                const GenericLane& lane) {
  std::optional<std::uint8_t> best;
  double best_turn = std::numeric_limits<double>::infinity();
  const double in_deg = direction_deg(lane.nodes[1], lane.nodes[0]);
  for (const Connection& c : lane.connects_to) {
    if (!c.signal_group) {
      continue;
    }
    double turn = 180.0;  // an egress lane the MAPEM does not describe: least likely straight
    const GenericLane* out = t.lane(c.connecting_lane);
    if (out != nullptr && out->nodes.size() >= 2) {
      turn = std::abs(
          geodesy::heading_difference_deg(direction_deg(out->nodes[0], out->nodes[1]), in_deg));
    }
    if (turn < best_turn) {
      best_turn = turn;
      best = c.signal_group;
    }
  }
  return best;
}

std::optional<SignalApplication::OnLane> SignalApplication::match(const OwnKinematics& own,
                                                                  clock::WallTime now) {
  const double age = std::clamp(seconds_between(own.time, now), 0.0, cfg_.max_fix_age_s);
  const double travelled = own.speed_mps * age;
  std::optional<OnLane> best;
  for (auto& [id, in] : maps_) {
    const geodesy::Enu p = in.frame.to_enu({own.latitude_deg, own.longitude_deg, 0.0});
    const LocalPose pose{p.east + travelled * std::sin(own.heading_deg * kDegToRad),
                         p.north + travelled * std::cos(own.heading_deg * kDegToRad),
                         own.heading_deg, own.speed_mps};
    // Every intersection's matcher sees every fix, so that its hysteresis stays current.
    const auto m = in.matcher.update(in.topology, pose);
    if (!m) {
      continue;
    }
    const double d = m->projection.distance_to_stop_line_m;
    const bool better =
        !best || (d >= 0.0 && (best->match.projection.distance_to_stop_line_m < 0.0 ||
                               d < best->match.projection.distance_to_stop_line_m));
    if (better) {
      best = OnLane{id, *m, in.topology.lane(m->lane_id), &in.topology};
    }
  }
  return best;
}

void SignalApplication::evaluate(const OwnKinematics& own, bool state_changed) {
  const clock::WallTime now = clock_.wall_now();
  std::erase_if(maps_, [&](const auto& kv) {
    return seconds_between(kv.second.topology.received_at, now) > cfg_.max_map_age_s;
  });
  std::erase_if(phases_, [&](const auto& kv) {
    return seconds_between(kv.second.received_at, now) > cfg_.max_map_age_s;
  });

  const std::optional<OnLane> on = match(own, now);
  // The group as a plain value (0 = none: SignalGroupID 0 is "not available"); an optional
  // here trips GCC's -Wmaybe-uninitialized.
  const std::uint8_t group =
      on ? signal_group_for(*on->topology, *on->lane).value_or(std::uint8_t{0}) : 0;

  // Within passed_margin_m beyond the line the car is taken to stand at it: GNSS noise around a
  // car waiting at the line must not make it pass and come back.
  const double raw_distance = on ? on->match.projection.distance_to_stop_line_m : 0.0;
  const bool passed = raw_distance < -cfg_.passed_margin_m;
  const double distance = passed ? raw_distance : std::max(0.0, raw_distance);

  std::optional<RlvwWarning> event;
  const SignalPhase* p = nullptr;
  std::vector<PhaseInterval> timeline;
  bool is_fresh = false;
  if (on && group != 0) {
    p = phase(on->intersection_id, group);
    is_fresh = fresh(p, now);
    if (is_fresh) {
      timeline = predict_phases(*p, now);
    }
    RlvwSituation s;
    s.intersection_id = on->intersection_id;
    s.lane_id = on->match.lane_id;
    s.signal_group = group;
    s.distance_to_stop_line_m = distance;
    s.speed_mps = own.speed_mps;
    s.longitudinal_accel_mps2 = own.longitudinal_accel_mps2;
    s.signal_fresh = is_fresh;
    s.timeline = timeline;
    event = rlvw_.evaluate(own.station_id, &s);
  } else {
    event = rlvw_.evaluate(own.station_id, nullptr);
  }
  if (event && warning_sink_) {
    warning_sink_(*event);
  }

  const bool approaching = on && group != 0 && !passed;
  if (!approaching) {
    if (last_status_ && last_status_->on_lane) {
      SignalStatus left;
      left.station_id = own.station_id;
      left.intersection_id = last_status_->intersection_id;
      left.on_lane = false;
      left.time = now;
      emit(left, true);
    }
    return;
  }

  SignalStatus s;
  s.station_id = own.station_id;
  s.intersection_id = on->intersection_id;
  s.on_lane = true;
  s.lane_id = on->match.lane_id;
  s.signal_group = group;
  s.distance_to_stop_line_m = distance;
  s.rlvw = rlvw_.active().has_value();
  s.time = now;
  if (is_fresh) {
    s.state = p->current.state;
    s.time_to_change_s = seconds_until(p->current.min_end_time, now);
    s.likely_time_to_change_s = seconds_until(p->current.likely_time, now);
    const std::optional<double> limit =
        on->lane->speed_limit_mps ? on->lane->speed_limit_mps : on->topology->speed_limit_mps;
    s.advice = glosa_advice(s.distance_to_stop_line_m, limit, timeline, cfg_.glosa);
  }
  const bool force = state_changed || (event && event->event != RlvwEvent::kUpdated) ||
                     !last_status_ || !last_status_->on_lane ||
                     last_status_->intersection_id != s.intersection_id ||
                     last_status_->lane_id != s.lane_id || last_status_->state != s.state;
  if (tracer_ != nullptr && tracer_->enabled()) {
    tracer_->record("its.signal",
                    {{"station", own.station_id},
                     {"intersection", unsigned{s.intersection_id}},
                     {"lane", unsigned{s.lane_id}},
                     {"group", unsigned{s.signal_group}},
                     {"state", static_cast<int>(s.state)},
                     {"spat_ms", p != nullptr ? unix_ms(p->received_at) : std::int64_t{0}},
                     {"dist", s.distance_to_stop_line_m},
                     {"speed", own.speed_mps},
                     {"warn", s.rlvw}});
  }
  emit(s, force);
}

void SignalApplication::emit(const SignalStatus& s, bool force) {
  const clock::SteadyTime now = clock_.steady_now();
  if (!force && last_emit_ && now - *last_emit_ < cfg_.status_min_interval) {
    return;
  }
  last_emit_ = now;
  last_status_ = s;
  if (status_sink_) {
    status_sink_(s);
  }
}

}  // namespace tb::its::apps::signal
