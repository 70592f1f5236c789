#pragma once
/// @file Geographical areas of GeoBroadcast: the geometric function F of EN 302 931 (clause 5).

#include "its-station/geonet/packet.hpp"

namespace tb::its::geonet {

/// Geographic coordinates in degrees.
struct GeoPoint {
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
};

/// Wire units (1/10 micro-degree) to degrees and back.
inline double to_degrees(std::int32_t tenth_micro_degree) {
  return tenth_micro_degree * 1e-7;
}
std::int32_t to_tenth_micro_degree(double degrees);

inline GeoPoint position_of(const LongPositionVector& pv) {
  return {to_degrees(pv.latitude), to_degrees(pv.longitude)};
}

/// Builds the wire form of an area from SI units: the centre rounded to 1/10 micro-degree,
/// distances rounded to metres and clamped to [0, 65535], the angle wrapped into [0, 360).
GeoArea make_geo_area(AreaShape shape, const GeoPoint& centre, double distance_a_m,
                      double distance_b_m = 0.0, double angle_deg = 0.0);

/// F(x, y) of EN 302 931 for @p point: 1 at the centre, > 0 inside, 0 on the border, < 0 outside.
/// x runs along the a axis (azimuth = angle, clockwise from north), y across it:
///   circle     F = 1 − (x/a)² − (y/a)²
///   ellipse    F = 1 − (x/a)² − (y/b)²
///   rectangle  F = min(1 − (x/a)², 1 − (y/b)²)
/// A degenerate area (a = 0, or b = 0 for a rectangle or ellipse) contains only its centre; an
/// area or point off the globe (|lat| > 90°, |lon| > 180°) gives −∞.
double geometric_function(const GeoArea& area, const GeoPoint& point);

inline bool is_inside_or_at_border(const GeoArea& area, const GeoPoint& point) {
  return geometric_function(area, point) >= 0.0;
}

/// Distance in metres between two points (on the WGS84 ellipsoid's local tangent plane at @p a,
/// which is what F uses; exact enough for the few-kilometre hops of GN forwarding). Infinite
/// when either point is off the globe.
double distance_m(const GeoPoint& a, const GeoPoint& b);

}  // namespace tb::its::geonet
