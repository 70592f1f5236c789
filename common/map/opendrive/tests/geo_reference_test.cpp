// geoReference through PROJ, checked against the testbed's own ellipsoidal ENU frame and UTM's
// defining values.

#include "common/map/opendrive/geo_reference.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "common/geodesy/local_frame.hpp"
#include "common/map/opendrive/road_network.hpp"

namespace tb::map::odr {
namespace {

/// Horizontal distance between two geodetic positions (m), small-distance approximation.
double metres_apart(const geodesy::Geodetic& a, const geodesy::Geodetic& b) {
  const double dn = (a.latitude_deg - b.latitude_deg) * 111'132.0;
  const double de =
      (a.longitude_deg - b.longitude_deg) * 111'320.0 * std::cos(a.latitude_deg * M_PI / 180.0);
  return std::hypot(dn, de);
}

TEST(GeoReference, TransverseMercatorAgreesWithTheLocalFrameNearItsOrigin) {
  const GeoReference g("+proj=tmerc +lat_0=48.1 +lon_0=11.5 +k=1 +x_0=0 +y_0=0 +ellps=WGS84",
                       "m.xodr");
  EXPECT_TRUE(g.notes().empty());
  const geodesy::LocalFrame enu({48.1, 11.5, 0.0});
  for (auto [x, y] : {std::pair{0.0, 0.0}, {100.0, 200.0}, {-350.0, 120.0}, {40.0, -480.0}}) {
    const geodesy::Geodetic a = g.to_wgs84(x, y, 0.0);
    const geodesy::Geodetic b = enu.to_geodetic({x, y, 0.0});
    EXPECT_LT(metres_apart(a, b), 0.01) << x << " " << y;
    double bx = 0, by = 0, bz = 0;
    g.from_wgs84(a, bx, by, bz);
    EXPECT_NEAR(bx, x, 1e-6);
    EXPECT_NEAR(by, y, 1e-6);
  }
  EXPECT_NEAR(g.to_wgs84(0, 0, 12.5).altitude_m, 12.5, 1e-6);  // z is the height
}

TEST(GeoReference, StringWithoutProjIsATransverseMercatorAtItsOrigin) {
  const GeoReference carla("+lat_0=49 +lon_0=8", "Town.xodr");
  ASSERT_EQ(carla.notes().size(), 1u);
  EXPECT_NE(carla.notes()[0].find("+proj=tmerc"), std::string::npos);
  const GeoReference explicit_tm("+proj=tmerc +lat_0=49 +lon_0=8", "x");
  const geodesy::Geodetic a = carla.to_wgs84(250, -90, 0);
  const geodesy::Geodetic b = explicit_tm.to_wgs84(250, -90, 0);
  EXPECT_DOUBLE_EQ(a.latitude_deg, b.latitude_deg);
  EXPECT_NEAR(carla.to_wgs84(0, 0, 0).latitude_deg, 49.0, 1e-12);
  EXPECT_NEAR(carla.to_wgs84(0, 0, 0).longitude_deg, 8.0, 1e-12);
}

TEST(GeoReference, UtmFalseEastingAtTheCentralMeridian) {
  const GeoReference utm("+proj=utm +zone=32 +datum=WGS84 +units=m +no_defs", "u.xodr");
  const geodesy::Geodetic p = utm.to_wgs84(500000.0, 0.0, 0.0);
  EXPECT_NEAR(p.latitude_deg, 0.0, 1e-9);
  EXPECT_NEAR(p.longitude_deg, 9.0, 1e-9);  // zone 32: 6-12 degrees east
}

TEST(GeoReference, MissingGeoidGridsAreIgnoredWithANote) {
  const GeoReference g("+proj=tmerc +lat_0=48 +lon_0=11 +geoidgrids=no_such_grid.gtx", "g.xodr");
  ASSERT_EQ(g.notes().size(), 1u);
  EXPECT_NE(g.notes()[0].find("+geoidgrids=no_such_grid.gtx"), std::string::npos);
  EXPECT_EQ(g.definition().find("geoidgrids"), std::string::npos);
  EXPECT_NEAR(g.to_wgs84(0, 0, 3).latitude_deg, 48.0, 1e-12);
}

TEST(GeoReference, UnreadableStringIsANamedError) {
  for (const char* bad : {"+proj=nonsense +lat_0=1", "", "+proj=tmerc +lat_0=abc"}) {
    try {
      GeoReference g(bad, "bad.xodr");
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const MapError& e) {
      EXPECT_EQ(e.file(), "bad.xodr");
      EXPECT_EQ(e.path(), "header/geoReference");
    }
  }
}

}  // namespace
}  // namespace tb::map::odr
