#include "sim-client/view3d/vehicle_node.hpp"

#include <gtest/gtest.h>

namespace tb::client::view3d {
namespace {

VehicleLook sedan() {
  VehicleLook l;
  l.id = "car";
  l.station_id = 1001;
  return l;  // 4.5 × 1.8 × 1.45 m, wheelbase 2.6 m, wheels 0.32 m
}

// The view draws every car of the scenario (20–300): one car must stay cheap.
TEST(VehicleNode, TrianglesPerCarWithinTheBudget) {
  VehicleNode car(sedan());
  const std::size_t n = count_triangles(*car.node());
  RecordProperty("triangles_per_car", static_cast<int>(n));
  EXPECT_GT(n, 200u);  // body, glasshouse, four wheels and the lamps are all there
  EXPECT_LE(n, 1500u);
}

// The lamps follow the state's light bits; the indicators blink at 1.4 Hz on sim time.
TEST(VehicleNode, LampsFollowTheLightBits) {
  VehicleNode car(sedan());
  wire::VehicleState s;
  s.sim_time_ns = 100'000'000;  // 0.1 s: first half of the 0.714 s period, lit
  s.lights = wire::kLowBeam | wire::kBrakeLights | wire::kIndicatorLeft;
  car.update(s);
  EXPECT_TRUE(car.headlights().lit());
  EXPECT_TRUE(car.brake_lights().lit());
  EXPECT_FALSE(car.reversing_lights().lit());
  EXPECT_TRUE(car.left_indicators().lit());
  EXPECT_FALSE(car.right_indicators().lit());
  s.sim_time_ns = 500'000'000;  // 0.5 s: second half, dark
  car.update(s);
  EXPECT_FALSE(car.left_indicators().lit());
  s.sim_time_ns = 800'000'000;  // 0.8 s: the next period's first half
  s.lights = wire::kHighBeam | wire::kReverseLight | wire::kHazard;
  car.update(s);
  EXPECT_TRUE(car.headlights().lit());
  EXPECT_FALSE(car.brake_lights().lit());
  EXPECT_TRUE(car.reversing_lights().lit());
  EXPECT_TRUE(car.left_indicators().lit());
  EXPECT_TRUE(car.right_indicators().lit());
  s.lights = 0;
  car.update(s);
  EXPECT_FALSE(car.headlights().lit());
  EXPECT_FALSE(car.left_indicators().lit());
}

}  // namespace
}  // namespace tb::client::view3d
