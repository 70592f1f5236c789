#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "common/geodesy/local_frame.hpp"
#include "its-station/facilities/gpsd_report.hpp"

namespace tb::its::facilities {
namespace {

// A GST older than this describes another epoch (receivers send one per fix, at most 10 Hz
// here; 1.5 s tolerates one lost datagram at 1 Hz).
constexpr auto kGstMaxAge = std::chrono::milliseconds{1500};

bool finite_positive(double v) {
  return std::isfinite(v) && v >= 0.0;
}

}  // namespace

double speed_confidence_95(double hdop) {
  return hdop * gnss_model::kRangeRateSigmaMps * gnss_model::k95OneD;
}

double heading_confidence_95(double speed_mps, double speed_confidence_mps) {
  if (!(speed_mps >= gnss_model::kMinSpeedForHeadingMps))
    return 180.0;
  // The cross-track velocity error turns the velocity vector by atan(error / speed).
  const double rad = std::atan2(speed_confidence_mps, speed_mps);
  return std::min(180.0, rad * 180.0 / std::numbers::pi);
}

FixAssembler::Outcome FixAssembler::on_report(const GpsdReport& r, clock::SteadyTime received,
                                              PositionFix& fix) {
  if (finite_positive(r.hdop))
    hdop_ = r.hdop;
  if (r.gst) {
    gst_ = r.gst;
    gst_received_ = received;
  }
  if (!r.mode)
    return Outcome::kNone;
  if (*r.mode == GpsdMode::kNotSeen || *r.mode == GpsdMode::kNoFix)
    return Outcome::kLoss;
  // A TPV with a fix mode but no usable position or time cannot be the reference of a CAM.
  if (!std::isfinite(r.latitude_deg) || !std::isfinite(r.longitude_deg) || !r.time ||
      std::abs(r.latitude_deg) > 90.0 || std::abs(r.longitude_deg) > 180.0)
    return Outcome::kNone;

  fix = PositionFix{};
  fix.time = *r.time;
  fix.received = received;
  fix.latitude_deg = r.latitude_deg;
  fix.longitude_deg = r.longitude_deg;
  if (*r.mode == GpsdMode::k3D && std::isfinite(r.altitude_hae_m))
    fix.altitude_m = r.altitude_hae_m;
  if (finite_positive(r.speed_mps))
    fix.speed_mps = r.speed_mps;
  if (std::isfinite(r.track_deg)) {
    fix.course_deg = geodesy::wrap_360(r.track_deg);
    fix.heading_deg = fix.course_deg;
  }

  // Position ellipse, best source first: the receiver's own error ellipse (GST, 1-sigma),
  // then gpsd's per-axis 95 % estimates, then its 95 % horizontal radius.
  const bool gst_fresh = gst_ && gst_received_ && received - *gst_received_ <= kGstMaxAge &&
                         finite_positive(gst_->semi_major_sigma_m) &&
                         finite_positive(gst_->semi_minor_sigma_m);
  if (gst_fresh) {
    PositionFix::Ellipse e;
    e.semi_major_m = gst_->semi_major_sigma_m * gnss_model::k95TwoD;
    e.semi_minor_m = gst_->semi_minor_sigma_m * gnss_model::k95TwoD;
    const double o = std::isfinite(gst_->orientation_deg) ? gst_->orientation_deg : 0.0;
    e.orientation_deg = std::fmod(std::fmod(o, 180.0) + 180.0, 180.0);
    if (e.semi_minor_m > e.semi_major_m) {
      std::swap(e.semi_major_m, e.semi_minor_m);
      e.orientation_deg = std::fmod(e.orientation_deg + 90.0, 180.0);
    }
    fix.position_confidence = e;
  } else if (finite_positive(r.epx_m) && finite_positive(r.epy_m)) {
    PositionFix::Ellipse e;
    const bool north_major = r.epy_m >= r.epx_m;
    e.semi_major_m = std::max(r.epx_m, r.epy_m);
    e.semi_minor_m = std::min(r.epx_m, r.epy_m);
    e.orientation_deg = north_major ? 0.0 : 90.0;
    fix.position_confidence = e;
  } else if (finite_positive(r.eph_m)) {
    fix.position_confidence = PositionFix::Ellipse{r.eph_m, r.eph_m, 0.0};
  }
  if (fix.altitude_m && finite_positive(r.epv_m))
    fix.altitude_confidence_m = r.epv_m;

  // Speed and heading confidences from the geometry (HDOP), not from gpsd's eps/epd, which are
  // differences between consecutive fixes and meaningless at 10 Hz (REFERENCES.md).
  double hdop = hdop_;
  if (!finite_positive(hdop) && finite_positive(r.eph_m))
    hdop = r.eph_m / gnss_model::kGpsdHorizontalUereM;
  if (finite_positive(hdop) && fix.speed_mps) {
    fix.speed_confidence_mps = speed_confidence_95(hdop);
    if (fix.heading_deg)
      fix.heading_confidence_deg = heading_confidence_95(*fix.speed_mps, *fix.speed_confidence_mps);
  }
  return Outcome::kFix;
}

}  // namespace tb::its::facilities
