#pragma once
/// @file How the testbed's local frame (x east, y north, z up, metres) lies on the Earth.
///
/// Two kinds exist: the exact ellipsoidal East-North-Up frame at a scenario's origin
/// (LocalFrame, local_frame.hpp) and a map's geoReference, a map projection such as UTM read
/// through PROJ (common/map). Consumers of positions (the GPS agents) take this interface, so
/// that they work the same on both.

#include "common/geodesy/wgs84.hpp"

namespace tb::geodesy {

/// A point of the local frame: east, north, up (on a projected map: the map's x, y, z).
struct Enu {
  double east = 0.0;
  double north = 0.0;
  double up = 0.0;
};

class Georeferencing {
 public:
  virtual ~Georeferencing() = default;
  /// WGS84 latitude, longitude and ellipsoidal height of a local point.
  virtual Geodetic to_geodetic(const Enu& p) const = 0;
  /// The local point of a WGS84 position.
  virtual Enu to_local(const Geodetic& g) const = 0;
  /// ETSI heading (degrees clockwise from true north, [0, 360)) of the local direction
  /// @p yaw_rad (counter-clockwise from the local x axis) at @p p. A projection's grid north
  /// differs from true north by the meridian convergence, which this includes.
  virtual double heading_deg(const Enu& p, double yaw_rad) const = 0;
};

}  // namespace tb::geodesy
