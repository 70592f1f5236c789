#include <gtest/gtest.h>

#include "sim-server/physics/powertrain.hpp"

namespace tb::server::physics {
namespace {

constexpr double kDt = 0.01;

TEST(Powertrain, TorqueCurveInterpolatesAndIsFlatBeyondItsEnds) {
  Powertrain p(scenario::VehicleModel{});
  EXPECT_DOUBLE_EQ(p.full_load_torque(500), 140.0);
  EXPECT_DOUBLE_EQ(p.full_load_torque(1250), 170.0);
  EXPECT_DOUBLE_EQ(p.full_load_torque(3000), 200.0);
  EXPECT_DOUBLE_EQ(p.full_load_torque(5500), 157.5);
  EXPECT_DOUBLE_EQ(p.full_load_torque(9000), 120.0);
}

TEST(Powertrain, ShiftsUpAboveShiftRpmAndCutsTorqueWhileShifting) {
  scenario::VehicleModel m;
  Powertrain p(m);
  const wire::Controls full{1.0f, 0.0f, 0.0f, false, false};
  // Just above the up-shift speed in first gear.
  const double v = (m.shift_up_rpm + 50) / p.rpm_at(1.0, 1);
  auto f = p.update(full, v, kDt);
  EXPECT_EQ(f.gear, 2);
  EXPECT_EQ(f.traction_n, 0.0);
  for (int i = 0; i < 50; ++i)
    f = p.update(full, v, kDt);
  EXPECT_EQ(f.gear, 2);
  EXPECT_GT(f.traction_n, 1000.0);
}

TEST(Powertrain, KicksDownSeveralGearsAtLowSpeed) {
  scenario::VehicleModel m;
  Powertrain p(m);
  const wire::Controls full{1.0f, 0.0f, 0.0f, false, false};
  double v = 0;
  for (int i = 0; i < 4000 && p.gear() < 5; ++i) {
    p.update(full, v, kDt);
    v += 0.02;
  }
  ASSERT_EQ(p.gear(), 5);
  // 29 km/h in fifth is far below the down-shift speed: once the up-shift is done, one step
  // goes down to second.
  for (int i = 0; i < 60 && p.gear() == 5; ++i)
    p.update(full, 8.0, kDt);
  EXPECT_LE(p.gear(), 2);
}

TEST(Powertrain, EngagesReverseOnlyNearStandstill) {
  Powertrain p(scenario::VehicleModel{});
  const wire::Controls rev{0.5f, 0.0f, 0.0f, true, false};
  EXPECT_EQ(p.update(rev, 5.0, kDt).gear, 1);
  const auto f = p.update(rev, 0.1, kDt);
  EXPECT_EQ(f.gear, -1);
  EXPECT_LT(f.traction_n, 0.0);
}

TEST(Powertrain, BrakeAndHandbrakeForces) {
  // Worked by hand: force at the tyre = torque at the wheel / wheel radius.
  scenario::VehicleModel m;
  m.brake_torque_nm = 3000.0;
  m.handbrake_torque_nm = 900.0;
  m.wheel_radius_m = 0.3;
  Powertrain p(m);
  const auto f = p.update({0.0f, 0.5f, 0.0f, false, true}, 10.0, kDt);
  EXPECT_NEAR(f.brake_n, 5000.0, 1e-9);  // half of 3000 N·m at 0.3 m
  EXPECT_NEAR(f.handbrake_n, 3000.0, 1e-9);
  // The pedal saturates at fully pressed; no handbrake, no handbrake force.
  const auto full = p.update({0.0f, 1.5f, 0.0f, false, false}, 10.0, kDt);
  EXPECT_NEAR(full.brake_n, 10000.0, 1e-9);
  EXPECT_EQ(full.handbrake_n, 0.0);
}

TEST(Powertrain, ClosedThrottleDragsAgainstTheMotion) {
  Powertrain p(scenario::VehicleModel{});
  DriveForces f;
  for (int i = 0; i < 100; ++i)  // through the up-shifts a fresh gearbox makes at 54 km/h
    f = p.update({}, 15.0, kDt);
  EXPECT_LT(f.traction_n, 0.0);
  EXPECT_GT(f.traction_n, -1000.0);
  // And none at standstill, where the clutch is open.
  Powertrain q(scenario::VehicleModel{});
  EXPECT_EQ(q.update({}, 0.0, kDt).traction_n, 0.0);
}

TEST(Powertrain, EngineDragFadesInAsTheThrottleCloses) {
  // No step in the drive force where the drag begins: a cruise at about 5 % throttle must
  // not jolt. Between 4.9 % and 5.1 % the force changes by the throttle's share alone.
  auto traction = [](float throttle) {
    Powertrain p(scenario::VehicleModel{});
    DriveForces f;
    for (int i = 0; i < 100; ++i)
      f = p.update({throttle, 0.0f, 0.0f, false, false}, 8.0, kDt);
    return f.traction_n;
  };
  const double below = traction(0.049f), above = traction(0.051f);
  EXPECT_LT(std::abs(above - below), 60.0) << below << " N vs " << above << " N";
  EXPECT_LT(traction(0.0f), traction(0.025f));  // fully closed drags most
  EXPECT_LT(traction(0.025f), below);
}

TEST(Powertrain, NoTorqueBeyondRedline) {
  scenario::VehicleModel m;
  m.gear_ratios = {3.62};  // nothing to shift into
  Powertrain p(m);
  const double v = 6700 / p.rpm_at(1.0, 1);
  EXPECT_EQ(p.update({1.0f, 0.0f, 0.0f, false, false}, v, kDt).traction_n, 0.0);
}

}  // namespace
}  // namespace tb::server::physics
