#pragma once
/// @file The testbed's local Cartesian frame: East-North-Up, anchored at the scenario's origin.
///
/// The simulation works in metres in this frame (x east, y north, z up). GNSS positions, CAM
/// reference positions and map coordinates go through LocalFrame, which uses the exact
/// ellipsoidal ENU transformation (not a flat-earth approximation), so round trips and distances
/// stay far inside the 1 cm budget within 20 km of the origin.

#include "common/geodesy/georeferencing.hpp"
#include "common/geodesy/wgs84.hpp"

namespace tb::geodesy {

class LocalFrame final : public Georeferencing {
 public:
  /// @throws std::invalid_argument if the origin is not a valid geodetic position.
  explicit LocalFrame(const Geodetic& origin);

  const Geodetic& origin() const { return origin_; }
  Geodetic to_geodetic(const Enu& p) const override;
  Enu to_enu(const Geodetic& g) const;
  Enu to_local(const Geodetic& g) const override { return to_enu(g); }
  /// The frame's north is true north at the origin; the testbed neglects the few hundredths of
  /// a degree by which it turns away within its 20 km (as it always has).
  double heading_deg(const Enu& p, double yaw_rad) const override;

 private:
  Geodetic origin_;
  Ecef origin_ecef_;
  // Rows of the ECEF→ENU rotation matrix.
  double east_[3];
  double north_[3];
  double up_[3];
};

/// Heading conventions.
///
/// ETSI heading (CDD HeadingValue, EN 302 637-2) is the direction of travel measured clockwise
/// from true north, in [0, 360) degrees; NMEA course over ground uses the same convention.
/// The local frame's yaw is the mathematical angle measured counter-clockwise from east (the
/// x axis), in radians. The two are related by heading = 90° − yaw.
double yaw_to_heading_deg(double yaw_rad);
double heading_deg_to_yaw(double heading_deg);

/// Wraps an angle in degrees into [0, 360).
double wrap_360(double deg);
/// Smallest signed difference a − b in degrees, in (−180, 180]; used wherever headings are
/// compared so that 359° and 1° are 2° apart.
double heading_difference_deg(double a, double b);

}  // namespace tb::geodesy
