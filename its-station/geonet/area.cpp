#include "its-station/geonet/area.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

#include "common/geodesy/local_frame.hpp"

namespace tb::its::geonet {

std::int32_t to_tenth_micro_degree(double degrees) {
  return static_cast<std::int32_t>(std::lround(degrees * 1e7));
}

namespace {

std::uint16_t metres(double m) {
  if (!std::isfinite(m) || m <= 0.0)
    return 0;
  return static_cast<std::uint16_t>(std::lround(std::min(m, 65535.0)));
}

}  // namespace

GeoArea make_geo_area(AreaShape shape, const GeoPoint& centre, double distance_a_m,
                      double distance_b_m, double angle_deg) {
  GeoArea area;
  area.shape = shape;
  area.latitude = to_tenth_micro_degree(std::clamp(centre.latitude_deg, -90.0, 90.0));
  area.longitude = to_tenth_micro_degree(std::clamp(centre.longitude_deg, -180.0, 180.0));
  area.distance_a = metres(distance_a_m);
  area.distance_b = shape == AreaShape::kCircle ? 0 : metres(distance_b_m);
  const double angle = std::isfinite(angle_deg) ? std::fmod(angle_deg, 360.0) : 0.0;
  area.angle = static_cast<std::uint16_t>(std::lround(angle < 0 ? angle + 360.0 : angle) % 360);
  return area;
}

namespace {

// Received packets may carry any 32-bit value; positions off the globe never match an area.
bool on_globe(const GeoPoint& p) {
  return std::abs(p.latitude_deg) <= 90.0 && std::abs(p.longitude_deg) <= 180.0;
}

geodesy::Enu offset(const GeoPoint& origin, const GeoPoint& p) {
  const geodesy::LocalFrame frame{{origin.latitude_deg, origin.longitude_deg, 0.0}};
  return frame.to_enu({p.latitude_deg, p.longitude_deg, 0.0});
}

}  // namespace

double geometric_function(const GeoArea& area, const GeoPoint& point) {
  const GeoPoint centre{to_degrees(area.latitude), to_degrees(area.longitude)};
  if (!on_globe(centre) || !on_globe(point))
    return -std::numeric_limits<double>::infinity();
  const geodesy::Enu d = offset(centre, point);
  const double theta = area.angle * std::numbers::pi / 180.0;
  // Rotate east/north into the area's axes: x along the azimuth theta, y 90° clockwise of it.
  const double x = d.east * std::sin(theta) + d.north * std::cos(theta);
  const double y = d.east * std::cos(theta) - d.north * std::sin(theta);
  const double a = area.distance_a;
  const double b = area.shape == AreaShape::kCircle ? a : static_cast<double>(area.distance_b);
  if (a <= 0.0 || b <= 0.0) {
    const bool at_centre = std::hypot(x, y) < 1e-3;
    return at_centre ? 0.0 : -1.0;
  }
  const double fx = 1.0 - (x / a) * (x / a);
  const double fy = 1.0 - (y / b) * (y / b);
  if (area.shape == AreaShape::kRectangle)
    return std::min(fx, fy);
  return fx + fy - 1.0;
}

double distance_m(const GeoPoint& a, const GeoPoint& b) {
  if (!on_globe(a) || !on_globe(b))
    return std::numeric_limits<double>::infinity();
  const geodesy::Enu d = offset(a, b);
  return std::hypot(d.east, d.north);
}

}  // namespace tb::its::geonet
