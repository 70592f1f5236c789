#include "its-station/facilities/cdd_convert.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tb::its::facilities::cdd {
namespace {

long round_to(double v) {
  return std::lround(v);
}

// Clamps before rounding: lround of a value beyond long's range is unspecified.
long round_clamped(double v, long lo, long hi) {
  if (v <= static_cast<double>(lo))
    return lo;
  if (v >= static_cast<double>(hi))
    return hi;
  return std::lround(v);
}

}  // namespace

m::Latitude latitude(double deg) {
  if (!std::isfinite(deg) || std::abs(deg) > 90.0)
    return m::kLatitudeUnavailable;
  return static_cast<m::Latitude>(round_to(deg * 1e7));
}
m::Longitude longitude(double deg) {
  if (!std::isfinite(deg) || std::abs(deg) > 180.0)
    return m::kLongitudeUnavailable;
  return static_cast<m::Longitude>(round_to(deg * 1e7));
}
std::optional<double> latitude_deg(m::Latitude v) {
  if (v == m::kLatitudeUnavailable)
    return std::nullopt;
  return v / 1e7;
}
std::optional<double> longitude_deg(m::Longitude v) {
  if (v == m::kLongitudeUnavailable)
    return std::nullopt;
  return v / 1e7;
}

m::PosConfidenceEllipse confidence_ellipse(const std::optional<PositionFix::Ellipse>& e) {
  m::PosConfidenceEllipse out;
  if (!e)
    return out;
  // SemiAxisLength, cm: 4094 = outOfRange (≥ 40.94 m), 4095 = unavailable. Rounded up so the
  // stated confidence is never smaller than the estimate.
  auto axis = [](double metres) -> m::SemiAxisLength {
    const double cm = std::ceil(metres * 100.0);
    if (!(cm >= 0.0))
      return m::kSemiAxisLengthUnavailable;
    if (cm >= m::kSemiAxisLengthOutOfRange)
      return m::kSemiAxisLengthOutOfRange;
    return static_cast<m::SemiAxisLength>(std::max(1.0, cm));
  };
  out.semiMajorConfidence = axis(e->semi_major_m);
  out.semiMinorConfidence = axis(e->semi_minor_m);
  out.semiMajorOrientation = heading_value(e->orientation_deg);
  return out;
}

m::Altitude altitude(std::optional<double> metres, std::optional<double> confidence_m) {
  m::Altitude out;
  if (metres && std::isfinite(*metres))
    out.altitudeValue =
        static_cast<m::AltitudeValue>(round_clamped(*metres * 100.0, -100000, 800000));
  if (confidence_m && std::isfinite(*confidence_m) && *confidence_m >= 0.0) {
    // The smallest class whose bound covers the estimate (CDD AltitudeConfidence).
    static constexpr double kBounds[] = {0.01, 0.02, 0.05, 0.1,  0.2,  0.5,   1.0,
                                         2.0,  5.0,  10.0, 20.0, 50.0, 100.0, 200.0};
    out.altitudeConfidence = m::AltitudeConfidence::outOfRange;
    for (std::size_t i = 0; i < std::size(kBounds); ++i) {
      if (*confidence_m <= kBounds[i]) {
        out.altitudeConfidence = static_cast<m::AltitudeConfidence>(i);
        break;
      }
    }
  }
  return out;
}

m::ReferencePosition reference_position(const PositionFix& fix) {
  m::ReferencePosition r;
  r.latitude = latitude(fix.latitude_deg);
  r.longitude = longitude(fix.longitude_deg);
  r.positionConfidenceEllipse = confidence_ellipse(fix.position_confidence);
  r.altitude = altitude(fix.altitude_m, fix.altitude_confidence_m);
  return r;
}

m::HeadingValue heading_value(std::optional<double> deg) {
  if (!deg || !std::isfinite(*deg))
    return m::kHeadingValueUnavailable;
  long v = round_to(std::fmod(std::fmod(*deg, 360.0) + 360.0, 360.0) * 10.0);
  if (v >= 3600)
    v -= 3600;
  return static_cast<m::HeadingValue>(v);
}
std::optional<double> heading_deg(m::HeadingValue v) {
  if (v >= m::kHeadingValueUnavailable)
    return std::nullopt;
  return v / 10.0;
}
m::HeadingConfidence heading_confidence(std::optional<double> deg) {
  if (!deg || !std::isfinite(*deg) || *deg < 0.0)
    return m::kHeadingConfidenceUnavailable;
  const double d = std::ceil(*deg * 10.0);
  if (d > 125.0)
    return m::kHeadingConfidenceOutOfRange;
  return static_cast<m::HeadingConfidence>(std::max(1.0, d));
}
m::Heading heading(std::optional<double> deg, std::optional<double> confidence_deg) {
  m::Heading h;
  h.headingValue = heading_value(deg);
  if (h.headingValue != m::kHeadingValueUnavailable)
    h.headingConfidence = heading_confidence(confidence_deg);
  return h;
}

m::SpeedValue speed_value(std::optional<double> mps) {
  if (!mps || !std::isfinite(*mps))
    return m::kSpeedValueUnavailable;
  // SpeedValue 16382 stands for ≥ 163.82 m/s.
  return static_cast<m::SpeedValue>(round_clamped(std::abs(*mps) * 100.0, 0, 16382));
}
std::optional<double> speed_mps(m::SpeedValue v) {
  if (v >= m::kSpeedValueUnavailable)
    return std::nullopt;
  return v / 100.0;
}
m::SpeedConfidence speed_confidence(std::optional<double> mps) {
  if (!mps || !std::isfinite(*mps) || *mps < 0.0)
    return m::kSpeedConfidenceUnavailable;
  const double c = std::ceil(*mps * 100.0);
  if (c > 125.0)
    return m::kSpeedConfidenceOutOfRange;
  return static_cast<m::SpeedConfidence>(std::max(1.0, c));
}

m::AccelerationValue acceleration_value(std::optional<double> mps2) {
  if (!mps2 || !std::isfinite(*mps2))
    return m::kAccelerationValueUnavailable;
  // ±160 (±16 m/s²) saturate, 161 is "unavailable".
  return static_cast<m::AccelerationValue>(round_clamped(*mps2 * 10.0, -160, 160));
}

m::YawRate yaw_rate(std::optional<double> dps) {
  m::YawRate y;
  if (!dps || !std::isfinite(*dps))
    return y;
  y.yawRateValue = static_cast<m::YawRateValue>(round_clamped(*dps * 100.0, -32766, 32766));
  // The CAN signal's resolution is 0.01 °/s; the sensor's accuracy is not known, so the
  // confidence stays "unavailable" rather than claiming one.
  return y;
}

m::SteeringWheelAngle steering_wheel_angle(std::optional<double> deg) {
  m::SteeringWheelAngle s;
  if (!deg || !std::isfinite(*deg))
    return s;
  s.steeringWheelAngleValue =
      static_cast<m::SteeringWheelAngleValue>(round_clamped(*deg / 1.5, -511, 511));
  // The sensor's accuracy is not known (the CAN signal gives none): "unavailable", not the best
  // class, which would claim 1.5° for a reading nobody vouched for.
  return s;
}

m::Curvature curvature(std::optional<double> yaw_rate_dps, std::optional<double> speed_mps) {
  m::Curvature c;
  if (!yaw_rate_dps || !speed_mps || !std::isfinite(*yaw_rate_dps) || !std::isfinite(*speed_mps) ||
      std::abs(*speed_mps) < 1.0)
    return c;  // below walking pace ω / v is noise
  const double kappa = (*yaw_rate_dps * std::numbers::pi / 180.0) / *speed_mps;
  c.curvatureValue = static_cast<m::CurvatureValue>(round_clamped(kappa * 10000.0, -1022, 1022));
  return c;
}

double relevance_radius_m(m::RelevanceDistance d) {
  switch (d) {
    case m::RelevanceDistance::lessThan50m:
      return 50.0;
    case m::RelevanceDistance::lessThan100m:
      return 100.0;
    case m::RelevanceDistance::lessThan200m:
      return 200.0;
    case m::RelevanceDistance::lessThan500m:
      return 500.0;
    case m::RelevanceDistance::lessThan1000m:
      return 1000.0;
    case m::RelevanceDistance::lessThan5km:
      return 5000.0;
    case m::RelevanceDistance::lessThan10km:
      return 10000.0;
    case m::RelevanceDistance::over10km:
      return 20000.0;
  }
  return 1000.0;
}

}  // namespace tb::its::facilities::cdd
