#include "its-station/apps/signal/phase_timeline.hpp"

#include <chrono>

namespace tb::its::apps::signal {
namespace {

double seconds_from(clock::WallTime now, clock::WallTime t) {
  return std::chrono::duration<double>(t - now).count();
}

}  // namespace

std::optional<clock::WallTime> estimated_end(const MovementEvent& e) {
  if (e.likely_time) {
    return e.likely_time;
  }
  switch (aspect(e.state)) {
    case Aspect::kStop:
      return e.max_end_time;
    case Aspect::kGo:
    case Aspect::kClearance:
      return e.min_end_time;
    case Aspect::kCaution:
    case Aspect::kUnknown:
      return std::nullopt;
  }
  return std::nullopt;
}

std::optional<MovementPhaseState> next_in_cycle(MovementPhaseState s) {
  switch (s) {
    case MovementPhaseState::kPermissiveMovementAllowed:
      return MovementPhaseState::kPermissiveClearance;
    case MovementPhaseState::kProtectedMovementAllowed:
      return MovementPhaseState::kProtectedClearance;
    case MovementPhaseState::kPermissiveClearance:
    case MovementPhaseState::kProtectedClearance:
      return MovementPhaseState::kStopAndRemain;
    // Red may be followed by red+amber first; GLOSA's arrival margin covers its usual 1 s.
    case MovementPhaseState::kStopAndRemain:
    case MovementPhaseState::kPreMovement:
      return MovementPhaseState::kProtectedMovementAllowed;
    case MovementPhaseState::kStopThenProceed:
    case MovementPhaseState::kCautionConflictingTraffic:
    case MovementPhaseState::kUnavailable:
    case MovementPhaseState::kDark:
      return std::nullopt;
  }
  return std::nullopt;
}

std::vector<PhaseInterval> predict_phases(const SignalPhase& p, clock::WallTime now) {
  std::vector<PhaseInterval> out;
  out.reserve(2 + p.upcoming.size());
  auto push = [&](const MovementEvent& e, double start) {
    PhaseInterval i;
    i.state = e.state;
    i.start_s = start;
    const auto end = estimated_end(e);
    i.end_s = end ? seconds_from(now, *end) : kUnknownTime;
    if (i.end_s < i.start_s) {
      i.end_s = i.start_s;  // inconsistent times: the phase is over as it begins
    }
    out.push_back(i);
    return i.end_s;
  };
  double t = push(p.current,
                  p.current.start_time ? seconds_from(now, *p.current.start_time) : -kUnknownTime);
  for (const MovementEvent& e : p.upcoming) {
    if (t == kUnknownTime) {
      return out;
    }
    t = push(e, t);
  }
  if (t != kUnknownTime) {
    if (const auto next = next_in_cycle(out.back().state)) {
      out.push_back(PhaseInterval{*next, t, kUnknownTime});
    }
  }
  return out;
}

const PhaseInterval* phase_at(const std::vector<PhaseInterval>& timeline, double t_s) {
  for (const PhaseInterval& i : timeline) {
    if (t_s >= i.start_s && t_s < i.end_s) {
      return &i;
    }
  }
  // Before a known start of the current phase: it was already showing when received.
  if (!timeline.empty() && t_s < timeline.front().start_s) {
    return &timeline.front();
  }
  return nullptr;
}

}  // namespace tb::its::apps::signal
