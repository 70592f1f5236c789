#include "network-emulator/gnss/world_start.hpp"

#include <gtest/gtest.h>

#include "common/clock/clock.hpp"

namespace tb::emu {
namespace {

using namespace std::chrono_literals;

constexpr std::int64_t kSecond = 1'000'000'000;
// 2026-11-27T08:00:00Z
const clock::WallTime kNow = clock::from_unix_ns(1'795'766'400LL * kSecond);

wire::VehicleState at_sim_time(std::int64_t sim_ns) {
  wire::VehicleState s;
  s.sim_time_ns = sim_ns;
  return s;
}

TEST(WorldStart, TheStatesStartTimeWinsAndIsSaidOnce) {
  WorldStart w(kNow - 24h);  // a pinned start_time the states overrule
  const std::int64_t from_server = clock::to_unix_ns(kNow) - 3 * kSecond;
  const auto first = w.update(from_server, at_sim_time(3 * kSecond), kNow);
  ASSERT_TRUE(first);
  EXPECT_EQ(clock::to_unix_ns(*first), from_server);
  EXPECT_EQ(w.source(), "sim-server's, with the states");
  EXPECT_FALSE(w.update(from_server, at_sim_time(4 * kSecond), kNow + 1s)) << "no change";
  // States without a start time keep the one known (no drift with the host's clock).
  EXPECT_FALSE(w.update(wire::kUnknownWorldStart, at_sim_time(5 * kSecond), kNow + 7s));
  // A restarted sim-server: a new start.
  const auto again = w.update(from_server + 60 * kSecond, at_sim_time(0), kNow + 60s);
  ASSERT_TRUE(again);
  EXPECT_EQ(clock::to_unix_ns(*again), from_server + 60 * kSecond);
}

TEST(WorldStart, WithoutTheStatesThePinnedStartTime) {
  const clock::WallTime pinned = kNow - 365 * 24h;
  WorldStart w(pinned);
  const auto start = w.update(wire::kUnknownWorldStart, at_sim_time(2 * kSecond), kNow);
  ASSERT_TRUE(start);
  EXPECT_EQ(*start, pinned);
  EXPECT_EQ(w.source(), "the scenario's start_time (the states do not carry one)");
}

TEST(WorldStart, WithNeitherTheHostsClockMinusTheFirstSimTime) {
  WorldStart w(std::nullopt);
  const auto start = w.update(wire::kUnknownWorldStart, at_sim_time(2500 * 1'000'000LL), kNow);
  ASSERT_TRUE(start);
  EXPECT_EQ(clock::to_unix_ns(*start), clock::to_unix_ns(kNow) - 2500 * 1'000'000LL);
  EXPECT_EQ(w.unix_ns(), clock::to_unix_ns(*start));
  // Later batches without a start time do not move it, whatever the host's clock says.
  EXPECT_FALSE(w.update(wire::kUnknownWorldStart, at_sim_time(10 * kSecond), kNow + 9s));
}

}  // namespace
}  // namespace tb::emu
