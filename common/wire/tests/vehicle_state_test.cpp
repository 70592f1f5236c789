#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

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
  s = sample();
  s.sim_time_ns = kMinSimTimeNs - 1;  // before the longest warm-up
  EXPECT_EQ(decode(encode(s)).error(), DecodeError::kOutOfRange);
}

TEST(VehicleState, WarmUpStatesCarryNegativeSimTime) {
  VehicleState s = sample();
  s.sim_time_ns = -2'990'000'000;
  auto d = decode(encode(s));
  ASSERT_TRUE(d.has_value());
  EXPECT_EQ(d->sim_time_ns, -2'990'000'000);
  s.sim_time_ns = kMinSimTimeNs;
  EXPECT_TRUE(decode(encode(s)).has_value());
}

std::vector<VehicleState> tick_of(std::size_t n) {
  std::vector<VehicleState> v;
  for (std::size_t i = 0; i < n; ++i) {
    VehicleState s = sample();
    s.station_id = 1000 + static_cast<std::uint32_t>(i);
    // Each state keeps its own times (a client may stamp them apart).
    s.step_wall_ns += static_cast<std::int64_t>(i) * 7;
    s.send_wall_ns += static_cast<std::int64_t>(i) * 11;
    s.position[0] += static_cast<double>(i);
    v.push_back(s);
  }
  return v;
}

TEST(StateBatch, RoundTripsEveryStateAndField) {
  std::vector<VehicleState> got;
  for (std::size_t n : {std::size_t{1}, std::size_t{2}, std::size_t{9}, kMaxStatesPerBatch}) {
    const auto states = tick_of(n);
    const auto bytes = encode_batch(states);
    ASSERT_EQ(bytes.size(), batch_datagram_size(n));
    const auto count = decode_batch(bytes, got);
    ASSERT_TRUE(count) << to_string(count.error());
    EXPECT_EQ(*count, n);
    EXPECT_EQ(got, states);
  }
}

TEST(StateBatch, LayoutIsHeadThenRecordBodies) {
  const auto states = tick_of(3);
  const auto bytes = encode_batch(states);
  EXPECT_EQ(bytes[0], 'V');
  EXPECT_EQ(bytes[1], 'S');
  EXPECT_EQ(bytes[2], kStateBatchVersion);
  EXPECT_EQ(bytes[3], 3);
  // Then the world's start time, little-endian; unknown here.
  for (std::size_t i = 4; i < 12; ++i)
    EXPECT_EQ(bytes[i], 0) << i;
  // Each body is the single record without its 4-byte head.
  for (std::size_t i = 0; i < 3; ++i) {
    const auto record = encode(states[i]);
    const std::vector<std::uint8_t> body(record.begin() + 4, record.end());
    const std::vector<std::uint8_t> in_batch(
        bytes.begin() + static_cast<std::ptrdiff_t>(12 + i * kVehicleStateBodySize),
        bytes.begin() + static_cast<std::ptrdiff_t>(12 + (i + 1) * kVehicleStateBodySize));
    EXPECT_EQ(in_batch, body) << i;
  }
}

TEST(StateBatch, CarriesTheWorldsStartTime) {
  // 2025-06-02T09:00:00Z, a pinned scenario's epoch, in Unix ns.
  constexpr std::int64_t kStart = 1'748'854'800'000'000'000;
  const auto bytes = encode_batch(tick_of(2), kStart);
  // Little-endian after the 4-byte head.
  std::int64_t raw = 0;
  for (int i = 7; i >= 0; --i)
    raw = (raw << 8) | bytes[4 + static_cast<std::size_t>(i)];
  EXPECT_EQ(raw, kStart);
  std::vector<VehicleState> got;
  std::int64_t start = -1;
  ASSERT_TRUE(decode_batch(bytes, got, &start));
  EXPECT_EQ(start, kStart);
  ASSERT_TRUE(decode_batch(encode_batch(tick_of(1)), got, &start));
  EXPECT_EQ(start, kUnknownWorldStart);
}

TEST(StateBatch, RefusesAStartTimeNoCamCouldDate) {
  std::vector<VehicleState> got;
  // 2003-12-31: the warm-up's fixes would fall before TimestampIts' epoch.
  EXPECT_EQ(decode_batch(encode_batch(tick_of(1), 1'072'828'800'000'000'000), got).error(),
            DecodeError::kOutOfRange);
  EXPECT_EQ(decode_batch(encode_batch(tick_of(1), -5), got).error(), DecodeError::kOutOfRange);
  EXPECT_EQ(decode_batch(encode_batch(tick_of(1), 9'000'000'000'000'000'000), got).error(),
            DecodeError::kOutOfRange);
  EXPECT_TRUE(got.empty());
}

TEST(StateBatch, DefaultDatagramLimitHoldsNineStates) {
  EXPECT_EQ(states_per_batch(kDefaultBatchDatagramSize), 9u);
  EXPECT_LE(batch_datagram_size(9), kDefaultBatchDatagramSize);
  EXPECT_EQ(states_per_batch(10), 1u);  // a limit below one state still sends one
  EXPECT_EQ(states_per_batch(65507), kMaxStatesPerBatch);
}

TEST(StateBatch, RefusesTheOldSingleStateDatagramByVersion) {
  std::vector<VehicleState> got = tick_of(2);
  const auto old = encode(sample());
  const auto d = decode_batch(old, got);
  ASSERT_FALSE(d);
  EXPECT_EQ(d.error(), DecodeError::kSingleStateVersion);
  EXPECT_TRUE(got.empty());
  EXPECT_NE(to_string(d.error()).find("version 1"), std::string_view::npos);
  // And the other way: a single-record reader does not misread a batch.
  const auto batch = encode_batch(tick_of(1));
  EXPECT_FALSE(decode(batch));
}

TEST(StateBatch, RefusesBadHeadsCountsAndRecordsAsAWhole) {
  std::vector<VehicleState> got;
  auto bytes = encode_batch(tick_of(4));
  for (std::size_t n = 0; n < bytes.size(); ++n) {  // every truncation
    const auto d = decode_batch(std::span<const std::uint8_t>(bytes.data(), n), got);
    ASSERT_FALSE(d) << n;
    EXPECT_TRUE(got.empty());
  }
  auto longer = bytes;
  longer.push_back(0);
  EXPECT_EQ(decode_batch(longer, got).error(), DecodeError::kBadCount);
  auto zero = bytes;
  zero[3] = 0;
  EXPECT_EQ(decode_batch(zero, got).error(), DecodeError::kBadCount);
  auto more = bytes;
  more[3] = 5;
  EXPECT_EQ(decode_batch(more, got).error(), DecodeError::kBadCount);
  auto magic = bytes;
  magic[1] = 'X';
  EXPECT_EQ(decode_batch(magic, got).error(), DecodeError::kBadMagic);
  auto version = bytes;
  version[2] = 2;  // the batch without a start time
  EXPECT_EQ(decode_batch(version, got).error(), DecodeError::kUnsupportedVersion);
  version[2] = 4;
  EXPECT_EQ(decode_batch(version, got).error(), DecodeError::kUnsupportedVersion);
  // A non-finite value in the last record refuses the whole datagram.
  auto states = tick_of(4);
  states[3].speed = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(decode_batch(encode_batch(states), got).error(), DecodeError::kNotFinite);
  EXPECT_TRUE(got.empty());
  states[3].speed = 1.0f;
  states[2].controls.throttle = 1.5f;
  EXPECT_EQ(decode_batch(encode_batch(states), got).error(), DecodeError::kOutOfRange);
}

TEST(StateBatch, EncodeRefusesEmptyTooManyAndSmallBuffers) {
  std::array<std::uint8_t, 2000> out{};
  EXPECT_EQ(encode_batch({}, out), 0u);
  const auto many = tick_of(kMaxStatesPerBatch + 1);
  std::vector<std::uint8_t> big(batch_datagram_size(many.size()));
  EXPECT_EQ(encode_batch(many, big), 0u);
  const auto two = tick_of(2);
  EXPECT_EQ(encode_batch(two, std::span<std::uint8_t>(out.data(), batch_datagram_size(2) - 1)), 0u);
  EXPECT_EQ(encode_batch(two, out), batch_datagram_size(2));
}

}  // namespace
}  // namespace tb::wire
