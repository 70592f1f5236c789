#pragma once
/// @file Red Light Violation Warning (RLVW): the use case the SPATEM/MAPEM of ETSI TS 103 301
/// (TLM and RLT services) serve, "signal violation warning" in ETSI TR 102 638's list of
/// basic applications; the decision is issue 34's rule.
///
/// Rule (README.md, "RLVW"), for the vehicle on an ingress lane at distance d before its stop
/// line with speed v:
///   stopping distance  D = v·t_r + v²/(2a),  t_r = 1 s reaction, a = 3 m/s² comfortable;
///                      a vehicle already braking at b stands after v²/(2b) (it has reacted),
///                      and can stop when either distance fits;
///   arrival            t = d / v (constant speed);
///   warn               when D > d (no comfortable stop before the line) and the light is red
///                      on arrival: the group's predicted phase at t is a stop phase (red,
///                      red+amber, flashing red), or amber that counts as red — amber the car
///                      could have stopped for comfortably when it came on (D ≤ its distance
///                      then, at the same speed).
/// The phases come from phase_timeline.hpp (likelyTime, else the safe-side bound); a phase
/// whose end is unknown lasts, and an arrival beyond what is known is not red.

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "common/clock/clock.hpp"
#include "its-station/apps/signal/phase_timeline.hpp"

namespace tb::its::apps::signal {

struct RlvwConfig {
  double reaction_time_s = 1.0;         ///< t_r (issue 34)
  double comfortable_decel_mps2 = 3.0;  ///< a (issue 34)
  /// Below this speed the vehicle stands: no arrival, no warning, an active one clears.
  double min_speed_mps = 0.5;
  /// A vehicle decelerating at least this much is already braking: the driver has reacted.
  double min_braking_mps2 = 0.3;
};

/// D = v·t_r + v²/(2a).
double stopping_distance_m(double speed_mps, const RlvwConfig& cfg);

/// The rule applied once, with what it used; for tests, logs and the `signal` message.
struct RlvwAssessment {
  double distance_to_stop_line_m = 0.0;
  double speed_mps = 0.0;
  double stopping_distance_m = 0.0;
  /// D ≤ d, or already braking hard enough to stand before the line (v²/(2b) ≤ d).
  bool can_stop = true;
  /// Braking (deceleration b ≥ min_braking_mps2) so as to stand before the line.
  bool stopping = false;
  std::optional<double> arrival_s;  ///< d / v; none when standing
  /// The phase predicted at the arrival; none when standing or beyond the known timeline.
  std::optional<MovementPhaseState> state_on_arrival;
  bool red_on_arrival = false;
  /// Until the group shows a stop phase: 0 when it does now; none when no stop phase is
  /// predicted within the known timeline.
  std::optional<double> time_to_red_s;
  bool warn = false;
};

/// @p longitudinal_accel_mps2: the vehicle's acceleration along its motion when known
/// (negative = braking).
RlvwAssessment assess_rlvw(double distance_to_stop_line_m, double speed_mps,
                           const std::vector<PhaseInterval>& timeline, const RlvwConfig& cfg,
                           std::optional<double> longitudinal_accel_mps2 = std::nullopt);

enum class RlvwEvent { kRaised, kUpdated, kCleared };
std::string_view to_string(RlvwEvent e);

/// Why a warning ended (MQTT rlvw_warning clear_reason); kNone while it is active.
enum class RlvwClearReason { kNone, kStopped, kPassed, kGreen, kLeftLane, kStale };
std::string_view to_string(RlvwClearReason r);

struct RlvwWarning {
  RlvwEvent event = RlvwEvent::kRaised;
  std::uint32_t station_id = 0;
  std::uint16_t intersection_id = 0;
  std::uint8_t signal_group = 0;
  std::uint8_t lane_id = 0;
  RlvwClearReason clear_reason = RlvwClearReason::kNone;
  double distance_to_stop_line_m = 0.0;
  double speed_mps = 0.0;
  std::optional<double> time_to_red_s;
  double stopping_distance_m = 0.0;
  clock::WallTime raised_at{};
  clock::WallTime updated_at{};
};

/// What the vehicle knows at one fix about the lane it is on.
struct RlvwSituation {
  std::uint16_t intersection_id = 0;
  std::uint8_t lane_id = 0;
  std::uint8_t signal_group = 0;
  double distance_to_stop_line_m = 0.0;  ///< negative once past it
  double speed_mps = 0.0;
  std::optional<double> longitudinal_accel_mps2;  ///< negative = braking; empty: unknown
  /// False when the group's SPATEM is missing or stale: nothing is known about the light.
  bool signal_fresh = false;
  std::vector<PhaseInterval> timeline;
};

/// The warning's life, like LCRW's (TS 101 539-3 annex B): idle until the rule warns, then
/// active — updated at each evaluation while the light is still red on arrival, even when
/// braking has made a stop possible again (the warning is what made the driver brake) — until
/// the vehicle stops, passes the stop line, the light will no longer be red on arrival, it
/// leaves the lane, or the signal data go stale.
class Rlvw {
 public:
  Rlvw(const clock::Clock& clock, RlvwConfig cfg) : clock_(clock), cfg_(cfg) {}

  /// @p s null: not on an ingress lane with a known signal group.
  std::optional<RlvwWarning> evaluate(std::uint32_t station_id, const RlvwSituation* s);

  const std::optional<RlvwWarning>& active() const { return active_; }
  const std::optional<RlvwAssessment>& last_assessment() const { return last_; }
  const RlvwConfig& config() const { return cfg_; }

 private:
  const clock::Clock& clock_;
  RlvwConfig cfg_;
  std::optional<RlvwWarning> active_;
  std::optional<RlvwAssessment> last_;
};

}  // namespace tb::its::apps::signal
