#pragma once
/// @file What the station uses of one gpsd report, independent of the libgps API version.
///
/// gpsd_adapter.cpp is the only file that includes <gps.h>: it copies a gps_data_t into a
/// GpsdReport, so every libgps difference (GPSD_API_MAJOR_VERSION) stays there, and the logic
/// below (FixAssembler) is tested with hand-made reports.

#include <cmath>
#include <limits>
#include <optional>

#include "common/clock/clock.hpp"
#include "its-station/facilities/position.hpp"

namespace tb::its::facilities {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// gpsd's fix modes (gps.h MODE_*).
enum class GpsdMode { kNotSeen = 0, kNoFix = 1, k2D = 2, k3D = 3 };

/// A GST report: pseudorange error statistics, 1-sigma, metres (NMEA GST).
struct GpsdGst {
  double semi_major_sigma_m = kNaN;
  double semi_minor_sigma_m = kNaN;
  double orientation_deg = kNaN;  ///< of the semi-major axis, clockwise from true north
  double altitude_sigma_m = kNaN;
};

/// Fields not reported are NaN (libgps's convention); test them with std::isfinite.
struct GpsdReport {
  std::optional<GpsdMode> mode;         ///< set only when the report carried a mode (MODE_SET)
  std::optional<clock::WallTime> time;  ///< fix time, when the report carried one (TIME_SET)
  double latitude_deg = kNaN;
  double longitude_deg = kNaN;
  double altitude_hae_m = kNaN;
  double speed_mps = kNaN;
  double track_deg = kNaN;
  double eph_m = kNaN;  ///< 95 % horizontal error estimate
  double epx_m = kNaN;  ///< 95 % longitude error estimate
  double epy_m = kNaN;  ///< 95 % latitude error estimate
  double epv_m = kNaN;  ///< 95 % vertical error estimate
  double hdop = kNaN;   ///< from SKY reports (DOP_SET)
  std::optional<GpsdGst> gst;
};

/// Confidence model constants (README "Positioning"), exposed for tests.
namespace gnss_model {
/// 1-sigma error of the Doppler range-rate measurement a consumer receiver's velocity comes
/// from, m/s. Velocity error ≈ HDOP × this; typical single-frequency receivers achieve 0.05 m/s.
inline constexpr double kRangeRateSigmaMps = 0.05;
/// 95 % quantile of a 1-D normal distribution, in sigmas.
inline constexpr double k95OneD = 1.959964;
/// 95 % quantile of a 2-D circular normal distribution (sqrt(-2 ln 0.05)), in sigmas.
inline constexpr double k95TwoD = 2.447747;
/// gpsd 3.22 computes eph as HDOP times this (its horizontal UERE for NMEA receivers), so eph
/// recovers the HDOP when no SKY report carried one.
inline constexpr double kGpsdHorizontalUereM = 19.0;
/// Below this speed the course over ground is noise; the heading confidence is "out of range".
inline constexpr double kMinSpeedForHeadingMps = 0.3;
}  // namespace gnss_model

/// Turns the stream of gpsd reports into fixes and losses. Keeps the latest HDOP and GST,
/// which arrive in their own reports (SKY, GST), to qualify the TPVs that follow.
class FixAssembler {
 public:
  enum class Outcome { kNone, kFix, kLoss };

  /// @p received stamps the fix; @p fix is filled when the outcome is kFix.
  Outcome on_report(const GpsdReport& r, clock::SteadyTime received, PositionFix& fix);

 private:
  double hdop_ = kNaN;
  std::optional<GpsdGst> gst_;
  std::optional<clock::SteadyTime> gst_received_;
};

/// Speed confidence (95 %, m/s) from the horizontal DOP, see gnss_model.
double speed_confidence_95(double hdop);
/// Heading confidence (95 %, degrees) of a course derived from a velocity whose per-axis error
/// is @p speed_confidence_mps; 180 when the speed is too low to say anything.
double heading_confidence_95(double speed_mps, double speed_confidence_mps);

}  // namespace tb::its::facilities
