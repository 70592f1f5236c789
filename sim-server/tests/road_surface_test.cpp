// Cars on OpenDRIVE maps with elevation and superelevation (issue 17): at rest on crest-curve's
// hill their wheels stand on the road surface within 2 cm; on a superelevated curve their roll
// is the road's within 0.5 degrees; a car that leaves the drivable lanes is reported and keeps
// driving on the ground beside the road, which is the terrain the 3D view draws (issue 32),
// also across the hilly junction's fields; the ground's ray test has no cracks at the seams.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <optional>

#include "common/map/opendrive/reader.hpp"
#include "common/map/opendrive/terrain.hpp"
#include "common/map/opendrive/tests/shared_maps.hpp"
#include "sim-server/physics/ground.hpp"
#include "sim-server/physics/world.hpp"

namespace tb::server::physics {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

std::shared_ptr<const map::ScenarioMap> shared_map(const std::string& name) {
  return std::make_shared<const map::ScenarioMap>(
      std::make_shared<const map::odr::RoadNetwork>(
          map::odr::load_opendrive((map::odr::test::shared_maps() / name).string())),
      geodesy::Geodetic{48.0, 11.0, 500.0});
}

/// One car parked on lane @p lane of road "0"/"1" at s, stepped @p steps times.
struct Parked {
  World world;
  std::size_t car;
  Parked(std::shared_ptr<const map::ScenarioMap> map, const std::string& road, int lane, double s,
         int steps = 300)
      : world(std::move(map), WorldOptions{}) {
    scenario::Spawn spawn;
    spawn.where = scenario::RoadSpawn{road, lane, s, 0.0, false};
    car = world.add_vehicle(scenario::VehicleModel{}, 1, spawn_pose(world.map(), spawn));
    for (int i = 0; i < steps; ++i)
      world.step();
  }
  const wire::VehicleState& state() const { return world.states()[car]; }
};

/// Height of the road surface under (x, y).
double surface_z(const map::ScenarioMap& m, double x, double y, double near_z) {
  const auto at = m.locator().locate(x, y, near_z);
  EXPECT_TRUE(at) << "no lane under " << x << ", " << y;
  return at ? at->z : NAN;
}

TEST(RoadSurface, ACarAtRestOnTheCrestHasItsWheelsOnTheRoad) {
  const auto m = shared_map("crest-curve.xodr");
  ASSERT_FALSE(m->flat());
  // Before the hill, climbing it, at its top (6 m up) and on the far slope in the spiral.
  for (double s : {50.0, 215.0, 235.0, 270.0, 300.0, 330.0}) {
    for (int lane : {-1, 1}) {
      SCOPED_TRACE(testing::Message() << "s " << s << " lane " << lane);
      Parked p(m, "0", lane, s);
      EXPECT_TRUE(p.world.mesh_cast());
      const auto contact = p.world.wheels_in_contact(p.car);
      const auto wheels = p.world.wheel_contacts(p.car);
      for (int w = 0; w < 4; ++w) {
        EXPECT_TRUE(contact[w]) << "wheel " << w;
        EXPECT_NEAR(wheels[w][2], surface_z(*m, wheels[w][0], wheels[w][1], wheels[w][2]), 0.02)
            << "wheel " << w;
      }
      // Parked: it stays where it was put.
      EXPECT_LT(std::abs(p.state().speed), 0.02f);
      EXPECT_NEAR(
          p.state().position[2],
          surface_z(*m, p.state().position[0], p.state().position[1], p.state().position[2]), 0.05);
      EXPECT_EQ(p.world.off_road().departures(), 0u);
    }
  }
}

TEST(RoadSurface, OnASuperelevatedCurveTheCarRollsWithTheRoad) {
  const auto m = shared_map("straight_500_superelevation_elevation_curve.xodr");
  const map::odr::Road& road = m->network().roads.front();
  for (double s : {80.0, 100.0, 150.0, 200.0}) {
    for (int lane : {-1, 1}) {
      SCOPED_TRACE(testing::Message() << "s " << s << " lane " << lane);
      Parked p(m, road.id, lane, s);
      // ZYX roll of a car facing its lane's direction: the superelevation, turned round for a
      // lane that runs against s.
      const double want = (road.forward(lane) ? 1.0 : -1.0) * road.superelevation.value(s);
      EXPECT_GT(std::abs(want), 0.05);
      EXPECT_NEAR(p.state().roll * kDeg, want * kDeg, 0.5);
      EXPECT_LT(std::abs(p.state().speed), 0.02f);
    }
  }
}

/// A road of 300 m climbing at 5 % (1 m per 20 m), a lane each way, nothing beside it.
std::shared_ptr<const map::ScenarioMap> climbing_road() {
  return std::make_shared<const map::ScenarioMap>(
      std::make_shared<const map::odr::RoadNetwork>(map::odr::parse_opendrive(
          R"(<OpenDRIVE><header revMajor="1" revMinor="6"/>
<road id="1" length="300" junction="-1"><planView><geometry s="0" x="0" y="0" hdg="0" length="300"><line/></geometry></planView>
<elevationProfile><elevation s="0" a="10" b="0.05" c="0" d="0"/></elevationProfile>
<lanes><laneSection s="0"><left><lane id="1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></left>
<center><lane id="0" type="none"/></center><right><lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></right></laneSection></lanes></road></OpenDRIVE>)",
          "climbing.xodr")),
      geodesy::Geodetic{48.0, 11.0, 500.0});
}

TEST(RoadSurface, ACarThatLeavesTheLanesIsReportedAndDrivesOnBesideTheRoad) {
  World world(climbing_road(), WorldOptions{});
  const map::odr::Terrain terrain(world.map().network());
  // On the right lane at s = 40, heading 20 degrees right of the road: in 6 s at 6 m/s it
  // crosses the road's right edge (y = -3.5) and goes some 10 m beyond it.
  scenario::Spawn spawn;
  spawn.where = scenario::RoadSpawn{"1", -1, 40.0, 0.0, false};
  SpawnPose pose = spawn_pose(world.map(), spawn);
  pose.yaw = -20.0 / kDeg;
  pose.speed = 6.0;
  const double slope = 0.05;  // the road's plane: z = 10 + 0.05 x
  map::orientation_on(-slope / std::hypot(slope, 1.0), 0.0, 1.0 / std::hypot(slope, 1.0), pose.yaw,
                      pose.pitch, pose.roll);
  const std::size_t car = world.add_vehicle(scenario::VehicleModel{}, 77, pose);
  world.set_controls(car, {0.1f, 0.0f, 0.0f, false, false}, 0);
  bool reported = false;
  double min_clearance = 1e9, max_clearance = -1e9;
  std::optional<std::array<double, 2>> first_off;  // x, z
  for (int i = 0; i < 600; ++i) {
    world.step();
    for (const auto& e : world.off_road().take_events()) {
      if (e.left && e.station_id == 77) {
        reported = true;
        EXPECT_LT(e.y, -3.0);
        EXPECT_EQ(e.last_road, "1");
        EXPECT_EQ(e.last_lane, -1);
      }
    }
    const auto& s = world.states()[car];
    if (s.position[1] < -6.0) {
      // Beside the road the ground is the terrain the view draws (the same map, the same
      // options).
      const double ground = terrain.height_at(s.position[0], s.position[1]);
      if (!first_off)
        first_off = std::array<double, 2>{s.position[0], s.position[2]};
      min_clearance = std::min(min_clearance, s.position[2] - ground);
      max_clearance = std::max(max_clearance, s.position[2] - ground);
      const auto contact = world.wheels_in_contact(car);
      EXPECT_GE(contact[0] + contact[1] + contact[2] + contact[3], 3) << "step " << i;
    }
  }
  EXPECT_TRUE(reported);
  EXPECT_EQ(world.off_road().off_now(), 1u);
  EXPECT_EQ(world.off_road().departures(), 1u);
  EXPECT_TRUE(world.off_road().off(car));
  // It went well beside the road, and stood on the ground all the way (never fell through it).
  EXPECT_LT(world.states()[car].position[1], -8.0);
  EXPECT_GT(min_clearance, -0.05);
  EXPECT_LT(max_clearance, 0.05);
  // And that ground climbs beside the climbing road: by at least half the road's 5 % over the
  // distance the car went along it (a level verge or plane would not).
  ASSERT_TRUE(first_off);
  const auto& last = world.states()[car];
  EXPECT_GT(last.position[0] - (*first_off)[0], 10.0);
  EXPECT_GT(last.position[2] - (*first_off)[1], 0.5 * slope * (last.position[0] - (*first_off)[0]));
}

TEST(RoadSurface, ACarDrivenOffTheHillyJunctionsArmDrivesOnTheTerrainTheViewDraws) {
  // The shipped hilly junction: its east arm climbs 3 m from the junction. A car on the arm's
  // outbound lane at s = 15, turned 25 degrees to the right, at 6 m/s: it crosses the sidewalk
  // and rolls on across the open south-east field for 10 s.
  const char* root = std::getenv("TESTBED_ROOT");
  const auto path = std::filesystem::path(root != nullptr ? root : ".") / "scenarios" / "maps" /
                    "four_way_junction.xodr";
  const auto m = std::make_shared<const map::ScenarioMap>(
      std::make_shared<const map::odr::RoadNetwork>(map::odr::load_opendrive(path.string())),
      geodesy::Geodetic{48.0, 11.0, 500.0});
  World world(m, WorldOptions{});
  const map::odr::Terrain terrain(m->network());  // what sim-client's 3D view draws
  scenario::Spawn spawn;
  spawn.where = scenario::RoadSpawn{"1", -1, 15.0, 0.0, false};
  SpawnPose pose = spawn_pose(world.map(), spawn);
  pose.yaw -= 25.0 / kDeg;
  pose.speed = 6.0;
  const std::size_t car = world.add_vehicle(scenario::VehicleModel{}, 5, pose);
  world.set_controls(car, {0.15f, 0.0f, 0.0f, false, false}, 0);
  double worst = 0.0, z_min = 1e9, z_max = -1e9;
  int on_terrain = 0;
  for (int i = 0; i < 1000; ++i) {
    world.step();
    const auto& s = world.states()[car];
    // Off the sidewalk (its outer edge at y = -5.5) by more than the car's half length.
    if (s.position[1] > -8.0)
      continue;
    ++on_terrain;
    const double ground = terrain.height_at(s.position[0], s.position[1]);
    worst = std::max(worst, std::abs(s.position[2] - ground));
    z_min = std::min(z_min, static_cast<double>(s.position[2]));
    z_max = std::max(z_max, static_cast<double>(s.position[2]));
    const auto contact = world.wheels_in_contact(car);
    EXPECT_GE(contact[0] + contact[1] + contact[2] + contact[3], 3) << "step " << i;
  }
  EXPECT_GT(on_terrain, 500);
  EXPECT_TRUE(world.off_road().off(car));
  EXPECT_LT(world.states()[car].position[1], -25.0);  // well out into the field
  // It followed the terrain to a few centimetres, over ground that is not level (it climbed
  // or fell with the field between the arms by more than half a metre).
  EXPECT_LT(worst, 0.05);
  EXPECT_GT(z_max - z_min, 0.5);
  RecordProperty("terrain_deviation_mm", std::to_string(std::lround(worst * 1000)));
}

TEST(Ground, RaysFindTheRoadAcrossEverySeamOfAJunctionMap) {
  // Vertical rays on a dense grid over the 4-way junction's roads, connecting roads and their
  // seams (the mesh forced, as for a map with elevation): wherever the locator finds a lane, the
  // ground is hit on that lane's surface.
  const auto m = shared_map("simple_4way_intersection.xodr");
  const Ground g(*m, 50.0, true);
  EXPECT_FALSE(g.flat());
  const auto& net = m->network();
  std::size_t tested = 0;
  for (double x = 0; x <= 226; x += 0.37) {
    for (double y = -113; y <= 113; y += 0.41) {
      const auto at = m->locator().locate(x, y);
      if (!at)
        continue;
      const auto hit = g.cast({x, y, at->z + 1.0}, {x, y, at->z - 1.0});
      ASSERT_TRUE(hit) << x << ", " << y << " on road " << net.roads[at->ref.road].id;
      EXPECT_NEAR(hit->point.z, at->z, 0.02) << x << ", " << y;
      ++tested;
    }
  }
  EXPECT_GT(tested, 15000u);  // 1068 m of lanes, one ray per 0.15 m^2
}

TEST(Ground, FlatMapsAreThePlaneAndTheFlatCastIsRefusedOnHills) {
  const World flat(scenario::MapSpec{}, WorldOptions{});
  EXPECT_FALSE(flat.mesh_cast());
  EXPECT_THROW(World(climbing_road(), WorldOptions{.ground_cast = GroundCast::kFlat}),
               std::invalid_argument);
  const World forced(scenario::MapSpec{}, WorldOptions{.ground_cast = GroundCast::kMesh});
  EXPECT_TRUE(forced.mesh_cast());
}

TEST(Ground, AMapFarFromItsOriginIsComputedNearTheOriginOfThePhysics) {
  // A road at UTM-like coordinates: positions come back in the map's frame, to the centimetre.
  const auto m = std::make_shared<const map::ScenarioMap>(
      std::make_shared<const map::odr::RoadNetwork>(map::odr::parse_opendrive(
          R"(<OpenDRIVE><header revMajor="1" revMinor="6"/>
<road id="1" length="300" junction="-1"><planView><geometry s="0" x="691000.5" y="5334000.25" hdg="0.3" length="300"><line/></geometry></planView>
<elevationProfile><elevation s="0" a="520" b="0.01" c="0" d="0"/></elevationProfile>
<lanes><laneSection s="0"><center><lane id="0" type="none"/></center><right><lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></right></laneSection></lanes></road></OpenDRIVE>)",
          "far.xodr")),
      geodesy::Geodetic{48.0, 11.0, 0.0});
  World world(m, WorldOptions{});
  scenario::Spawn spawn;
  spawn.where = scenario::RoadSpawn{"1", -1, 100.0, 0.0, false};
  const SpawnPose pose = spawn_pose(*m, spawn);
  const std::size_t car = world.add_vehicle(scenario::VehicleModel{}, 1, pose);
  for (int i = 0; i < 200; ++i)
    world.step();
  const auto& s = world.states()[car];
  EXPECT_NEAR(s.position[0], pose.x, 0.02);
  EXPECT_NEAR(s.position[1], pose.y, 0.02);
  EXPECT_NEAR(s.position[2], pose.z, 0.03);
  EXPECT_EQ(world.off_road().departures(), 0u);
}

}  // namespace
}  // namespace tb::server::physics
