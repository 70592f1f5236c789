// The warm-up (scenario warmup_s): negative sim time, every vehicle held on its run-up to its
// spawn pose, the physics taking over at sim time 0 with the controls the drivers sent last.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/map/road_map.hpp"
#include "common/map/scenario_map.hpp"
#include "common/scenario/loader.hpp"
#include "sim-server/physics/run_up.hpp"
#include "sim-server/physics/world.hpp"

namespace tb::server::physics {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(RunUp, StraightBackAlongTheHeading) {
  const SpawnPose spawn{.x = 100.0, .y = 5.0, .yaw = kPi / 2, .speed = 10.0};
  const RunUpPose p = run_up(spawn, -2.0);
  EXPECT_NEAR(p.x, 100.0, 1e-9);
  EXPECT_NEAR(p.y, -15.0, 1e-9);  // 20 m south of the spawn, heading north
  EXPECT_NEAR(p.yaw, kPi / 2, 1e-12);
  EXPECT_DOUBLE_EQ(p.yaw_rate, 0.0);
  // At and after sim time 0: the spawn pose.
  EXPECT_DOUBLE_EQ(run_up(spawn, 0.0).y, 5.0);
  EXPECT_DOUBLE_EQ(run_up(spawn, 1.0).y, 5.0);
}

TEST(RunUp, ParkedCarStandsOnItsSpawn) {
  const SpawnPose spawn{.x = 3.0, .y = 4.0, .yaw = 1.0, .speed = 0.0, .curvature = 0.01};
  const RunUpPose p = run_up(spawn, -3.0);
  EXPECT_DOUBLE_EQ(p.x, 3.0);
  EXPECT_DOUBLE_EQ(p.y, 4.0);
  EXPECT_DOUBLE_EQ(p.yaw, 1.0);
}

TEST(RunUp, AQuarterOfARingBack) {
  // Counter-clockwise on a circle of 150 m round the origin: at (150, 0) heading north. A
  // quarter turn back (150·π/2 m at 15 m/s = 5π s) is (0, -150), heading east.
  const SpawnPose spawn{
      .x = 150.0, .y = 0.0, .yaw = kPi / 2, .speed = 15.0, .curvature = 1.0 / 150};
  const RunUpPose p = run_up(spawn, -5.0 * kPi);
  EXPECT_NEAR(p.x, 0.0, 1e-9);
  EXPECT_NEAR(p.y, -150.0, 1e-9);
  EXPECT_NEAR(p.yaw, 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(p.yaw_rate, 0.1);       // v / R
  EXPECT_DOUBLE_EQ(p.lateral_accel, 1.5);  // v² / R, to the left
  // Clockwise (curvature < 0): the mirror image.
  const SpawnPose cw{.x = 150.0, .y = 0.0, .yaw = -kPi / 2, .speed = 15.0, .curvature = -1.0 / 150};
  const RunUpPose q = run_up(cw, -5.0 * kPi);
  EXPECT_NEAR(q.x, 0.0, 1e-9);
  EXPECT_NEAR(q.y, 150.0, 1e-9);
  EXPECT_NEAR(q.yaw, 0.0, 1e-12);
}

scenario::Scenario ring_scenario() {
  return scenario::parse(R"({
    "name": "warm-up", "map": {"type": "ring", "lanes": 2, "radius": 150},
    "origin": {"lat": 48.1, "lon": 11.5}, "warmup_s": 2,
    "vehicles": [
      {"id": "moving", "station_id": 1, "spawn": {"lane": 0, "s": 0, "speed": 20}},
      {"id": "against", "station_id": 2, "spawn": {"lane": 1, "s": 300, "speed": 10,
                                                    "direction": "against"}},
      {"id": "parked", "station_id": 3, "spawn": {"lane": 1, "s": 100}}
    ]})",
                         "warmup.json");
}

TEST(WorldWarmUp, HoldsEveryCarOnItsLaneUpToItsSpawnThenStepsThePhysics) {
  const auto sc = ring_scenario();
  const auto steps = static_cast<std::uint64_t>(std::llround(sc.warmup_s * sc.rates.physics_hz));
  ASSERT_EQ(steps, 200u);
  World w(sc, WorldOptions{.step_s = 0.01, .warmup_steps = steps});
  const map::RoadMap road(sc.map);
  const map::ScenarioMap placed(sc);
  std::vector<SpawnPose> spawns;
  for (const auto& v : sc.vehicles)
    spawns.push_back(spawn_pose(placed, v.spawn));
  EXPECT_EQ(w.sim_time_ns(), -2'000'000'000);
  EXPECT_TRUE(w.warming_up());
  // Drivers' controls during the warm-up move nothing: full throttle on the parked car.
  w.set_controls(2, {1.0f, 0.0f, 0.0f, false, false}, 0);
  double travelled = 0.0;
  std::array<double, 2> last{w.states()[0].position[0], w.states()[0].position[1]};
  for (std::uint64_t k = 1; k <= steps; ++k) {
    w.step(1000 + static_cast<std::int64_t>(k));
    ASSERT_EQ(w.tick(), k);
    const double t = -2.0 + 0.01 * static_cast<double>(k);
    ASSERT_EQ(w.states()[0].sim_time_ns, std::llround(t * 1e9));
    for (std::size_t i = 0; i < 3; ++i) {
      const auto& s = w.states()[i];
      const auto& lane =
          road.lane(0, std::get<scenario::LaneSpawn>(sc.vehicles[i].spawn.where).lane);
      // On its lane's centre line, at its spawn speed, along the lane (or against it).
      EXPECT_NEAR(map::project(lane.centre, {s.position[0], s.position[1]}).lateral, 0.0, 1e-6);
      EXPECT_FLOAT_EQ(s.speed, static_cast<float>(spawns[i].speed));
      EXPECT_NEAR(std::hypot(s.velocity[0], s.velocity[1]), spawns[i].speed, 1e-4);
      EXPECT_NEAR(s.yaw_rate, spawns[i].speed * spawns[i].curvature, 1e-6);
      EXPECT_EQ(s.step_wall_ns, 1000 + static_cast<std::int64_t>(k));
    }
    EXPECT_FLOAT_EQ(w.states()[2].controls.throttle, 0.0f);  // the held car's, not the driver's
    EXPECT_FLOAT_EQ(w.states()[2].controls.brake, 1.0f);
    travelled +=
        std::hypot(w.states()[0].position[0] - last[0], w.states()[0].position[1] - last[1]);
    last = {w.states()[0].position[0], w.states()[0].position[1]};
  }
  EXPECT_NEAR(travelled, 20.0 * 2.0, 1e-3);  // from the state of sim time -2 s, 200 steps of 0.2 m
  // Sim time 0: every car exactly on its spawn pose, the curvature of its lane for the turn.
  EXPECT_EQ(w.sim_time_ns(), 0);
  EXPECT_FALSE(w.warming_up());
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(w.states()[i].position[0], spawns[i].x, 1e-9);
    EXPECT_NEAR(w.states()[i].position[1], spawns[i].y, 1e-9);
    EXPECT_NEAR(std::remainder(w.states()[i].yaw - spawns[i].yaw, 2 * kPi), 0.0, 1e-6);
  }
  EXPECT_GT(spawns[0].curvature, 0.0);  // counter-clockwise ring: a left turn
  EXPECT_LT(spawns[1].curvature, 0.0);  // against it: a right turn
  // Then the physics, from there, with the controls the drivers sent: the parked car pulls away.
  for (int k = 0; k < 100; ++k)
    w.step();
  EXPECT_EQ(w.sim_time_ns(), 1'000'000'000);
  // Rolling on from its spawn speed, the throttle closed (engine braking, drag).
  EXPECT_GT(w.states()[0].speed, 18.5);
  EXPECT_LT(w.states()[0].speed, 20.0);
  EXPECT_GT(w.states()[2].speed, 0.5);
  EXPECT_FLOAT_EQ(w.states()[2].controls.throttle, 1.0f);
}

TEST(WorldWarmUp, NoWarmUpStartsAtSimTimeZero) {
  World w(ring_scenario());
  EXPECT_FALSE(w.warming_up());
  EXPECT_EQ(w.sim_time_ns(), 0);
  w.step();
  EXPECT_EQ(w.sim_time_ns(), 10'000'000);
}

}  // namespace
}  // namespace tb::server::physics
