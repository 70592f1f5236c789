// Where an RSU's antenna is (rsu_site.hpp), graded by hand-worked geometry: a straight road
// along +x climbing 6 m over 100 m (z = 0.06 s), a 3.5 m lane each side.

#include <gtest/gtest.h>

#include <memory>

#include "common/map/opendrive/reader.hpp"
#include "common/map/rsu_site.hpp"

namespace tb::map {
namespace {

std::shared_ptr<const odr::RoadNetwork> climbing_road(double slope) {
  const std::string xml =
      "<OpenDRIVE><header revMajor=\"1\" revMinor=\"6\"/><road id=\"1\" length=\"100\" "
      "junction=\"-1\"><planView><geometry s=\"0\" x=\"0\" y=\"0\" hdg=\"0\" length=\"100\">"
      "<line/></geometry></planView><elevationProfile><elevation s=\"0\" a=\"0\" b=\"" +
      std::to_string(slope) +
      "\" c=\"0\" d=\"0\"/></elevationProfile><lanes><laneSection s=\"0\"><left><lane id=\"1\" "
      "type=\"driving\"><width sOffset=\"0\" a=\"3.5\" b=\"0\" c=\"0\" d=\"0\"/></lane></left>"
      "<center><lane id=\"0\" type=\"none\"/></center><right><lane id=\"-1\" type=\"driving\">"
      "<width sOffset=\"0\" a=\"3.5\" b=\"0\" c=\"0\" d=\"0\"/></lane></right></laneSection>"
      "</lanes></road></OpenDRIVE>";
  return std::make_shared<const odr::RoadNetwork>(odr::parse_opendrive(xml, "hand.xodr"));
}

scenario::Rsu rsu(double x, double y, double h) {
  scenario::Rsu r;
  r.id = "r";
  r.x = x;
  r.y = y;
  r.height_m = h;
  return r;
}

TEST(RsuSite, OnAFlatMapTheAntennaIsItsHeightAboveZero) {
  const ScenarioMap m(climbing_road(0.0), geodesy::Geodetic{48.0, 11.0, 500.0});
  const auto sites = rsu_sites({rsu(50, 10, 5.0), rsu(20, -1, 2.5)}, m);
  ASSERT_EQ(sites.size(), 2u);
  EXPECT_EQ(sites[0].x, 50.0);
  EXPECT_EQ(sites[0].y, 10.0);
  EXPECT_EQ(sites[0].ground_z, 0.0);
  EXPECT_EQ(sites[0].antenna_z, 5.0);
  EXPECT_EQ(sites[1].antenna_z, 2.5);
}

TEST(RsuSite, OnALaneTheGroundIsTheRoadSurface) {
  const ScenarioMap m(climbing_road(0.06), geodesy::Geodetic{48.0, 11.0, 500.0});
  const auto sites = rsu_sites({rsu(50, -1.75, 5.0), rsu(80, 1.0, 0.0)}, m);
  EXPECT_NEAR(sites[0].ground_z, 3.0, 1e-6);  // 0.06 × 50
  EXPECT_NEAR(sites[0].antenna_z, 8.0, 1e-6);
  EXPECT_NEAR(sites[1].ground_z, 4.8, 1e-6);
}

TEST(RsuSite, BesideTheRoadTheGroundFollowsIt) {
  const ScenarioMap m(climbing_road(0.06), geodesy::Geodetic{48.0, 11.0, 500.0});
  // 6.5 m off the lane's edge at s = 50: the terrain, which lies a kerb (5 cm) below the road
  // along its edges and has no slope across its border, is near the road's 3.0 m there and
  // climbs with it.
  const auto sites = rsu_sites({rsu(50, 10, 5.0), rsu(90, 10, 5.0)}, m);
  EXPECT_NEAR(sites[0].ground_z, 3.0, 0.5);
  EXPECT_NEAR(sites[1].ground_z, 5.4, 0.5);
  EXPECT_NEAR(sites[0].antenna_z - sites[0].ground_z, 5.0, 1e-9);
}

}  // namespace
}  // namespace tb::map
