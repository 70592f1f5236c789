#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sim-client/driver/scripted_driver.hpp"

#include "common/map/builtin_network.hpp"
#include "sim-client/driver/tests/plant.hpp"

namespace tb::client {
namespace {

constexpr double kPi = std::numbers::pi;
using test::Plant;

struct Pose {
  struct {
    double x, y;
  } p;
  double yaw;
};

// A built-in layout as the drivers see it, and lane followers placed on it as the scenario's
// lane spawns place them.
struct World {
  explicit World(const scenario::MapSpec& s)
      : spec(s), map(std::make_shared<const map::ScenarioMap>(s, std::nullopt)) {}
  LaneFollowDriver driver(const scenario::LaneFollowDriver& d, const scenario::VehicleModel& m,
                          int lane, double s, bool against = false) const {
    scenario::Vehicle v;
    v.spawn.where = scenario::LaneSpawn{0, lane, s, against};
    const auto start = map::vehicle_start(v, map.scenario_map());
    if (!start)
      throw std::invalid_argument("no lane there");
    return LaneFollowDriver(d, m, map,
                            map::RoutePlan(map.network(), map.graph(), d.route, *start, 1));
  }
  // Where built-in lane @p lane puts a car at @p s: x, y and the lane's yaw.
  Pose pose(int lane, double s) const {
    scenario::Vehicle v;
    v.spawn.where = scenario::LaneSpawn{0, lane, s, false};
    const auto st = map::vehicle_start(v, map.scenario_map());
    const auto p = map::odr::lane_pose(map.network(), st->road, st->lane, st->s);
    const double yaw = map.network().roads[0].forward(st->lane) ? p.heading : p.heading + kPi;
    return {{p.x, p.y}, yaw};
  }
  scenario::MapSpec spec;
  DriveMap map;
};

scenario::MapSpec straight_road() {
  scenario::MapSpec m;
  m.type = scenario::MapType::kStraight;
  m.lanes = 2;
  m.oncoming_lanes = 1;
  m.length = 1000.0;
  return m;
}

scenario::MapSpec ring_road() {
  scenario::MapSpec m;
  m.type = scenario::MapType::kRing;
  m.lanes = 2;
  m.oncoming_lanes = 1;
  m.radius = 150.0;
  return m;
}

scenario::LaneFollowDriver profile(std::vector<scenario::SpeedPoint> pts, bool by_distance) {
  scenario::LaneFollowDriver d;
  d.profile = std::move(pts);
  d.by_distance = by_distance;
  d.max_accel = 2.0;
  d.max_decel = 3.0;
  return d;
}

// How far the car's body may move sideways before a wheel leaves its lane.
double lane_margin(const scenario::VehicleModel& m, double lane_width) {
  return (lane_width - m.width_m) / 2.0;
}

TEST(LaneFollowDriver, ReachesTargetSpeedAndKeepsLaneOnStraight) {
  const World road(straight_road());
  const scenario::VehicleModel model;
  LaneFollowDriver driver = road.driver(profile({{0.0, 13.9}}, false), model, 0, 20.0);
  // Start off-centre and a little askew, standing still.
  const Pose start = road.pose(0, 20.0);
  Plant car(start.p.x, start.p.y + 0.5, start.yaw + 0.05, 0.0);
  double max_accel = 0.0, max_lateral = 0.0;
  for (int i = 0; i < 100 * 40; ++i) {  // 40 s at 100 Hz
    car.step(driver.update(car.state()), 0.01);
    max_accel = std::max(max_accel, car.accel());
    max_lateral = std::max(max_lateral, std::abs(driver.status().lateral));
    if (i >= 100 * 12) {
      ASSERT_NEAR(car.speed(), 13.9, 0.5) << "at t = " << i / 100.0 << " s";
    }
  }
  EXPECT_LT(max_lateral, lane_margin(model, 3.5));
  EXPECT_NEAR(driver.status().lateral, 0.0, 0.1);
  // Comfortable acceleration: the reference rises at max_accel; feedback adds a little.
  EXPECT_LT(max_accel, 2.0 * 1.3);
}

TEST(LaneFollowDriver, FollowsDistanceProfileAroundRing) {
  const World road(ring_road());
  const scenario::VehicleModel model;
  LaneFollowDriver driver =
      road.driver(profile({{0.0, 15.0}, {400.0, 15.0}, {450.0, 8.0}}, true), model, 0, 0.0);
  const Pose start = road.pose(0, 0.0);
  Plant car(start.p.x, start.p.y, start.yaw, 15.0);
  double max_lateral = 0.0;
  double min_accel = 0.0;
  for (int i = 0; i < 100 * 90; ++i) {  // 90 s: about two laps
    const wire::VehicleState s = car.state();
    car.step(driver.update(s), 0.01);
    max_lateral = std::max(max_lateral, std::abs(driver.status().lateral));
    min_accel = std::min(min_accel, car.accel());
    const double d = driver.status().distance;
    if (d < 380.0 && i > 300) {
      ASSERT_NEAR(car.speed(), 15.0, 0.5) << "at " << d << " m";
    }
    if (d > 480.0) {
      ASSERT_NEAR(car.speed(), 8.0, 0.5) << "at " << d << " m";
    }
  }
  EXPECT_GT(driver.status().distance, 600.0);
  EXPECT_LT(max_lateral, lane_margin(model, 3.5));
  EXPECT_GT(min_accel, -3.0 * 1.3);
}

TEST(LaneFollowDriver, StartsAtSimTimeZeroNotInTheWarmUp) {
  // Held on its run-up for 3 s at 15 m/s (sim-server's warm-up), the car's distance profile
  // must count from its spawn: braking from 20 m, not 25 m before it.
  const World road(straight_road());
  LaneFollowDriver driver = road.driver(profile({{0.0, 15.0}, {20.0, 15.0}, {21.0, 0.0}}, true),
                                        scenario::VehicleModel{}, 0, 100.0);
  const Pose spawn = road.pose(0, 100.0);
  for (int k = -300; k < 0; ++k) {
    wire::VehicleState s;
    s.sim_time_ns = k * 10'000'000LL;
    s.position = {spawn.p.x + 15.0 * k * 0.01, spawn.p.y, 0.0};
    s.yaw = static_cast<float>(spawn.yaw);
    s.speed = 15.0f;
    const wire::Controls c = driver.update(s);
    ASSERT_EQ(c, wire::Controls{}) << "released during the warm-up";
  }
  EXPECT_DOUBLE_EQ(driver.status().distance, 0.0);
  Plant car(spawn.p.x, spawn.p.y, spawn.yaw, 15.0);
  while (driver.status().distance < 19.0) {
    const wire::Controls c = driver.update(car.state());
    ASSERT_FLOAT_EQ(c.brake, 0.0f) << "at " << driver.status().distance << " m";
    car.step(c, 0.01);
  }
}

TEST(LaneFollowDriver, StopsBeforeTheEndOfAnOpenLane) {
  const World road(straight_road());
  LaneFollowDriver driver =
      road.driver(profile({{0.0, 20.0}}, false), scenario::VehicleModel{}, 0, 700.0);
  const Pose start = road.pose(0, 700.0);
  Plant car(start.p.x, start.p.y, start.yaw, 20.0);
  for (int i = 0; i < 100 * 60; ++i)
    car.step(driver.update(car.state()), 0.01);
  EXPECT_NEAR(car.speed(), 0.0, 0.01);
  EXPECT_GT(driver.status().remaining, 0.0) << "ran past the end of the lane";
  EXPECT_LT(driver.status().remaining, 15.0);
  EXPECT_LT(std::abs(driver.status().lateral), 0.3);
}

TEST(LaneFollowDriver, DrivesAgainstTheLaneDirection) {
  const World road(straight_road());
  // Lane 0 runs east; driving against it means heading west from s = 600.
  LaneFollowDriver driver =
      road.driver(profile({{0.0, 10.0}}, false), scenario::VehicleModel{}, 0, 600.0, true);
  const Pose at = road.pose(0, 600.0);
  Plant car(at.p.x, at.p.y - 0.4, at.yaw + kPi, 10.0);
  for (int i = 0; i < 100 * 30; ++i)
    car.step(driver.update(car.state()), 0.01);
  EXPECT_NEAR(car.state().position[0], 600.0 - 300.0, 10.0);
  EXPECT_NEAR(car.state().position[1], at.p.y, 0.1);
  EXPECT_NEAR(car.speed(), 10.0, 0.5);
}

TEST(LaneFollowDriver, ReversesAlongTheLaneAtANegativeTargetSpeed) {
  // Forward at 5 m/s for 6 s, then -3 m/s (issue 22): the car stops, engages reverse and backs
  // along its lane, staying in it, at 3 m/s.
  const World road(straight_road());
  const scenario::VehicleModel model;
  LaneFollowDriver driver =
      road.driver(profile({{0.0, 5.0}, {6.0, 5.0}, {6.1, -3.0}}, false), model, 0, 100.0);
  const Pose start = road.pose(0, 100.0);
  Plant car(start.p.x, start.p.y, start.yaw, 0.0);
  double max_lateral = 0.0, min_speed = 0.0;
  bool reversed = false;
  for (int i = 0; i < 100 * 30; ++i) {  // 30 s at 100 Hz
    const wire::Controls c = driver.update(car.state());
    reversed = reversed || c.reverse;
    car.step(c, 0.01);
    max_lateral = std::max(max_lateral, std::abs(driver.status().lateral));
    min_speed = std::min(min_speed, car.speed());
  }
  EXPECT_TRUE(reversed);
  EXPECT_NEAR(car.speed(), -3.0, 0.3);
  EXPECT_GT(min_speed, -3.0 * 1.3);  // no overshoot beyond 30 %
  EXPECT_LT(max_lateral, lane_margin(model, 3.5));
  EXPECT_NEAR(driver.status().lateral, 0.0, 0.2);
}

TEST(LaneFollowDriver, ProfileInterpolatesAndHoldsEnds) {
  const std::vector<scenario::SpeedPoint> p{{10.0, 5.0}, {20.0, 15.0}, {30.0, 15.0}};
  EXPECT_DOUBLE_EQ(LaneFollowDriver::profile_speed(p, 0.0), 5.0);
  EXPECT_DOUBLE_EQ(LaneFollowDriver::profile_speed(p, 15.0), 10.0);
  EXPECT_DOUBLE_EQ(LaneFollowDriver::profile_speed(p, 25.0), 15.0);
  EXPECT_DOUBLE_EQ(LaneFollowDriver::profile_speed(p, 99.0), 15.0);
}

TEST(LaneFollowDriver, RejectsEmptyProfile) {
  const World road(straight_road());
  EXPECT_THROW(road.driver(profile({}, false), scenario::VehicleModel{}, 0, 10.0),
               std::invalid_argument);
}

TEST(TimelineDriver, EachStepHoldsUntilTheNext) {
  scenario::TimelineDriver spec;
  spec.steps = {{1.0, 0.5, 0.0, 0.1, false, false}, {3.0, 0.0, 0.8, -0.2, false, true}};
  TimelineDriver d(spec);
  EXPECT_EQ(d.at(0.5), wire::Controls{});
  EXPECT_FLOAT_EQ(d.at(1.0).throttle, 0.5f);
  EXPECT_FLOAT_EQ(d.at(2.99).steer, 0.1f);
  const wire::Controls late = d.at(10.0);
  EXPECT_FLOAT_EQ(late.brake, 0.8f);
  EXPECT_FLOAT_EQ(late.steer, -0.2f);
  EXPECT_TRUE(late.handbrake);
  wire::VehicleState s;
  s.sim_time_ns = 3'000'000'000;
  EXPECT_TRUE(d.update(s).handbrake);
  // The warm-up (negative sim time) is before every step; a step at 0 acts from sim time 0.
  scenario::TimelineDriver brake;
  brake.steps = {{0.0, 0.0, 1.0, 0.0, false, false}};
  TimelineDriver b(brake);
  EXPECT_EQ(b.at(-0.01), wire::Controls{});
  EXPECT_FLOAT_EQ(b.at(0.0).brake, 1.0f);
}

TEST(ScriptedDriver, MadeFromTheScenarioDriverField) {
  const World road(straight_road());
  scenario::Scenario sc;
  sc.map = straight_road();
  scenario::Vehicle v;
  v.id = "a";
  v.spawn.where = scenario::LaneSpawn{0, 1, 100.0, false};
  EXPECT_EQ(make_scripted_driver(v, sc, road.map), nullptr);
  v.driver = scenario::TimelineDriver{{{0.0, 1.0}}};
  EXPECT_NE(dynamic_cast<TimelineDriver*>(make_scripted_driver(v, sc, road.map).get()), nullptr);
  v.driver = profile({{0, 5}}, false);
  EXPECT_NE(dynamic_cast<LaneFollowDriver*>(make_scripted_driver(v, sc, road.map).get()), nullptr);
  // A pose spawn heading west in the eastbound lane drives against it.
  v.spawn.where = scenario::PoseSpawn{100.0, -1.75, 270.0};
  const auto r = map::vehicle_start(v, road.map.scenario_map());
  ASSERT_TRUE(r);
  EXPECT_EQ(r->lane, -1);
  EXPECT_TRUE(r->against);
  v.spawn.where = scenario::PoseSpawn{100.0, 30.0, 90.0};
  EXPECT_THROW(make_scripted_driver(v, sc, road.map), std::invalid_argument);
}

}  // namespace
}  // namespace tb::client
