#include "sim-client/view3d/interpolation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace tb::client::view3d {
namespace {

using namespace std::chrono_literals;
namespace sim = wire::sim;

constexpr std::int64_t kStep = 10'000'000;  // 100 Hz

sim::StateFrame frame(std::uint64_t tick, double x, float yaw = 0.0f) {
  sim::StateFrame f;
  f.tick = tick;
  f.sim_time_ns = static_cast<std::int64_t>(tick) * kStep;
  wire::VehicleState v;
  v.tick = tick;
  v.sim_time_ns = f.sim_time_ns;
  v.position = {x, 2.0 * x, 0.1};
  v.yaw = yaw;
  v.speed = static_cast<float>(x);
  v.controls.throttle = tick % 2 == 0 ? 1.0f : 0.0f;
  f.vehicles.push_back(v);
  return f;
}

clock::SteadyTime t0() {
  return clock::SteadyTime{std::chrono::seconds{100}};
}

TEST(StateInterpolator, NothingBeforeTheFirstFrameThenTheFrameItself) {
  StateInterpolator in;
  EXPECT_FALSE(in.sample(t0()).has_value());
  in.push(frame(1, 5.0), t0());
  const auto s = in.sample(t0() + 1s);
  ASSERT_TRUE(s);
  EXPECT_EQ(s->vehicles[0].position[0], 5.0);
  EXPECT_EQ(s->sim_time_ns, kStep);
}

TEST(StateInterpolator, OneStepBehindWhenFramesArriveOnTime) {
  StateInterpolator in;
  in.push(frame(1, 1.0), t0());
  in.push(frame(2, 2.0), t0() + 10ms);
  // At the second arrival the view shows the first frame; half a step later, the middle.
  auto s = in.sample(t0() + 10ms);
  EXPECT_NEAR(s->vehicles[0].position[0], 1.0, 1e-9);
  s = in.sample(t0() + 15ms);
  EXPECT_NEAR(s->alpha, 0.5, 1e-9);
  EXPECT_NEAR(s->vehicles[0].position[0], 1.5, 1e-9);
  EXPECT_NEAR(s->vehicles[0].position[1], 3.0, 1e-9);
  EXPECT_EQ(s->sim_time_ns, 15'000'000);
  // Discrete fields are the latest frame's.
  EXPECT_EQ(s->vehicles[0].controls.throttle, 1.0f);
}

TEST(StateInterpolator, NeverExtrapolatesPastTheLatestState) {
  StateInterpolator in;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> jitter_us(0, 9000);
  clock::SteadyTime now = t0();
  for (std::uint64_t tick = 1; tick < 400; ++tick) {
    // Frames arrive with up to 9 ms of jitter, sometimes two at once, sometimes a gap.
    const auto arrival = t0() + std::chrono::milliseconds(10 * tick) +
                         std::chrono::microseconds(jitter_us(rng)) + (tick % 50 == 0 ? 40ms : 0ms);
    const double x = std::sin(static_cast<double>(tick) * 0.05) * 10.0;
    in.push(frame(tick, x), arrival);
    const double prev_x = std::sin(static_cast<double>(tick - 1) * 0.05) * 10.0;
    for (int k = 0; k < 5; ++k) {
      now = std::max(now, arrival) + std::chrono::microseconds(jitter_us(rng) / 3);
      const auto s = in.sample(now);
      ASSERT_TRUE(s);
      EXPECT_LE(s->sim_time_ns, static_cast<std::int64_t>(tick) * kStep);
      EXPECT_GE(s->alpha, 0.0);
      EXPECT_LE(s->alpha, 1.0);
      const double got = s->vehicles[0].position[0];
      if (tick > 1) {
        EXPECT_GE(got, std::min(x, prev_x) - 1e-9) << "tick " << tick;
        EXPECT_LE(got, std::max(x, prev_x) + 1e-9) << "tick " << tick;
      }
    }
  }
  // Long after the last frame the view holds it.
  const auto s = in.sample(now + 10s);
  EXPECT_EQ(s->sim_time_ns, 399 * kStep);
  EXPECT_DOUBLE_EQ(s->alpha, 1.0);
}

TEST(StateInterpolator, AServerThatStartsOverStartsTheHistoryOver) {
  StateInterpolator in;
  in.push(frame(100, 50.0), t0());
  in.push(frame(101, 51.0), t0() + 10ms);
  in.push(frame(1, 0.5), t0() + 20ms);  // restarted: sim time went back
  const auto s = in.sample(t0() + 25ms);
  EXPECT_EQ(s->vehicles[0].position[0], 0.5);
}

TEST(Interpolate, YawTakesTheShortWayRound) {
  wire::VehicleState a, b;
  a.yaw = static_cast<float>(std::numbers::pi - 0.1);
  b.yaw = static_cast<float>(-std::numbers::pi + 0.1);
  const auto m = interpolate(a, b, 0.5);
  EXPECT_NEAR(std::abs(m.yaw), std::numbers::pi, 1e-6);
}

}  // namespace
}  // namespace tb::client::view3d
