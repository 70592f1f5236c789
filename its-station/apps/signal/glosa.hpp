#pragma once
/// @file Green Light Optimal Speed Advisory (GLOSA; "traffic light optimal speed advisory" in
/// ETSI TR 102 638, served by TS 103 301's SPATEM/MAPEM): the range of constant speeds at which
/// the vehicle reaches its stop line while its light is green.
///
/// Rule (README.md, "GLOSA"): with d the distance to the stop line and a green window [s, e)
/// from the phase timeline (phase_timeline.hpp: s = when the red ends, e = when the green ends,
/// +∞ when unknown), arriving at constant speed v takes t = d / v, and t must lie in
/// [s + margin, e − margin]; so v ∈ [d / (e − margin), d / (s + margin)], intersected with
/// [min_speed, speed limit]. The first window (in time) with a non-empty range is advised;
/// none when no window has one.

#include <optional>
#include <vector>

#include "its-station/apps/signal/phase_timeline.hpp"

namespace tb::its::apps::signal {

struct GlosaConfig {
  /// The speed limit when neither the lane nor the intersection gives one: 50 km/h, the urban
  /// limit in most of Europe.
  double default_max_speed_mps = 50.0 / 3.6;
  /// Below 20 km/h a crawl to the line holds up the traffic behind and is not advised.
  double min_speed_mps = 20.0 / 3.6;
  /// Arrive at least this long after the green begins and before it ends: the SPAT's timing
  /// confidence, the GNSS error over the approach, a driver's imprecise speed, and an
  /// unannounced 1 s red+amber before the green.
  double margin_s = 1.0;
};

/// A span of consecutive go phases (green), seconds from now; end +∞ when unknown.
struct GreenWindow {
  double start_s = 0.0;
  double end_s = kUnknownTime;
};

/// The go phases of @p timeline that are not over, consecutive ones merged.
std::vector<GreenWindow> green_windows(const std::vector<PhaseInterval>& timeline);

struct SpeedAdvice {
  double min_speed_mps = 0.0;
  double max_speed_mps = 0.0;
  GreenWindow window;  ///< the window the range aims at
};

/// The advice for a vehicle @p distance_m before its stop line, or none.
/// @p speed_limit_mps: the lane's (or intersection's) limit; empty: cfg.default_max_speed_mps.
std::optional<SpeedAdvice> glosa_advice(double distance_m, std::optional<double> speed_limit_mps,
                                        const std::vector<PhaseInterval>& timeline,
                                        const GlosaConfig& cfg);

}  // namespace tb::its::apps::signal
