#include "common/geodesy/wgs84.hpp"

#include <cmath>
#include <numbers>

namespace tb::geodesy {
namespace {
constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kRadToDeg = 180.0 / std::numbers::pi;
}  // namespace

Ecef to_ecef(const Geodetic& g) {
  const double lat = g.latitude_deg * kDegToRad;
  const double lon = g.longitude_deg * kDegToRad;
  const double sin_lat = std::sin(lat);
  const double cos_lat = std::cos(lat);
  const double n = kSemiMajorAxis / std::sqrt(1.0 - kFirstEccentricitySquared * sin_lat * sin_lat);
  return Ecef{(n + g.altitude_m) * cos_lat * std::cos(lon),
              (n + g.altitude_m) * cos_lat * std::sin(lon),
              (n * (1.0 - kFirstEccentricitySquared) + g.altitude_m) * sin_lat};
}

Geodetic to_geodetic(const Ecef& e) {
  const double p = std::hypot(e.x, e.y);
  const double lon = std::atan2(e.y, e.x);
  // Start from the spherical latitude and refine; a few iterations reach 1e-12 rad.
  double lat = std::atan2(e.z, p * (1.0 - kFirstEccentricitySquared));
  double height = 0.0;
  for (int i = 0; i < 8; ++i) {
    const double sin_lat = std::sin(lat);
    const double n =
        kSemiMajorAxis / std::sqrt(1.0 - kFirstEccentricitySquared * sin_lat * sin_lat);
    const double cos_lat = std::cos(lat);
    height = std::abs(cos_lat) > 1e-10 ? p / cos_lat - n : std::abs(e.z) - kSemiMinorAxis;
    const double next = std::atan2(e.z, p * (1.0 - kFirstEccentricitySquared * n / (n + height)));
    if (std::abs(next - lat) < 1e-14) {
      lat = next;
      break;
    }
    lat = next;
  }
  return Geodetic{lat * kRadToDeg, lon * kRadToDeg, height};
}

}  // namespace tb::geodesy
