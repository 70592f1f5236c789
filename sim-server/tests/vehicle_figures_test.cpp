// The default vehicle model against the published figures of the car it stands for, the
// Volkswagen Golf VII 1.4 TSI 90 kW (manufacturer's 2013 data sheet: 0–100 km/h 9.3 s, top
// speed 203 km/h, turning circle 10.9 m; braking 100–0 km/h about 36 m in magazine tests).
// Each figure must lie within 15 %.

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "sim-server/physics/world.hpp"

namespace tb::server::physics {
namespace {

constexpr double kKmh = 1.0 / 3.6;
constexpr double kTolerance = 0.15;

struct Bench {
  World world;
  std::size_t car;
  explicit Bench(double speed = 0.0)
      : world(scenario::MapSpec{.type = scenario::MapType::kStraight, .length = 8000.0},
              WorldOptions{}),
        car(world.add_vehicle(scenario::VehicleModel{}, 1, SpawnPose{20.0, -1.75, 0.0, speed})) {}
  const wire::VehicleState& state() const { return world.states()[car]; }
  void drive(const wire::Controls& c) { world.set_controls(car, c, 0); }
  double t() const { return world.sim_time_ns() * 1e-9; }
};

void expect_near_published(double measured, double published, const char* what) {
  EXPECT_NEAR(measured, published, published * kTolerance) << what;
  std::printf("%s: measured %.2f, published %.2f (%+.1f %%)\n", what, measured, published,
              (measured / published - 1.0) * 100.0);
}

TEST(VehicleFigures, SettlesOnItsWheelsAndStaysParked) {
  Bench b;
  for (int i = 0; i < 300; ++i)
    b.world.step();
  EXPECT_NEAR(b.state().position[2], 0.0, 0.03);
  EXPECT_NEAR(b.state().position[0], 20.0, 0.02);
  EXPECT_LT(std::abs(b.state().speed), 0.01f);
  EXPECT_LT(std::abs(b.state().pitch), 0.02f);
}

TEST(VehicleFigures, ZeroToHundredKmh) {
  Bench b;
  for (int i = 0; i < 100; ++i)
    b.world.step();
  const double t0 = b.t();
  b.drive({1.0f, 0.0f, 0.0f, false, false});
  while (b.state().speed < 100.0 * kKmh && b.t() - t0 < 30.0)
    b.world.step();
  expect_near_published(b.t() - t0, 9.3, "0-100 km/h, s");
  EXPECT_EQ(b.state().gear, 3);
}

TEST(VehicleFigures, TopSpeed) {
  Bench b(30.0);
  b.drive({1.0f, 0.0f, 0.0f, false, false});
  double at_130 = 0.0;
  while (b.t() < 150.0) {
    b.world.step();
    if (at_130 == 0.0 && b.t() >= 130.0)
      at_130 = b.state().speed;
  }
  const double top = b.state().speed;
  // Settled: less than 1 km/h gained over the last 20 s.
  EXPECT_LT(top - at_130, 1.0 * kKmh) << "still accelerating";
  expect_near_published(top / kKmh, 203.0, "top speed, km/h");
}

TEST(VehicleFigures, StoppingDistanceFromHundredKmh) {
  Bench b(100.0 * kKmh + 0.5);
  while (b.state().speed > 100.0 * kKmh)
    b.world.step();
  const double v0 = b.state().speed;
  const auto p0 = b.state().position;
  b.drive({0.0f, 1.0f, 0.0f, false, false});
  while (b.state().speed > 0.01 && b.t() < 20.0)
    b.world.step();
  const auto p1 = b.state().position;
  const double d = std::hypot(p1[0] - p0[0], p1[1] - p0[1]);
  // Scaled to exactly 100 km/h (distance grows with the square of the speed).
  expect_near_published(d * std::pow(100.0 * kKmh / v0, 2), 36.0, "100-0 km/h, m");
  EXPECT_NEAR(p1[1], p0[1], 0.5) << "pulled to one side";
}

/// Diameter of the circle the outer front wheel runs on at walking pace and full lock.
double turning_circle(double steer) {
  Bench b;
  const std::size_t outer = steer < 0 ? 1 : 0;  // steer < 0 turns left: the right wheel is outer
  std::vector<std::array<double, 3>> pts;
  while (b.t() < 40.0) {
    // Hold about 1.5 m/s with a little throttle, as a driver parking does.
    const float throttle = b.state().speed < 1.5f ? 0.15f : 0.0f;
    b.drive({throttle, 0.0f, static_cast<float>(steer), false, false});
    b.world.step();
    if (b.t() > 15.0)
      pts.push_back(b.world.wheel_contacts(b.car)[outer]);
  }
  double cx = 0, cy = 0;
  for (const auto& p : pts)
    cx += p[0], cy += p[1];
  cx /= pts.size();
  cy /= pts.size();
  double r = 0;
  for (const auto& p : pts)
    r += std::hypot(p[0] - cx, p[1] - cy);
  return 2.0 * r / pts.size();
}

TEST(VehicleFigures, TurningCircle) {
  const double left = turning_circle(-1.0);
  const double right = turning_circle(1.0);
  // Kerb-to-kerb adds the tyre's half width (205 mm) outside the contact patch centre.
  expect_near_published(left + 0.205, 10.9, "turning circle left, m");
  expect_near_published(right + 0.205, 10.9, "turning circle right, m");
  EXPECT_NEAR(left, right, 0.1);
}

TEST(VehicleFigures, ReversesAndShowsReverseLight) {
  Bench b;
  b.drive({0.3f, 0.0f, 0.0f, true, false});
  for (int i = 0; i < 300; ++i)
    b.world.step();
  EXPECT_EQ(b.state().gear, -1);
  EXPECT_LT(b.state().speed, -1.0f);
  EXPECT_LT(b.state().position[0], 20.0);
  EXPECT_TRUE(b.state().lights & wire::kReverseLight);
}

TEST(VehicleFigures, SteeringRightTurnsClockwise) {
  Bench b(10.0);
  b.drive({0.2f, 0.0f, 0.5f, false, false});
  for (int i = 0; i < 100; ++i)
    b.world.step();
  EXPECT_LT(b.state().yaw_rate, -0.1f);
  EXPECT_LT(b.state().steering_angle, 0.0f);
  EXPECT_LT(b.state().acceleration[1], -1.0f) << "lateral acceleration to the right";
}

}  // namespace
}  // namespace tb::server::physics
