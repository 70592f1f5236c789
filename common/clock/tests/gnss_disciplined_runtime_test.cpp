#include "common/clock/gnss_disciplined_runtime.hpp"

#include <gtest/gtest.h>

namespace tb::clock {
namespace {

using namespace std::chrono_literals;

// The host believes it is late 2026; the world (a pinned scenario) runs in mid 2025.
const WallTime kHostStart{std::chrono::seconds{1'795'000'000}};
const WallTime kWorldStart{std::chrono::seconds{1'748'854'800}};  // 2025-06-02T09:00:00Z

std::int64_t ms_between(WallTime a, WallTime b) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(b - a).count();
}

TEST(GnssDisciplinedRuntime, IsTheHostClockUntilTheFirstFix) {
  ManualRuntime host(kHostStart);
  GnssDisciplinedRuntime its(host);
  EXPECT_FALSE(its.synchronised());
  EXPECT_EQ(its.wall_now(), host.wall_now());
  EXPECT_EQ(its.steady_now(), host.steady_now());
}

TEST(GnssDisciplinedRuntime, RunsOnTheWorldsEpochFromTheFirstFix) {
  ManualRuntime host(kHostStart);
  GnssDisciplinedRuntime its(host);
  host.advance(3s);
  its.on_fix(kWorldStart);
  EXPECT_TRUE(its.synchronised());
  EXPECT_EQ(its.wall_now(), kWorldStart);
  host.advance(40ms);  // between fixes: last fix + monotonic time since
  EXPECT_EQ(ms_between(kWorldStart, its.wall_now()), 40);
  // A kernel receive stamp 10 ms ago, on the host's wall clock, lands 30 ms after the fix.
  EXPECT_EQ(ms_between(kWorldStart, its.to_its(host.wall_now() - 10ms)), 30);
}

TEST(GnssDisciplinedRuntime, SteadyTimeIsContinuousAcrossTheFirstFix) {
  ManualRuntime host(kHostStart);
  GnssDisciplinedRuntime its(host);
  host.advance(2s);
  const auto before = its.steady_now();
  its.on_fix(kWorldStart);
  EXPECT_EQ(its.steady_now(), before);
}

// sim-server --fast: the world runs 4 times as fast as the host.
TEST(GnssDisciplinedRuntime, FollowsSimTimeWhenItRunsFasterThanTheHost) {
  ManualRuntime host(kHostStart);
  GnssDisciplinedRuntime its(host);
  WallTime world = kWorldStart;
  for (int i = 0; i < 60; ++i) {  // 10 Hz fixes of sim time: every 25 ms of host time
    its.on_fix(world);
    host.advance(25ms);
    world += 100ms;
  }
  EXPECT_NEAR(its.rate(), 4.0, 1e-9);
  // A standard's interval (T_GenCam, a DEN repetition) of 100 ms of ITS time is 25 ms here.
  bool fired = false;
  its.schedule_in(100ms, [&] { fired = true; });
  host.advance(24ms);
  EXPECT_FALSE(fired);
  host.advance(1ms);
  EXPECT_TRUE(fired);
  // Between fixes the wall clock advances at the world's rate.
  its.on_fix(world);
  host.advance(10ms);
  EXPECT_EQ(ms_between(world, its.wall_now()), 40);
}

TEST(GnssDisciplinedRuntime, RealTimeJitterDoesNotMoveTheRateMuch) {
  ManualRuntime host(kHostStart);
  GnssDisciplinedRuntime its(host);
  WallTime world = kWorldStart;
  for (int i = 0; i < 50; ++i) {  // fixes delivered 100 ms apart ± 3 ms
    its.on_fix(world);
    const auto jitter = std::chrono::milliseconds{(i % 3) * 3 - 3};
    host.advance(100ms + jitter);
    world += 100ms;
  }
  EXPECT_NEAR(its.rate(), 1.0, 0.01);
}

TEST(GnssDisciplinedRuntime, APauseOfTheFeedIsNotARate) {
  ManualRuntime host(kHostStart);
  GnssDisciplinedRuntime its(host);
  WallTime world = kWorldStart;
  its.on_fix(world);
  host.advance(3s);  // the simulation waits for its drivers; no fixes
  for (int i = 0; i < 30; ++i) {
    world += 100ms;
    host.advance(100ms);
    its.on_fix(world);
  }
  EXPECT_NEAR(its.rate(), 1.0, 1e-9);
}

TEST(GnssDisciplinedRuntime, ANewWorldIsTakenAsItIs) {
  ManualRuntime host(kHostStart);
  GnssDisciplinedRuntime its(host);
  its.on_fix(kWorldStart);
  host.advance(100ms);
  const WallTime restarted = kWorldStart - std::chrono::hours{24 * 30};
  its.on_fix(restarted);
  EXPECT_EQ(its.resyncs(), 1u);
  EXPECT_EQ(its.wall_now(), restarted);
}

TEST(GnssDisciplinedRuntime, TimersScheduledBeforeTheFirstFixRunOnTheHost) {
  ManualRuntime host(kHostStart);
  GnssDisciplinedRuntime its(host);
  bool fired = false;
  const auto id = its.schedule_in(50ms, [&] { fired = true; });
  host.advance(49ms);
  EXPECT_FALSE(fired);
  its.cancel(id);
  host.advance(10ms);
  EXPECT_FALSE(fired);
}

}  // namespace
}  // namespace tb::clock
