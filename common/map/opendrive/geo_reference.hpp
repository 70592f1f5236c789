#pragma once
/// @file The file's geoReference through PROJ: inertial (x east, y north, z up) <-> WGS84.

#include <memory>
#include <string>
#include <vector>

#include "common/geodesy/wgs84.hpp"

namespace tb::map::odr {

/// A projection from a map's inertial frame to WGS84 latitude, longitude, ellipsoidal height.
/// Built from the header's PROJ string (`+proj=tmerc/utm/...`). Where the issue is silent:
/// - a string without `+proj` (CARLA writes `+lat_0=49 +lon_0=8`) is read as a transverse
///   Mercator at that origin on WGS84; `notes` says so once;
/// - `+geoidgrids` files that are not installed are dropped, with a note naming them, so the
///   heights are ellipsoidal (the map's z) rather than an error;
/// - a missing `+ellps`/`+datum` means WGS84 (PROJ's own default is GRS80, 0.1 mm apart).
class GeoReference {
 public:
  /// @throws MapError (file @p source, path `header/geoReference`) for a string PROJ cannot
  /// read or that does not map the origin to a finite position.
  GeoReference(const std::string& proj, const std::string& source);
  ~GeoReference();
  GeoReference(GeoReference&&) noexcept;
  GeoReference& operator=(GeoReference&&) noexcept;

  geodesy::Geodetic to_wgs84(double x, double y, double z) const;
  /// The inverse: x, y, z of a WGS84 position.
  void from_wgs84(const geodesy::Geodetic& g, double& x, double& y, double& z) const;

  /// The PROJ string used, after the adjustments above.
  const std::string& definition() const { return definition_; }
  /// What was adjusted, for the log (one line each).
  const std::vector<std::string>& notes() const { return notes_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string definition_;
  std::vector<std::string> notes_;
};

}  // namespace tb::map::odr
