#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "common/wire/vehicle_state.hpp"

namespace tb::wire {
namespace {

VehicleState sample() {
  VehicleState s;
  s.station_id = 0xA1B2C3D4;
  s.tick = 123456789012ULL;
  s.sim_time_ns = 1'234'560'000'000;
  s.step_wall_ns = 1'732'233'600'123'456'789;
  s.send_wall_ns = 1'732'233'600'123'556'789;
  s.position = {1234.5678901234, -42.25, 0.5};
  s.roll = 0.01f, s.pitch = -0.02f, s.yaw = 1.5f;
  s.velocity = {13.9f, 0.1f, 0.0f};
  s.angular_velocity = {0.0f, 0.0f, 0.2f};
  s.acceleration = {-3.5f, 0.4f, 0.0f};
  s.speed = 13.9f;
  s.yaw_rate = 0.2f;
  s.steering_angle = -0.05f;
  s.wheel_speeds = {13.8f, 13.9f, 14.0f, 14.1f};
  s.controls = {0.25f, 0.5f, -0.75f, true, false};
  s.gear = 3;
  s.lights = kLowBeam | kBrakeLights | kIndicatorLeft;
  s.engine_rpm = 2500.0f;
  return s;
}

TEST(VehicleState, RoundTripsEveryField) {
  const VehicleState s = sample();
  const auto bytes = encode(s);
  const auto decoded = decode(bytes);
  ASSERT_TRUE(decoded) << to_string(decoded.error());
  EXPECT_EQ(*decoded, s);
}

TEST(VehicleState, LayoutIsLittleEndianWithMagicAndVersion) {
  const auto bytes = encode(sample());
  EXPECT_EQ(bytes[0], 'V');
  EXPECT_EQ(bytes[1], 'S');
  EXPECT_EQ(bytes[2], kVehicleStateVersion);
  // station id at offset 4, little-endian
  EXPECT_EQ(bytes[4], 0xD4);
  EXPECT_EQ(bytes[7], 0xA1);
}

TEST(VehicleState, RejectsWrongSizes) {
  const auto bytes = encode(sample());
  for (std::size_t n : {std::size_t{0}, std::size_t{1}, kVehicleStateSize - 1}) {
    const auto d = decode(std::span<const std::uint8_t>(bytes.data(), n));
    ASSERT_FALSE(d);
    EXPECT_EQ(d.error(), DecodeError::kWrongSize);
  }
  std::vector<std::uint8_t> longer(bytes.begin(), bytes.end());
  longer.push_back(0);
  EXPECT_EQ(decode(longer).error(), DecodeError::kWrongSize);
}

TEST(VehicleState, RejectsBadMagicAndVersion) {
  auto bytes = encode(sample());
  bytes[0] = 'X';
  EXPECT_EQ(decode(bytes).error(), DecodeError::kBadMagic);
  bytes = encode(sample());
  bytes[2] = 2;
  EXPECT_EQ(decode(bytes).error(), DecodeError::kUnsupportedVersion);
}

TEST(VehicleState, RejectsNonFiniteAndOutOfRangeValues) {
  VehicleState s = sample();
  s.position[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(decode(encode(s)).error(), DecodeError::kNotFinite);
  s = sample();
  s.yaw_rate = std::numeric_limits<float>::infinity();
  EXPECT_EQ(decode(encode(s)).error(), DecodeError::kNotFinite);
  s = sample();
  s.controls.throttle = 1.5f;
  EXPECT_EQ(decode(encode(s)).error(), DecodeError::kOutOfRange);
  s = sample();
  s.controls.steer = -1.01f;
  EXPECT_EQ(decode(encode(s)).error(), DecodeError::kOutOfRange);
}

}  // namespace
}  // namespace tb::wire
