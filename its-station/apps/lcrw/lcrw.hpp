#pragma once
/// @file Longitudinal Collision Risk Warning (LCRW) after ETSI TS 101 539-3.
///
/// A pure decision library: it is handed the own vehicle and the neighbours known from received
/// CAMs (the LDM), in SI units in the local metric frame, and returns warning events. It reads
/// the time from an injected Clock and does no I/O, so tests drive it with a ManualClock.
///
/// Path model (README.md, "LCRW path prediction"): each vehicle follows a circular arc given by
/// what its CAM carries — the curvature from yaw rate and speed (CDD YawRate, Curvature), the
/// speed and longitudinal acceleration along it. A neighbour is projected onto the own predicted
/// arc: the distance along the arc is the gap, the distance off it the lateral offset; its own
/// arc predicts where it will be at the contact instant. A zero curvature is the straight line.

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "common/clock/clock.hpp"
#include "common/geodesy/local_frame.hpp"

namespace tb::its::apps {

/// One vehicle as LCRW sees it. Position is the centre of the vehicle's bounding box on the
/// ground; callers holding a CAM reference position (EN 302 637-2: centre of the front side of
/// the bounding box for vehicles) convert it with centre_from_front_reference().
struct VehicleKinematics {
  std::uint32_t station_id = 0;
  double x = 0.0;  ///< east in the local frame, m
  double y = 0.0;  ///< north in the local frame, m
  /// Orientation of the vehicle, ETSI convention: clockwise from north, [0, 360) degrees.
  double heading_deg = 0.0;
  /// Magnitude of the velocity, m/s (CDD SpeedValue is never negative).
  double speed_mps = 0.0;
  /// CDD DriveDirection backward: the vehicle moves against its heading.
  bool reversing = false;
  /// Longitudinal acceleration along the heading, m/s² (CDD LongitudinalAcceleration; positive
  /// = speeding up when driving forward). Empty when unavailable: constant-speed TTC then.
  std::optional<double> longitudinal_accel_mps2;
  /// Yaw rate, deg/s, positive counter-clockwise (CDD YawRate). Empty when unavailable.
  std::optional<double> yaw_rate_dps;
  /// Curvature of the path, 1/m, positive when the path bends to the left of the orientation
  /// (CDD Curvature, ω / v with v signed along the orientation). Used where the yaw rate is
  /// unavailable or the speed too low to divide by.
  std::optional<double> curvature_per_m;
  double length_m = 4.5;
  double width_m = 1.8;
  /// When this state was valid (CAM generation time / GNSS fix time).
  clock::WallTime time{};
};

/// Converts a position given as the centre of the front side of the bounding box (the CAM
/// reference point, EN 302 637-2 annex B) to the bounding-box centre that LCRW uses.
VehicleKinematics centre_from_front_reference(VehicleKinematics v);

/// Fills x/y from latitude/longitude through the scenario's local frame.
VehicleKinematics with_geodetic_position(VehicleKinematics v, const geodesy::LocalFrame& frame,
                                         double latitude_deg, double longitude_deg);

/// TS 101 539-3 distinguishes the frontal (head-on, opposite directions) and the forward
/// (rear-end, same direction) collision cases.
enum class CollisionCase { kFrontal, kForward };
std::string_view to_string(CollisionCase c);

/// kWarning below ttc_warning_s, kCritical below ttc_critical_s (the driver has about a
/// reaction time left, TS 101 539-3 annex C "minimum time for warning issuing").
enum class Severity { kWarning, kCritical };
std::string_view to_string(Severity s);

enum class WarningEvent { kRaised, kUpdated, kCleared };
std::string_view to_string(WarningEvent e);

/// Why a warning ended; kNone while it is active.
enum class ClearReason { kNone, kRiskEnded, kMovingApart, kLeftPath, kNeighbourLost };
std::string_view to_string(ClearReason r);

struct LcrwWarning {
  WarningEvent event = WarningEvent::kRaised;
  std::uint32_t station_id = 0;        ///< the own station
  std::uint32_t other_station_id = 0;  ///< the neighbour at risk
  CollisionCase collision_case = CollisionCase::kForward;
  Severity severity = Severity::kWarning;
  ClearReason clear_reason = ClearReason::kNone;
  /// Time to collision, s; the last computed value on kCleared (may be infinite).
  double ttc_s = 0.0;
  /// Bumper-to-bumper gap along the own path, m.
  double distance_m = 0.0;
  /// Closing speed along the own path, m/s; positive = approaching.
  double relative_speed_mps = 0.0;
  double lateral_offset_m = 0.0;
  clock::WallTime raised_at{};   ///< when the warning was first raised
  clock::WallTime updated_at{};  ///< when this event was computed
  clock::WallTime own_state_time{};
  clock::WallTime other_state_time{};
};

struct LcrwConfig {
  double ttc_warning_s = 3.0;  ///< raise below this TTC (the thesis's threshold)
  /// Clear only when TTC rises to or above this (hysteresis against flicker); >= ttc_warning_s.
  double ttc_clear_s = 3.5;
  double ttc_critical_s = 1.5;
  /// Beyond this TTC the solver stops looking: no collision within the horizon.
  double horizon_s = 10.0;
  double lane_width_m = 3.5;
  /// Added to the half widths of both vehicles for positioning error; the in-path limit never
  /// exceeds lane_width_m, so that a vehicle centred in the next lane is never in path.
  double lateral_margin_m = 0.5;
  /// Largest angle between the headings (or their opposite) still counted as one path; wider
  /// angles are crossings, which LCRW does not cover (TS 101 539-2 ICRW does).
  double max_heading_difference_deg = 30.0;
  /// Neighbours whose state is older than this are lost (CAMs come at least every 1 s,
  /// EN 302 637-2 T_GenCamMax; two missed CAMs and a margin).
  double max_neighbour_age_s = 2.5;
  /// Warn also for vehicles approaching from behind the own direction of travel. Off by default:
  /// the warning is for the driver who can act on it by braking.
  bool include_vehicles_behind = false;
  /// Use the CAM's longitudinal acceleration for a constant-acceleration TTC.
  bool use_acceleration = true;
  /// Predict curved paths from yaw rate / curvature; false: straight lines along the headings.
  bool use_curvature = true;
  /// Below this speed the curvature is not ω / v (noise over a small number) but the CAM's
  /// Curvature, or straight.
  double min_speed_for_curvature_mps = 1.0;
  /// Tighter paths than this radius are clamped to it (a passenger car's turning circle is
  /// about 5.5 m; tighter values are sensor noise).
  double min_path_radius_m = 5.0;
  /// A neighbour that is in path (warning active) leaves it only when its lateral offset
  /// exceeds the in-path limit by this much (hysteresis against "left path" flicker).
  double lateral_hysteresis_m = 0.5;
};

/// The predicted path of a vehicle: a circular arc (or a line) through its position, tangent to
/// its orientation. Arc lengths s are signed along the orientation (negative behind).
class PredictedPath {
 public:
  /// @p curvature_per_m positive bends left of the orientation @p heading_deg.
  PredictedPath(double x, double y, double heading_deg, double curvature_per_m);

  struct Point {
    double x = 0.0;
    double y = 0.0;
  };
  /// Where a point lies relative to the path: s along it to the nearest point (on the half
  /// circle ahead or behind), offset across it, positive to the right.
  struct Projection {
    double s = 0.0;
    double lateral = 0.0;
  };
  Point at(double s) const;
  /// Orientation of the tangent at @p s, ETSI degrees.
  double heading_at_deg(double s) const;
  Projection project(double x, double y) const;
  double curvature() const { return k_; }

 private:
  double x0_, y0_, h0_, k_;
};

/// The curvature LCRW predicts @p v's path with (VehicleKinematics::yaw_rate_dps over the speed,
/// else curvature_per_m, else 0), clamped to cfg.min_path_radius_m.
double path_curvature(const VehicleKinematics& v, const LcrwConfig& cfg);

/// What LCRW computes for one neighbour, exposed for tests and logs.
struct PairAssessment {
  bool in_path = false;
  bool ahead = false;  ///< in the own direction of travel
  std::optional<CollisionCase> collision_case;
  double longitudinal_offset_m = 0.0;  ///< neighbour centre along the own predicted path
  double lateral_offset_m = 0.0;       ///< neighbour centre off that path, positive = right
  double lateral_at_contact_m = 0.0;   ///< the same where the vehicles meet (its own path)
  double own_curvature_per_m = 0.0;    ///< the own path's curvature used
  double gap_m = 0.0;                  ///< bumper to bumper along the path
  double closing_speed_mps = 0.0;      ///< positive = approaching
  double closing_accel_mps2 = 0.0;
  double ttc_s = 0.0;  ///< infinity when no contact within the horizon
};

/// Earliest t in [0, horizon] at which two bodies moving on a line with constant accelerations,
/// each stopping (not reversing) once its speed reaches zero under braking, close a gap. Speeds
/// and accelerations are along the line; @p gap_m > 0. Returns infinity when they never meet.
double time_to_close(double gap_m, double lead_speed, double lead_accel, double follow_speed,
                     double follow_accel, double horizon_s);

/// Geometry and TTC of one neighbour relative to the own vehicle, both extrapolated to @p now.
/// @p was_in_path: the neighbour is under an active warning (lateral hysteresis applies).
PairAssessment assess(const VehicleKinematics& own, const VehicleKinematics& other,
                      clock::WallTime now, const LcrwConfig& cfg, bool was_in_path = false);

/// Moves a state forward to @p now along its predicted path (an arc of @p curvature_per_m, see
/// path_curvature) with its speed and acceleration (dead reckoning of a CAM that is a few
/// hundred ms old), turning the heading with the arc; never extrapolates a stop into reversing.
VehicleKinematics extrapolate(const VehicleKinematics& v, clock::WallTime now, bool use_accel,
                              double curvature_per_m = 0.0);

/// The LCRW application state machine (TS 101 539-3 annex B): idle per neighbour until the risk
/// appears, active while it lasts, back to idle with a clear event.
class Lcrw {
 public:
  Lcrw(const clock::Clock& clock, LcrwConfig cfg);

  /// Evaluates every neighbour against the own vehicle at the clock's current time and returns
  /// the events: kRaised for a new risk, kUpdated for a risk that persists, kCleared when it
  /// ends (also for a neighbour that is no longer in @p neighbours or is too old).
  std::vector<LcrwWarning> evaluate(const VehicleKinematics& own,
                                    std::span<const VehicleKinematics> neighbours);

  /// The active warnings, by other station id.
  const std::map<std::uint32_t, LcrwWarning>& active() const { return active_; }
  /// What the last evaluate() computed for each neighbour it assessed, by station id.
  const std::map<std::uint32_t, PairAssessment>& last_assessments() const { return assessed_; }
  /// The predicted onset: how long after the last evaluate() the first neighbour without a
  /// warning that is in path ahead and closing reaches ttc_warning_s, its TTC falling one second
  /// per second (both keep their motion); empty when none does. A station evaluates on its fixes
  /// (10 Hz) and the CAMs it receives, so a TTC crosses the threshold between two evaluations
  /// and the warning would come up to a fix period late; evaluating again at the predicted onset
  /// raises it on time (its-station/station/station.cpp).
  std::optional<double> time_to_onset_s() const;
  const LcrwConfig& config() const { return cfg_; }

 private:
  const clock::Clock& clock_;
  LcrwConfig cfg_;
  std::map<std::uint32_t, LcrwWarning> active_;
  std::map<std::uint32_t, PairAssessment> assessed_;
};

}  // namespace tb::its::apps
