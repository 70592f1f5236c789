#include <gtest/gtest.h>

#include <cmath>

#include "common/geodesy/local_frame.hpp"
#include "its-station/geonet/area.hpp"

namespace tb::its::geonet {
namespace {

constexpr double kLat = 48.15;
constexpr double kLon = -1.6;

// A point @p east / @p north metres from the areas' centre.
GeoPoint at(double east, double north) {
  const geodesy::LocalFrame frame{{kLat, kLon, 0.0}};
  const auto g = frame.to_geodetic({east, north, 0.0});
  return {g.latitude_deg, g.longitude_deg};
}

GeoArea area(AreaShape shape, std::uint16_t a, std::uint16_t b, std::uint16_t angle) {
  return {shape, to_tenth_micro_degree(kLat), to_tenth_micro_degree(kLon), a, b, angle};
}

TEST(GeoArea, CircleFollowsEn302931) {
  const GeoArea c = area(AreaShape::kCircle, 100, 0, 0);
  EXPECT_NEAR(geometric_function(c, at(0, 0)), 1.0, 1e-6);
  EXPECT_NEAR(geometric_function(c, at(0, 50)), 0.75, 1e-4);
  EXPECT_NEAR(geometric_function(c, at(-60, 80)), 0.0, 1e-4);  // on the border
  EXPECT_TRUE(is_inside_or_at_border(c, at(70, -70)));
  EXPECT_FALSE(is_inside_or_at_border(c, at(150, 0)));
  EXPECT_NEAR(geometric_function(c, at(200, 0)), -3.0, 1e-3);
}

TEST(GeoArea, RectangleIsAlignedWithItsAzimuth) {
  const GeoArea east_west = area(AreaShape::kRectangle, 100, 20, 90);  // a axis points east
  EXPECT_TRUE(is_inside_or_at_border(east_west, at(90, 0)));
  EXPECT_TRUE(is_inside_or_at_border(east_west, at(-90, 15)));
  EXPECT_FALSE(is_inside_or_at_border(east_west, at(0, 30)));
  EXPECT_FALSE(is_inside_or_at_border(east_west, at(110, 0)));
  // Corners are inside a rectangle (unlike an ellipse): F = min(1 − 0.81, 1 − 0.5625).
  EXPECT_NEAR(geometric_function(east_west, at(90, 15)), 0.19, 1e-3);

  const GeoArea north_south = area(AreaShape::kRectangle, 100, 20, 0);
  EXPECT_TRUE(is_inside_or_at_border(north_south, at(0, -90)));
  EXPECT_FALSE(is_inside_or_at_border(north_south, at(90, 0)));
}

TEST(GeoArea, EllipseRotatedBy45Degrees) {
  const GeoArea e = area(AreaShape::kEllipse, 100, 50, 45);
  const double s = std::sqrt(0.5);
  EXPECT_NEAR(geometric_function(e, at(90 * s, 90 * s)), 1 - 0.81, 1e-3);  // along a (NE)
  EXPECT_TRUE(is_inside_or_at_border(e, at(-40 * s, 40 * s)));             // along b (NW)
  EXPECT_FALSE(is_inside_or_at_border(e, at(-60 * s, 60 * s)));
  EXPECT_FALSE(is_inside_or_at_border(e, at(0, 90)));  // due north is off both axes
  EXPECT_NEAR(geometric_function(e, at(90 * s, 90 * s)),
              geometric_function(e, at(-90 * s, -90 * s)), 1e-6);
}

TEST(GeoArea, DegenerateAreaHoldsOnlyItsCentre) {
  const GeoArea dot = area(AreaShape::kCircle, 0, 0, 0);
  EXPECT_TRUE(is_inside_or_at_border(dot, at(0, 0)));
  EXPECT_FALSE(is_inside_or_at_border(dot, at(1, 0)));
  const GeoArea line = area(AreaShape::kEllipse, 100, 0, 0);
  EXPECT_FALSE(is_inside_or_at_border(line, at(0, 50)));
}

TEST(GeoArea, PositionsOffTheGlobeAreNeverInside) {
  GeoArea bad = area(AreaShape::kCircle, 65535, 0, 0);
  bad.latitude = 950'000'000;  // 95°: only a malformed packet says so
  EXPECT_TRUE(std::isinf(geometric_function(bad, at(0, 0))));
  EXPECT_FALSE(is_inside_or_at_border(area(AreaShape::kCircle, 100, 0, 0), {0.0, 200.0}));
  EXPECT_TRUE(std::isinf(distance_m({0, 0}, {91, 0})));
}

TEST(GeoArea, MakeGeoAreaRoundsClampsAndWraps) {
  const GeoArea a =
      make_geo_area(AreaShape::kEllipse, {48.15000004, -1.60000006}, 120.6, 40.4, -30.0);
  EXPECT_EQ(a.latitude, 481'500'000);
  EXPECT_EQ(a.longitude, -16'000'001);
  EXPECT_EQ(a.distance_a, 121);
  EXPECT_EQ(a.distance_b, 40);
  EXPECT_EQ(a.angle, 330);
  const GeoArea c = make_geo_area(AreaShape::kCircle, {0, 0}, 1e9, 50.0, 359.6);
  EXPECT_EQ(c.distance_a, 65535);
  EXPECT_EQ(c.distance_b, 0);  // a circle has only a radius
  EXPECT_EQ(c.angle, 0);       // 359.6° rounds to 360° = 0°
  EXPECT_EQ(make_geo_area(AreaShape::kRectangle, {95, 200}, -5, NAN, 720).latitude, 900'000'000);
  EXPECT_EQ(make_geo_area(AreaShape::kRectangle, {95, 200}, -5, NAN, 720).distance_a, 0);
}

TEST(GeoArea, DistanceIsMetresOnTheGround) {
  EXPECT_NEAR(distance_m(at(0, 0), at(300, 400)), 500.0, 0.01);
}

}  // namespace
}  // namespace tb::its::geonet
