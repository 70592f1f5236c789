#pragma once
/// @file A signal group's predicted sequence of phases, from a SPATEM's MovementEvents.
///
/// End of a phase (README.md, "Phase timing"): likelyTime when the SPAT gives one; otherwise the
/// bound on the safe side — minEndTime for a phase that lets traffic go (it may end that early),
/// maxEndTime for one that stops it (it may last that long); without either the phase lasts
/// (its end is unknown, so nothing after it is predicted). After the last event the SPAT lists,
/// the next phase follows the fixed-time cycle (green → amber → red → green; red+amber →
/// green), with an unknown end.

#include <limits>
#include <optional>
#include <vector>

#include "common/clock/clock.hpp"
#include "its-station/apps/signal/signal_model.hpp"

namespace tb::its::apps::signal {

inline constexpr double kUnknownTime = std::numeric_limits<double>::infinity();

/// One phase, times in seconds relative to now (negative: in the past). The current phase
/// starts at -infinity when its start is unknown; a phase with an unknown end ends at +infinity.
struct PhaseInterval {
  MovementPhaseState state = MovementPhaseState::kUnavailable;
  double start_s = -kUnknownTime;
  double end_s = kUnknownTime;
};

/// The end the timeline uses for @p e (see the file comment); empty when unknown.
std::optional<clock::WallTime> estimated_end(const MovementEvent& e);

/// The phase the fixed-time cycle brings after @p s; empty when there is no cycle (flashing,
/// dark, unavailable).
std::optional<MovementPhaseState> next_in_cycle(MovementPhaseState s);

/// The current phase first, then the ones that follow, up to the first with an unknown end.
std::vector<PhaseInterval> predict_phases(const SignalPhase& p, clock::WallTime now);

/// The phase at @p t_s seconds from now; null when the timeline does not reach that far.
const PhaseInterval* phase_at(const std::vector<PhaseInterval>& timeline, double t_s);

}  // namespace tb::its::apps::signal
