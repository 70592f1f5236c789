// Cars on OpenDRIVE maps with elevation and superelevation (issue 17): at rest on crest-curve's
// hill their wheels stand on the road surface within 2 cm; on a superelevated curve their roll
// is the road's within 0.5 degrees; a car that leaves the drivable lanes is reported and keeps
// driving on the ground beside the road; the ground's ray test has no cracks at the seams.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/map/opendrive/reader.hpp"
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
  scenario::Spawn spawn;
  spawn.where = scenario::RoadSpawn{"1", -1, 40.0, 0.0, false};
  spawn.speed = 8.0;
  const std::size_t car =
      world.add_vehicle(scenario::VehicleModel{}, 77, spawn_pose(world.map(), spawn));
  // Steer right, off the road's right edge (y < -3.5), and keep rolling through the verge.
  world.set_controls(car, {0.15f, 0.0f, 0.35f, false, false}, 0);
  bool reported = false;
  double min_clearance = 1e9;
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
      // Beside the road the verge starts 5 cm below its edge and falls at 4 %.
      const double edge = 10.0 + 0.05 * s.position[0];
      const double verge = edge - 0.05 - 0.04 * (-s.position[1] - 3.5);
      min_clearance = std::min(min_clearance, s.position[2] - verge);
      const auto contact = world.wheels_in_contact(car);
      EXPECT_GE(contact[0] + contact[1] + contact[2] + contact[3], 3) << "step " << i;
    }
  }
  EXPECT_TRUE(reported);
  EXPECT_EQ(world.off_road().off_now(), 1u);
  EXPECT_EQ(world.off_road().departures(), 1u);
  EXPECT_TRUE(world.off_road().off(car));
  // It went well beside the road, and stood on the verge all the way (never fell through it).
  EXPECT_LT(world.states()[car].position[1], -8.0);
  EXPECT_GT(min_clearance, -0.1);
  EXPECT_LT(min_clearance, 0.1);
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
