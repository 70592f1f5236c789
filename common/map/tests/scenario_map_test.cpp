// The map every program builds from a scenario: built-in lane spawns stand where RoadMap puts
// them, OpenDRIVE lane spawns stand on the surface with its slope and superelevation, and the
// frame is placed by the geoReference (PROJ) or by the scenario's origin, never by neither.

#include "common/map/scenario_map.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/geodesy/local_frame.hpp"
#include "common/map/builtin_network.hpp"
#include "common/map/opendrive/geo_reference.hpp"
#include "common/map/opendrive/reader.hpp"
#include "common/map/opendrive/tests/shared_maps.hpp"
#include "common/map/road_map.hpp"

namespace tb::map {
namespace {

constexpr double kPi = std::numbers::pi;

std::shared_ptr<const odr::RoadNetwork> load(const std::string& name) {
  return std::make_shared<const odr::RoadNetwork>(
      odr::load_opendrive((odr::test::shared_maps() / name).string()));
}

/// A straight road of 200 m along +x with one lane each way, placed by @p geo_reference.
std::shared_ptr<const odr::RoadNetwork> straight(const std::string& geo_reference) {
  const std::string header = geo_reference.empty()
                                 ? R"(<header revMajor="1" revMinor="6"/>)"
                                 : R"(<header revMajor="1" revMinor="6"><geoReference><![CDATA[)" +
                                       geo_reference + R"(]]></geoReference></header>)";
  return std::make_shared<const odr::RoadNetwork>(odr::parse_opendrive(
      R"(<OpenDRIVE>)" + header +
          R"(<road id="7" length="200" junction="-1"><planView><geometry s="0" x="0" y="0" hdg="0" length="200"><line/></geometry></planView>
<lanes><laneSection s="0"><left><lane id="1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></left>
<center><lane id="0" type="none"/></center><right><lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></right></laneSection></lanes></road></OpenDRIVE>)",
      "straight.xodr"));
}

double angle_diff(double a, double b) {
  return std::remainder(a - b, 2 * kPi);
}

TEST(ScenarioMap, BuiltinLaneSpawnsStandWhereRoadMapPutsThem) {
  for (const auto& [type, lanes, oncoming] :
       {std::tuple{scenario::MapType::kStraight, 2, 1},
        std::tuple{scenario::MapType::kStraight, 4, 2},
        std::tuple{scenario::MapType::kStraight, 3, 0}, std::tuple{scenario::MapType::kRing, 2, 1},
        std::tuple{scenario::MapType::kRing, 3, 0},
        std::tuple{scenario::MapType::kCrossing, 2, 1}}) {
    scenario::MapSpec spec;
    spec.type = type;
    spec.lanes = lanes;
    spec.oncoming_lanes = oncoming;
    spec.length = 600;
    spec.radius = 90;
    spec.arm_length = 250;
    const RoadMap old(spec);
    const ScenarioMap m(spec, std::nullopt);
    EXPECT_TRUE(m.flat());
    for (std::size_t road = 0; road < old.roads().size(); ++road) {
      for (int lane = 0; lane < lanes; ++lane) {
        for (double s : {0.0, 17.5, 250.0, 599.0, 1234.5}) {
          if (type != scenario::MapType::kRing &&
              s > length(old.lane(static_cast<int>(road), lane).centre))
            continue;
          for (bool against : {false, true}) {
            SCOPED_TRACE(testing::Message()
                         << "type " << static_cast<int>(type) << " lanes " << lanes << " road "
                         << road << " lane " << lane << " s " << s << (against ? " against" : ""));
            scenario::Spawn spawn;
            spawn.where = scenario::LaneSpawn{static_cast<int>(road), lane, s, against};
            const Placement p = m.place(spawn);
            const Pose want = old.lane_pose(static_cast<int>(road), lane, s);
            EXPECT_EQ(m.network_spawn(std::get<scenario::LaneSpawn>(spawn.where)).lane,
                      opendrive_lane_id(spec, lane));
            EXPECT_NEAR(p.x, want.p.x, 1e-6);
            EXPECT_NEAR(p.y, want.p.y, 1e-6);
            EXPECT_NEAR(angle_diff(p.yaw, want.yaw + (against ? kPi : 0.0)), 0.0, 1e-9);
            EXPECT_EQ(p.z, 0.0);
            EXPECT_NEAR(p.pitch, 0.0, 1e-12);
            EXPECT_NEAR(p.roll, 0.0, 1e-12);
          }
        }
      }
    }
  }
}

TEST(ScenarioMap, ALaneSpawnRestsOnTheSlopeAndTheSuperelevation) {
  const ScenarioMap m(load("straight_500_superelevation_elevation_curve.xodr"), std::nullopt);
  EXPECT_FALSE(m.flat());
  const odr::Road& road = m.network().roads.front();
  for (double s : {100.0, 150.0, 300.0, 330.0}) {
    for (int lane : {-1, 1}) {
      SCOPED_TRACE(testing::Message() << "s " << s << " lane " << lane);
      const Placement p = m.place(scenario::RoadSpawn{road.id, lane, s, 0.0, false});
      const double t = odr::lane_centre_t(road, lane, s);
      const odr::SurfacePose surface = road.surface(s, t);
      EXPECT_NEAR(p.z, surface.z, 1e-9);
      // Travel along s (right lane) climbs where the road climbs: ZYX pitch is minus the slope
      // angle; against s both turn round.
      const double sign = road.forward(lane) ? 1.0 : -1.0;
      const double slope = std::atan(road.elevation.derivative(s));
      const double roll = road.superelevation.value(s);
      EXPECT_NEAR(p.pitch, -sign * slope, 2e-3);
      EXPECT_NEAR(p.roll, sign * roll, 2e-3);
    }
  }
  // Standing across the road (a pose spawn heading along +t): the superelevation is its pitch
  // (uphill towards the raised left side, so the nose is up: ZYX pitch negative).
  scenario::Spawn across;
  const odr::SurfacePose c = road.surface(150.0, -1.75);
  across.where = scenario::PoseSpawn{c.x, c.y, geodesy::yaw_to_heading_deg(c.heading + kPi / 2)};
  const Placement p = m.place(across);
  EXPECT_NEAR(p.z, c.z, 1e-6);
  EXPECT_NEAR(p.pitch, -road.superelevation.value(150.0), 1e-6);
}

TEST(ScenarioMap, TheGeoReferencePlacesTheFrame) {
  const std::string utm = "+proj=utm +zone=32 +ellps=WGS84 +units=m";
  // 500 km east of zone 32's central meridian (9 E) is x = 500000; start 230 km east of it.
  const auto net = straight(utm);
  const ScenarioMap m(net, geodesy::Geodetic{10.0, 10.0, 0.0});
  ASSERT_TRUE(m.placed());
  EXPECT_EQ(m.origin().source, "geoReference");
  ASSERT_EQ(m.notes().size(), 1u);
  EXPECT_NE(m.notes()[0].find("origin is not used"), std::string::npos);
  const odr::GeoReference direct(utm, "direct");
  for (const auto& [x, y, z] :
       {std::tuple{730000.0, 5330000.0, 500.0}, std::tuple{500000.0, 4000000.0, 0.0}}) {
    const geodesy::Geodetic a = m.to_wgs84(x, y, z), b = direct.to_wgs84(x, y, z);
    EXPECT_EQ(a.latitude_deg, b.latitude_deg);
    EXPECT_EQ(a.longitude_deg, b.longitude_deg);
    EXPECT_EQ(a.altitude_m, b.altitude_m);
    const geodesy::Enu back = m.georeferencing().to_local(a);
    EXPECT_NEAR(back.east, x, 1e-6);
    EXPECT_NEAR(back.north, y, 1e-6);
    EXPECT_NEAR(back.up, z, 1e-6);
  }
  // Grid north east of the central meridian lies clockwise of true north by the meridian
  // convergence, about atan(tan(dlon) sin(lat)) (Snyder, Map Projections, 8-42 on the sphere).
  const geodesy::Geodetic g = m.to_wgs84(730000.0, 5330000.0, 0.0);
  const double dlon = (g.longitude_deg - 9.0) * kPi / 180.0;
  const double gamma =
      std::atan(std::tan(dlon) * std::sin(g.latitude_deg * kPi / 180.0)) * 180.0 / kPi;
  EXPECT_GT(gamma, 2.0);
  EXPECT_NEAR(m.georeferencing().heading_deg({730000.0, 5330000.0, 0.0}, kPi / 2), gamma, 0.02);
  EXPECT_NEAR(m.georeferencing().heading_deg({730000.0, 5330000.0, 0.0}, 0.0), 90.0 + gamma, 0.02);
}

TEST(ScenarioMap, WithoutAGeoReferenceTheOriginPlacesTheFrame) {
  const geodesy::Geodetic origin{41.105, 29.023, 60.0};
  const ScenarioMap m(straight(""), origin);
  EXPECT_EQ(m.origin().source, "scenario origin");
  EXPECT_TRUE(m.notes().empty());
  const geodesy::LocalFrame frame(origin);
  const geodesy::Geodetic a = m.to_wgs84(150.0, -1.75, 0.3),
                          b = frame.to_geodetic({150.0, -1.75, 0.3});
  EXPECT_EQ(a.latitude_deg, b.latitude_deg);
  EXPECT_EQ(a.longitude_deg, b.longitude_deg);
  EXPECT_EQ(a.altitude_m, b.altitude_m);
  EXPECT_DOUBLE_EQ(m.georeferencing().heading_deg({150, 0, 0}, 0.0), 90.0);
}

TEST(ScenarioMap, NothingPlacesTheFrameIsAnError) {
  const ScenarioMap tool(straight(""), std::nullopt);
  EXPECT_FALSE(tool.placed());
  EXPECT_EQ(tool.origin().source, "none");
  EXPECT_THROW((void)tool.georeferencing(), odr::MapError);

  scenario::Scenario s;
  s.map.type = scenario::MapType::kOpenDrive;
  s.network = straight("");
  try {
    const ScenarioMap m(s);
    ADD_FAILURE() << "a map placed by nothing was accepted";
  } catch (const odr::MapError& e) {
    EXPECT_EQ(e.path(), "header/geoReference");
    EXPECT_NE(std::string(e.what()).find("no geoReference and the scenario gives no origin"),
              std::string::npos)
        << e.what();
  }
}

TEST(ScenarioMap, LanesThatDoNotExistOrAreNotDrivableAreNamedErrors) {
  const ScenarioMap m(load("crest-curve.xodr"), geodesy::Geodetic{48.0, 11.0, 0.0});
  EXPECT_THROW(m.place(scenario::RoadSpawn{"0", -1, 450.0, 0.0, false}), odr::MapError);
  EXPECT_THROW(m.place(scenario::RoadSpawn{"0", -5, 50.0, 0.0, false}), odr::MapError);
  EXPECT_THROW(m.place(scenario::RoadSpawn{"0", -2, 50.0, 0.0, false}), odr::MapError);  // border
  EXPECT_THROW(m.place(scenario::RoadSpawn{"nope", -1, 50.0, 0.0, false}), odr::MapError);
  scenario::Spawn builtin;
  builtin.where = scenario::LaneSpawn{0, 0, 10.0, false};
  EXPECT_THROW(m.place(builtin), std::invalid_argument);
}

TEST(ScenarioMap, LocatorAndGraphAreBuiltOnceOnFirstUse) {
  const ScenarioMap m(load("simple_4way_intersection.xodr"), std::nullopt);
  const odr::LaneLocator* a = &m.locator();
  EXPECT_EQ(a, &m.locator());
  EXPECT_GT(m.locator().pieces(), 0u);
  EXPECT_GT(m.graph().size(), 0u);
  EXPECT_EQ(&m.graph(), &m.graph());
}

TEST(Orientation, OnAPlaneTiltedAboutOneAxisTheAnglesAreTheTilt) {
  double pitch = 0, roll = 0;
  // A surface raised towards +y by 5 degrees, driving along +x: roll +5 degrees (left up).
  const double a = 5.0 * kPi / 180.0;
  orientation_on(0.0, -std::sin(a), std::cos(a), 0.0, pitch, roll);
  EXPECT_NEAR(pitch, 0.0, 1e-12);
  EXPECT_NEAR(roll, a, 1e-12);
  // The same surface driven along +y: uphill, so the nose is up (ZYX pitch negative).
  orientation_on(0.0, -std::sin(a), std::cos(a), kPi / 2, pitch, roll);
  EXPECT_NEAR(pitch, -a, 1e-12);
  EXPECT_NEAR(roll, 0.0, 1e-12);
}

}  // namespace
}  // namespace tb::map
