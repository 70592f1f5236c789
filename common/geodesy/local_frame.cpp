#include "common/geodesy/local_frame.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace tb::geodesy {
namespace {
constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kRadToDeg = 180.0 / std::numbers::pi;
}  // namespace

LocalFrame::LocalFrame(const Geodetic& origin) : origin_(origin) {
  if (!std::isfinite(origin.latitude_deg) || std::abs(origin.latitude_deg) > 90.0) {
    throw std::invalid_argument("origin latitude " + std::to_string(origin.latitude_deg) +
                                " is outside [-90, 90]");
  }
  if (!std::isfinite(origin.longitude_deg) || std::abs(origin.longitude_deg) > 180.0) {
    throw std::invalid_argument("origin longitude " + std::to_string(origin.longitude_deg) +
                                " is outside [-180, 180]");
  }
  if (!std::isfinite(origin.altitude_m)) {
    throw std::invalid_argument("origin altitude is not a finite number");
  }
  origin_ecef_ = to_ecef(origin);
  const double lat = origin.latitude_deg * kDegToRad;
  const double lon = origin.longitude_deg * kDegToRad;
  const double sl = std::sin(lat), cl = std::cos(lat), so = std::sin(lon), co = std::cos(lon);
  east_[0] = -so, east_[1] = co, east_[2] = 0.0;
  north_[0] = -sl * co, north_[1] = -sl * so, north_[2] = cl;
  up_[0] = cl * co, up_[1] = cl * so, up_[2] = sl;
}

Enu LocalFrame::to_enu(const Geodetic& g) const {
  const Ecef e = to_ecef(g);
  const double d[3] = {e.x - origin_ecef_.x, e.y - origin_ecef_.y, e.z - origin_ecef_.z};
  return Enu{east_[0] * d[0] + east_[1] * d[1] + east_[2] * d[2],
             north_[0] * d[0] + north_[1] * d[1] + north_[2] * d[2],
             up_[0] * d[0] + up_[1] * d[1] + up_[2] * d[2]};
}

Geodetic LocalFrame::to_geodetic(const Enu& p) const {
  // The rotation is orthonormal: its inverse is its transpose.
  const Ecef e{origin_ecef_.x + east_[0] * p.east + north_[0] * p.north + up_[0] * p.up,
               origin_ecef_.y + east_[1] * p.east + north_[1] * p.north + up_[1] * p.up,
               origin_ecef_.z + east_[2] * p.east + north_[2] * p.north + up_[2] * p.up};
  return tb::geodesy::to_geodetic(e);
}

double LocalFrame::heading_deg(const Enu& /*p*/, double yaw_rad) const {
  return yaw_to_heading_deg(yaw_rad);
}

double wrap_360(double deg) {
  double w = std::fmod(deg, 360.0);
  if (w < 0.0)
    w += 360.0;
  if (w >= 360.0)
    w -= 360.0;  // fmod of a tiny negative number can round up to 360
  return w;
}

double heading_difference_deg(double a, double b) {
  double d = wrap_360(a - b);
  return d > 180.0 ? d - 360.0 : d;
}

double yaw_to_heading_deg(double yaw_rad) {
  return wrap_360(90.0 - yaw_rad * kRadToDeg);
}

double heading_deg_to_yaw(double heading_deg) {
  double yaw = (90.0 - heading_deg) * kDegToRad;
  return std::remainder(yaw, 2.0 * std::numbers::pi);
}

}  // namespace tb::geodesy
