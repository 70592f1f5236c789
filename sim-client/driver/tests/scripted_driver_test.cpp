#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sim-client/driver/scripted_driver.hpp"

namespace tb::client {
namespace {

constexpr double kPi = std::numbers::pi;

// A kinematic bicycle with a simple longitudinal model, deliberately not the one the driver
// assumes (heavier, weaker engine, steering that lags), so that the test checks the driver's
// feedback and not its own feed-forward.
class Plant {
 public:
  Plant(double x, double y, double yaw, double speed) : x_(x), y_(y), yaw_(yaw), v_(speed) {}

  void step(const wire::Controls& c, double dt) {
    const double max_steer = 36.0 * kPi / 180.0;
    const double wanted = -c.steer * max_steer;
    const double rate = 0.6 * dt;  // rad/s of road-wheel angle
    delta_ += std::clamp(wanted - delta_, -rate, rate);
    const double mass = 1500.0;
    // A gearbox that engages reverse (or forward) only below 0.5 m/s, like the server's.
    if (c.reverse != reverse_ && std::abs(v_) < 0.5)
      reverse_ = c.reverse;
    const double gear = reverse_ ? -1.0 : 1.0;
    const double drive =
        gear * c.throttle * std::min(5000.0, 70000.0 * 0.9 / std::max(std::abs(v_), 1.0));
    const double brake = c.brake * 9000.0;
    const double sign = v_ > 0.0 ? 1.0 : (v_ < 0.0 ? -1.0 : 0.0);
    const double resist =
        sign * (0.5 * 1.2 * 0.33 * 2.3 * v_ * v_ + (std::abs(v_) > 0.01 ? 0.013 * mass * 9.81 : 0));
    double a = (drive - resist) / mass;
    const double v_free = v_ + a * dt;
    // Brakes oppose the motion and hold a standing car.
    const double dv_brake = brake / mass * dt;
    double v_next = v_free;
    if (v_free > dv_brake)
      v_next = v_free - dv_brake;
    else if (v_free < -dv_brake)
      v_next = v_free + dv_brake;
    else
      v_next = 0.0;
    a = (v_next - v_) / dt;
    accel_ = a;
    v_ = v_next;
    // Rear-axle reference point.
    const double rx = x_ - std::cos(yaw_) * kWheelbase / 2,
                 ry = y_ - std::sin(yaw_) * kWheelbase / 2;
    const double nrx = rx + v_ * std::cos(yaw_) * dt, nry = ry + v_ * std::sin(yaw_) * dt;
    yaw_ += v_ * std::tan(delta_) / kWheelbase * dt;
    x_ = nrx + std::cos(yaw_) * kWheelbase / 2;
    y_ = nry + std::sin(yaw_) * kWheelbase / 2;
    t_ns_ += static_cast<std::int64_t>(dt * 1e9);
  }

  wire::VehicleState state() const {
    wire::VehicleState s;
    s.sim_time_ns = t_ns_;
    s.position = {x_, y_, 0.0};
    s.yaw = static_cast<float>(yaw_);
    s.speed = static_cast<float>(v_);
    return s;
  }
  double accel() const { return accel_; }
  double speed() const { return v_; }

  static constexpr double kWheelbase = 2.637;

 private:
  double x_, y_, yaw_, v_;
  double delta_ = 0.0;
  double accel_ = 0.0;
  bool reverse_ = false;
  std::int64_t t_ns_ = 0;
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
  const map::RoadMap road(straight_road());
  const scenario::VehicleModel model;
  LaneFollowDriver driver(profile({{0.0, 13.9}}, false), model, road, {0, 0, false});
  // Start off-centre and a little askew, standing still.
  const map::Pose start = road.lane_pose(0, 0, 20.0);
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
  const map::RoadMap road(ring_road());
  const scenario::VehicleModel model;
  LaneFollowDriver driver(profile({{0.0, 15.0}, {400.0, 15.0}, {450.0, 8.0}}, true), model, road,
                          {0, 0, false});
  const map::Pose start = road.lane_pose(0, 0, 0.0);
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
  const map::RoadMap road(straight_road());
  LaneFollowDriver driver(profile({{0.0, 15.0}, {20.0, 15.0}, {21.0, 0.0}}, true),
                          scenario::VehicleModel{}, road, {0, 0, false});
  const map::Pose spawn = road.lane_pose(0, 0, 100.0);
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
  const map::RoadMap road(straight_road());
  LaneFollowDriver driver(profile({{0.0, 20.0}}, false), scenario::VehicleModel{}, road,
                          {0, 0, false});
  const map::Pose start = road.lane_pose(0, 0, 700.0);
  Plant car(start.p.x, start.p.y, start.yaw, 20.0);
  for (int i = 0; i < 100 * 60; ++i)
    car.step(driver.update(car.state()), 0.01);
  EXPECT_NEAR(car.speed(), 0.0, 0.01);
  EXPECT_GT(driver.status().remaining, 0.0) << "ran past the end of the lane";
  EXPECT_LT(driver.status().remaining, 15.0);
  EXPECT_LT(std::abs(driver.status().lateral), 0.3);
}

TEST(LaneFollowDriver, DrivesAgainstTheLaneDirection) {
  const map::RoadMap road(straight_road());
  // Lane 0 runs east; driving against it means heading west from s = 600.
  LaneFollowDriver driver(profile({{0.0, 10.0}}, false), scenario::VehicleModel{}, road,
                          {0, 0, true});
  const map::Pose at = road.lane_pose(0, 0, 600.0);
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
  const map::RoadMap road(straight_road());
  const scenario::VehicleModel model;
  LaneFollowDriver driver(profile({{0.0, 5.0}, {6.0, 5.0}, {6.1, -3.0}}, false), model, road,
                          {0, 0, false});
  const map::Pose start = road.lane_pose(0, 0, 100.0);
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
  const map::RoadMap road(straight_road());
  EXPECT_THROW(LaneFollowDriver(profile({}, false), scenario::VehicleModel{}, road, {0, 0, false}),
               std::invalid_argument);
  EXPECT_THROW(
      LaneFollowDriver(profile({{0, 1}}, false), scenario::VehicleModel{}, road, {0, 7, false}),
      std::out_of_range);
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
  const map::RoadMap road(straight_road());
  scenario::Vehicle v;
  v.id = "a";
  v.spawn.where = scenario::LaneSpawn{0, 1, 100.0, false};
  EXPECT_EQ(make_scripted_driver(v, road), nullptr);
  v.driver = scenario::TimelineDriver{{{0.0, 1.0}}};
  EXPECT_NE(dynamic_cast<TimelineDriver*>(make_scripted_driver(v, road).get()), nullptr);
  v.driver = profile({{0, 5}}, false);
  EXPECT_NE(dynamic_cast<LaneFollowDriver*>(make_scripted_driver(v, road).get()), nullptr);
  // A pose spawn heading west in the eastbound lane drives against it.
  v.spawn.where = scenario::PoseSpawn{100.0, -1.75, 270.0};
  const LaneRef r = start_lane(v, road);
  EXPECT_EQ(r.lane, 0);
  EXPECT_TRUE(r.against);
  v.spawn.where = scenario::PoseSpawn{100.0, 30.0, 90.0};
  EXPECT_THROW(start_lane(v, road), std::invalid_argument);
}

}  // namespace
}  // namespace tb::client
