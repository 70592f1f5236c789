#pragma once
/// @file CAM generation frequency management, EN 302 637-2 V1.4.1 clause 6.1.3, without I/O:
/// given the time and the newest fix, is a CAM due, and why?

#include <cstdint>
#include <optional>
#include <string_view>

#include "common/clock/clock.hpp"
#include "common/scenario/scenario.hpp"
#include "its-station/facilities/position.hpp"

namespace tb::its::facilities {

using namespace std::chrono_literals;

/// Parameters of clause 6.1.3 (names as in the standard).
struct CamTiming {
  clock::Duration T_GenCamMin = 100ms;
  clock::Duration T_GenCamMax = 1000ms;
  /// Without DCC (no access-layer congestion control here) T_GenCam_Dcc = T_GenCamMin.
  clock::Duration T_GenCam_Dcc = 100ms;
  /// Period of the generation check; the standard asks T_CheckCamGen ≤ T_GenCamMin.
  clock::Duration T_CheckCamGen = 100ms;
  int N_GenCam = 3;
  /// GNSS epochs jitter around their grid: a fix that arrived at most this long before a
  /// time-triggered CAM falls due is taken as the fix of that instant. And at T_GenCamMax, where
  /// the CAM cannot wait for the next fix, the check waits this long past the due instant for
  /// the fix that is due then (a CAM 1000 ms after one made on a fix is due the very instant the
  /// tenth fix after it is). That wait also brings a CAM grid lying off the fixes (a standing
  /// car's 1 s CAMs after a late first fix) onto them, 10 ms per CAM: made at the due instant
  /// instead, such CAMs would carry a fix up to 100 ms old for as long as the car stands
  /// (tried: frontal scenario, state → CAM p99 170 ms instead of 106–160 ms).
  clock::Duration fresh_fix_wait = 10ms;
  /// Low-frequency container: in the first CAM, then when this much time has passed (B.3.5).
  clock::Duration lf_interval = 500ms;
  /// Special-vehicle container: the same rule, its own clock (clause 6.1.3: in the first CAM,
  /// then when 500 ms or more have passed since the last CAM that carried it).
  clock::Duration special_vehicle_interval = 500ms;
  /// Thresholds of condition 1.
  double heading_threshold_deg = 4.0;
  double position_threshold_m = 4.0;
  double speed_threshold_mps = 0.5;
};

enum class CamTrigger : std::uint8_t {
  kNone,
  kFirst,     ///< first CAM after start (or after the fix came back)
  kHeading,   ///< condition 1: heading changed > 4°
  kPosition,  ///< condition 1: moved > 4 m
  kSpeed,     ///< condition 1: speed changed > 0.5 m/s
  kTime,      ///< condition 2: T_GenCam elapsed
  kFixed,     ///< fixed policy: its constant period elapsed
};
std::string_view to_string(CamTrigger t);

/// State of clause 6.1.3 between CAMs. check() is pure; generated() records a CAM.
class CamRules {
 public:
  CamRules(CamTiming timing, scenario::CamPolicy policy);

  /// The reason a CAM is due at @p now with @p fix as the newest fix, or kNone.
  CamTrigger check(clock::SteadyTime now, const PositionFix& fix) const;
  /// Records that a CAM was generated at @p now from @p fix for @p why; updates T_GenCam.
  void generated(clock::SteadyTime now, const PositionFix& fix, CamTrigger why);
  /// Forgets the last CAM (after a fix loss), so the next CAM counts as the first.
  void reset();

  /// Whether the CAM to be generated at @p now carries the low-frequency container.
  bool low_frequency_due(clock::SteadyTime now) const;
  void low_frequency_sent(clock::SteadyTime now) { last_lf_ = now; }
  /// Whether the CAM to be generated at @p now carries the special-vehicle container (for a
  /// station that has one).
  bool special_vehicle_due(clock::SteadyTime now) const;
  void special_vehicle_sent(clock::SteadyTime now) { last_special_ = now; }

  /// The earliest instant a time-based CAM can become due (for the check timer); empty before
  /// the first CAM.
  std::optional<clock::SteadyTime> next_time_due() const;
  /// The latest instant a time-based CAM may wait for a fresh fix (see CaService): one check
  /// period past next_time_due(), never past T_GenCamMax after the last CAM (plus
  /// fresh_fix_wait); empty before the first CAM.
  std::optional<clock::SteadyTime> time_cam_deadline() const;
  /// When the last CAM was generated; empty before the first.
  std::optional<clock::SteadyTime> last_time() const {
    return last_ ? std::optional(last_->time) : std::nullopt;
  }

  clock::Duration T_GenCam() const { return t_gen_cam_; }
  const CamTiming& timing() const { return timing_; }
  const scenario::CamPolicy& policy() const { return policy_; }

 private:
  struct Last {
    clock::SteadyTime time;
    double latitude_deg, longitude_deg;
    std::optional<double> heading_deg;
    std::optional<double> speed_mps;
  };

  CamTiming timing_;
  scenario::CamPolicy policy_;
  std::optional<Last> last_;
  std::optional<clock::SteadyTime> last_lf_;
  std::optional<clock::SteadyTime> last_special_;
  clock::Duration t_gen_cam_;
  int consecutive_time_cams_ = 0;
};

/// Distance between two positions on the WGS84 ellipsoid, m (chord through ECEF; equal to the
/// surface distance to well below a millimetre at the few metres compared here).
double distance_m(double lat1_deg, double lon1_deg, double lat2_deg, double lon2_deg);

}  // namespace tb::its::facilities
