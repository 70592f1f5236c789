#pragma once
/// @file The signal application as a vehicle station runs it: holds the intersections (MAPEM)
/// and signal states (SPATEM) it received, and at every own fix matches the ingress lane, runs
/// RLVW and GLOSA, and hands the `signal` status and the `rlvw_warning` events to the HMI side
/// (MQTT, its-station/apps/mqtt). Clock injected, no I/O.

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "common/clock/clock.hpp"
#include "common/geodesy/local_frame.hpp"
#include "common/trace/tracer.hpp"
#include "common/util/expected.hpp"
#include "its-station/apps/signal/glosa.hpp"
#include "its-station/apps/signal/lane_matcher.hpp"
#include "its-station/apps/signal/rlvw.hpp"
#include "its-station/apps/signal/signal_model.hpp"

namespace tb::its::apps::signal {

struct SignalAppConfig {
  LaneMatcherConfig matcher;
  RlvwConfig rlvw;
  GlosaConfig glosa;
  /// A group's SPATEM older than this is stale: no state, no RLVW, no advice. RSUs send SPATEM
  /// at up to 10 Hz (C-Roads; at least on every change), so 2 s is many lost messages.
  double max_spat_age_s = 2.0;
  /// An intersection whose MAPEM has not been heard for this long is forgotten (MAPEM comes
  /// about once a second while in the RSU's range).
  double max_map_age_s = 30.0;
  /// A car is past its stop line only when more than this beyond it (the GNSS tolerance); up
  /// to it, it stands at the line (distance 0), so that the position noise of a car waiting
  /// there does not make it pass and come back.
  double passed_margin_m = 1.0;
  /// The own fix is moved forward along its heading to now, but never by more than this.
  double max_fix_age_s = 1.0;
  /// Never two regular `signal` messages closer than this: one per own fix (10 Hz), with room
  /// for the fixes' jitter. A change of the own group's state and leaving the lane are sent at
  /// once regardless.
  clock::Duration status_min_interval = std::chrono::milliseconds{90};
};

/// The own vehicle at a fix, geodetic.
struct OwnKinematics {
  std::uint32_t station_id = 0;
  /// The point the stop-line distance is measured from: the vehicle's front (CAM reference
  /// point), not its centre.
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double heading_deg = 0.0;  ///< ETSI
  double speed_mps = 0.0;
  /// Along the motion, negative = braking (CAN / CDD LongitudinalAcceleration). Empty: the
  /// application estimates it from the speeds of consecutive fixes.
  std::optional<double> longitudinal_accel_mps2;
  clock::WallTime time{};  ///< the fix time
};

/// The MQTT `signal` message's content (its/<id>/app/signal).
struct SignalStatus {
  std::uint32_t station_id = 0;
  std::uint16_t intersection_id = 0;
  /// False: the vehicle has just left the ingress lane ("lane": null); only the intersection
  /// id is meaningful then.
  bool on_lane = false;
  std::uint8_t lane_id = 0;
  std::uint8_t signal_group = 0;
  MovementPhaseState state = MovementPhaseState::kUnavailable;  ///< unavailable when stale
  std::optional<double> time_to_change_s;                       ///< minEndTime − now
  std::optional<double> likely_time_to_change_s;                ///< likelyTime − now
  double distance_to_stop_line_m = 0.0;
  std::optional<SpeedAdvice> advice;
  bool rlvw = false;  ///< a red light violation warning is active
  clock::WallTime time{};
};

enum class MapUpdate { kAdded, kReplaced, kRefreshed };

class SignalApplication {
 public:
  using StatusSink = std::function<void(const SignalStatus&)>;
  using WarningSink = std::function<void(const RlvwWarning&)>;

  /// @p tracer (may be null): an `its.signal` record per evaluation on a lane
  /// (docs/tracing.md).
  SignalApplication(const clock::Clock& clock, SignalAppConfig cfg, StatusSink status,
                    WarningSink warning, trace::Tracer* tracer = nullptr);

  /// A decoded MAPEM's intersection: a new revision replaces the geometry (and the lane
  /// match), the same one only refreshes it. Refused, with the lane and field named, when
  /// validate() finds it unusable; the intersection held before is kept then. A topology
  /// without `received_at` is taken as received now (so are SPAT groups without one).
  Expected<MapUpdate, TopologyError> on_map(IntersectionTopology t);

  /// A decoded SPATEM's signal groups of one intersection. A state the application has not
  /// seen the group in before gets its start time (when missing) from this reception. If the
  /// group of the own lane changes state, the situation is evaluated again at once (from the
  /// last fix), so that the change reaches the HMI without waiting for the next fix.
  void on_spat(std::uint16_t intersection_id, std::span<const SignalPhase> groups);

  /// At every own fix. A fix with a non-finite or impossible value is ignored.
  void update(const OwnKinematics& own);

  /// The signal group that governs @p lane for a vehicle going straight on: the connection
  /// whose egress lane leaves closest to the ingress lane's direction (no route is known); the
  /// only one when all connections share a group. Empty when no connection is signalised.
  static std::optional<std::uint8_t> signal_group_for(const IntersectionTopology& t,
                                                      const GenericLane& lane);

  const std::optional<SignalStatus>& last_status() const { return last_status_; }
  const Rlvw& rlvw() const { return rlvw_; }
  std::size_t intersections() const { return maps_.size(); }
  const SignalPhase* phase(std::uint16_t intersection_id, std::uint8_t signal_group) const;

 private:
  struct Intersection {
    IntersectionTopology topology;
    geodesy::LocalFrame frame;
    IngressLaneMatcher matcher;
  };
  struct OnLane {
    std::uint16_t intersection_id = 0;
    LaneMatch match;
    const GenericLane* lane = nullptr;
    const IntersectionTopology* topology = nullptr;
  };

  void evaluate(const OwnKinematics& own, bool state_changed);
  std::optional<OnLane> match(const OwnKinematics& own, clock::WallTime now);
  bool fresh(const SignalPhase* p, clock::WallTime now) const;
  void emit(const SignalStatus& s, bool force);

  const clock::Clock& clock_;
  SignalAppConfig cfg_;
  StatusSink status_sink_;
  WarningSink warning_sink_;
  trace::Tracer* tracer_;
  Rlvw rlvw_;
  std::map<std::uint16_t, Intersection> maps_;
  std::map<std::pair<std::uint16_t, std::uint8_t>, SignalPhase> phases_;
  std::optional<OwnKinematics> last_own_;    ///< with the acceleration filled in
  std::optional<SignalStatus> last_status_;  ///< the last one emitted
  std::optional<clock::SteadyTime> last_emit_;
};

}  // namespace tb::its::apps::signal
