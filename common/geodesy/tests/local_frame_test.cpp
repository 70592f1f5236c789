#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/geodesy/local_frame.hpp"

namespace tb::geodesy {
namespace {

struct Vector {
  Geodetic origin;
  Enu enu;
  Geodetic expected;
};

// Computed independently with GeographicLib's CartConvert (geographiclib-tools 2.1, Debian 12):
//   echo "E N U" | CartConvert -r -l LAT0 LON0 H0 -p 10
// Origins: Istanbul, Helsinki, Sydney (southern hemisphere) and the equator next to the
// antimeridian (longitude wraps); points up to 20 km from the origin.
const Vector kVectors[] = {
    {{41.0255, 28.9742, 40},
     {10000, 0, 0},
     {41.025438671814300, 29.093101259966506, 47.8279123217}},
    {{41.0255, 28.9742, 40},
     {0, -15000, 12},
     {40.890430828300985, 28.974200000000007, 69.6804521571}},
    {{41.0255, 28.9742, 40},
     {-14142.1356, 14142.1356, -30},
     {41.152719189853563, 28.805723125349594, 41.3715586082}},
    {{41.0255, 28.9742, 40},
     {123.456, -987.654, 1.5},
     {41.016606616707158, 28.975667711699039, 41.5778442270}},
    {{41.0255, 28.9742, 40},
     {5000, 7000, 200},
     {41.088514057597230, 29.033705570201988, 245.8071651169}},
    {{60.1699, 24.9384, 15},
     {10000, 0, 0},
     {60.169777602853770, 25.118534884984900, 22.8194847430}},
    {{60.1699, 24.9384, 15},
     {0, -15000, 12},
     {60.035267861639788, 24.938400000000001, 44.6232536117}},
    {{60.1699, 24.9384, 15},
     {-14142.1356, 14142.1356, -30},
     {60.296584684713210, 24.682664051140101, 16.3039066169}},
    {{60.1699, 24.9384, 15},
     {123.456, -987.654, 1.5},
     {60.161035370686008, 24.940623281150117, 16.5775950365}},
    {{60.1699, 24.9384, 15},
     {5000, 7000, 200},
     {60.232694953106432, 25.028637121015354, 220.7926092540}},
    {{-33.8688, 151.2093, 5},
     {10000, 0, 0},
     {-33.868752613681799, 151.317376842367366, 12.8311151844}},
    {{-33.8688, 151.2093, 5},
     {0, -15000, 12},
     {-34.004030477619374, 151.209300000000013, 34.7017012522}},
    {{-33.8688, 151.2093, 5},
     {-14142.1356, 14142.1356, -30},
     {-33.741205571619808, 151.056682615961591, 6.3975397189}},
    {{-33.8688, 151.2093, 5},
     {123.456, -987.654, 1.5},
     {-33.877704176897993, 151.210634413278427, 6.5779379268}},
    {{-33.8688, 151.2093, 5},
     {5000, 7000, 200},
     {-33.805681383574111, 151.263297043857449, 210.8126926383}},
    {{0.0, 179.95, 0}, {10000, 0, 0}, {0.000000000000000, -179.960168545195074, 7.8392748964}},
    {{0.0, 179.95, 0}, {0, -15000, 12}, {-0.135654908588424, 179.949999999999989, 29.7571944735}},
    {{0.0, 179.95, 0},
     {-14142.1356, 14142.1356, -30},
     {0.127897232320098, 179.822958645050392, 1.4628547153}},
    {{0.0, 179.95, 0},
     {123.456, -987.654, 1.5},
     {-0.008932039125319, 179.951109023856191, 1.5781792302}},
    {{0.0, 179.95, 0}, {5000, 7000, 200}, {0.063303819389980, 179.994914346621158, 205.8267688471}},
};

// Metres per degree, generous upper bounds for turning an angular error into a distance.
constexpr double kMetresPerDegLat = 111'700.0;

double longitude_error_deg(double a, double b) {
  return std::remainder(a - b, 360.0);
}

TEST(LocalFrame, EnuToGeodeticMatchesGeographicLib) {
  for (const auto& v : kVectors) {
    const LocalFrame frame(v.origin);
    const Geodetic g = frame.to_geodetic(v.enu);
    const double cos_lat = std::cos(v.expected.latitude_deg * std::numbers::pi / 180.0);
    EXPECT_LT(std::abs(g.latitude_deg - v.expected.latitude_deg) * kMetresPerDegLat, 0.001)
        << "origin " << v.origin.latitude_deg << "," << v.origin.longitude_deg;
    EXPECT_LT(std::abs(longitude_error_deg(g.longitude_deg, v.expected.longitude_deg)) *
                  kMetresPerDegLat * cos_lat,
              0.001);
    EXPECT_NEAR(g.altitude_m, v.expected.altitude_m, 0.001);
  }
}

TEST(LocalFrame, GeodeticToEnuMatchesGeographicLib) {
  for (const auto& v : kVectors) {
    const LocalFrame frame(v.origin);
    const Enu e = frame.to_enu(v.expected);
    EXPECT_NEAR(e.east, v.enu.east, 0.001);
    EXPECT_NEAR(e.north, v.enu.north, 0.001);
    EXPECT_NEAR(e.up, v.enu.up, 0.001);
  }
}

TEST(LocalFrame, RoundTripOnAGridWithin20KmStaysBelowOneMillimetre) {
  const LocalFrame frame({48.7758, 9.1829, 250.0});
  for (double e = -20000; e <= 20000; e += 2500) {
    for (double n = -20000; n <= 20000; n += 2500) {
      const Enu p{e, n, 3.0};
      const Enu back = frame.to_enu(frame.to_geodetic(p));
      EXPECT_NEAR(back.east, e, 1e-3);
      EXPECT_NEAR(back.north, n, 1e-3);
      EXPECT_NEAR(back.up, 3.0, 1e-3);
    }
  }
}

TEST(LocalFrame, OriginMapsToZero) {
  const LocalFrame frame({41.0255, 28.9742, 40});
  const Enu e = frame.to_enu(frame.origin());
  EXPECT_NEAR(e.east, 0.0, 1e-6);
  EXPECT_NEAR(e.north, 0.0, 1e-6);
  EXPECT_NEAR(e.up, 0.0, 1e-6);
}

TEST(LocalFrame, RejectsInvalidOrigin) {
  EXPECT_THROW(LocalFrame({91.0, 0.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(LocalFrame({0.0, 181.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(LocalFrame({NAN, 0.0, 0.0}), std::invalid_argument);
}

TEST(Heading, EtsiHeadingIsClockwiseFromNorth) {
  constexpr double pi = std::numbers::pi;
  EXPECT_NEAR(yaw_to_heading_deg(0.0), 90.0, 1e-9);          // driving east
  EXPECT_NEAR(yaw_to_heading_deg(pi / 2), 0.0, 1e-9);        // north
  EXPECT_NEAR(yaw_to_heading_deg(pi), 270.0, 1e-9);          // west
  EXPECT_NEAR(yaw_to_heading_deg(-pi / 2), 180.0, 1e-9);     // south
  EXPECT_NEAR(yaw_to_heading_deg(3 * pi / 4), 315.0, 1e-9);  // north-west
  for (double h = 0.0; h < 360.0; h += 7.5) {
    EXPECT_NEAR(yaw_to_heading_deg(heading_deg_to_yaw(h)), h, 1e-9);
  }
}

TEST(Heading, DifferenceWrapsAround) {
  EXPECT_NEAR(heading_difference_deg(1.0, 359.0), 2.0, 1e-12);
  EXPECT_NEAR(heading_difference_deg(359.0, 1.0), -2.0, 1e-12);
  EXPECT_NEAR(heading_difference_deg(180.0, 0.0), 180.0, 1e-12);
  EXPECT_NEAR(wrap_360(-0.5), 359.5, 1e-12);
  EXPECT_NEAR(wrap_360(720.25), 0.25, 1e-12);
  EXPECT_LT(wrap_360(-1e-18), 360.0);
}

}  // namespace
}  // namespace tb::geodesy
