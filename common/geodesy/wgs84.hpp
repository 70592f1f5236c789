#pragma once
/// @file WGS84 ellipsoid, geographic and Earth-centred Earth-fixed (ECEF) coordinates.

namespace tb::geodesy {

/// WGS84 defining parameters (NIMA TR8350.2, table 3.1).
inline constexpr double kSemiMajorAxis = 6378137.0;
inline constexpr double kFlattening = 1.0 / 298.257223563;
inline constexpr double kSemiMinorAxis = kSemiMajorAxis * (1.0 - kFlattening);
inline constexpr double kFirstEccentricitySquared = kFlattening * (2.0 - kFlattening);

/// Geodetic position: latitude and longitude in degrees, height above the ellipsoid in metres.
struct Geodetic {
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double altitude_m = 0.0;
};

struct Ecef {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

Ecef to_ecef(const Geodetic& g);

/// Exact inverse of to_ecef (Bowring's iteration, converged to well below a micrometre for any
/// point near the Earth's surface).
Geodetic to_geodetic(const Ecef& e);

}  // namespace tb::geodesy
