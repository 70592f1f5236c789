#include "its-station/app/its_clock.hpp"

#include <array>

#include <gtest/gtest.h>

#include "its-station/app/time_synced_link.hpp"
#include "its-station/link/test_link.hpp"

namespace tb::its::station {
namespace {

using namespace std::chrono_literals;
using clock::WallTime;

// The host believes it is late 2026; the world (a pinned scenario) runs in mid 2025.
const WallTime kHostStart{std::chrono::seconds{1'795'000'000}};
const WallTime kWorldStart{std::chrono::seconds{1'748'854'800}};  // 2025-06-02T09:00:00Z

std::int64_t ms_between(WallTime a, WallTime b) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(b - a).count();
}

TEST(GnssDisciplinedRuntime, IsTheHostClockUntilTheFirstFix) {
  clock::ManualRuntime host(kHostStart);
  GnssDisciplinedRuntime its(host);
  EXPECT_FALSE(its.synchronised());
  EXPECT_EQ(its.wall_now(), host.wall_now());
  EXPECT_EQ(its.steady_now(), host.steady_now());
}

TEST(GnssDisciplinedRuntime, RunsOnTheWorldsEpochFromTheFirstFix) {
  clock::ManualRuntime host(kHostStart);
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
  clock::ManualRuntime host(kHostStart);
  GnssDisciplinedRuntime its(host);
  host.advance(2s);
  const auto before = its.steady_now();
  its.on_fix(kWorldStart);
  EXPECT_EQ(its.steady_now(), before);
}

// sim-server --fast: the world runs 4 times as fast as the host.
TEST(GnssDisciplinedRuntime, FollowsSimTimeWhenItRunsFasterThanTheHost) {
  clock::ManualRuntime host(kHostStart);
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
  clock::ManualRuntime host(kHostStart);
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
  clock::ManualRuntime host(kHostStart);
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
  clock::ManualRuntime host(kHostStart);
  GnssDisciplinedRuntime its(host);
  its.on_fix(kWorldStart);
  host.advance(100ms);
  const WallTime restarted = kWorldStart - std::chrono::hours{24 * 30};
  its.on_fix(restarted);
  EXPECT_EQ(its.resyncs(), 1u);
  EXPECT_EQ(its.wall_now(), restarted);
}

TEST(GnssDisciplinedRuntime, TimersScheduledBeforeTheFirstFixRunOnTheHost) {
  clock::ManualRuntime host(kHostStart);
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
}  // namespace tb::its::station

namespace tb::its::station {
namespace {

// The e2e signed three-vehicle case: a station that had no fix yet judged its neighbours' CAMs
// on the host's clock, seconds ahead of the world's, and refused them as out of the window.
TEST(TimeSyncedLink, TakesFramesInOnlyOnceTheClockHasAFix) {
  clock::ManualRuntime host(kHostStart);
  GnssDisciplinedRuntime its(host);
  link::TestLink inner(link::MacAddress{2, 0, 0, 0, 0, 1});
  TimeSyncedLink synced(inner, its);
  int delivered = 0;
  synced.set_receive_handler([&](const link::ReceivedFrame&) { ++delivered; });
  const std::array<std::uint8_t, 3> payload{1, 2, 3};
  inner.inject(link::MacAddress{2, 0, 0, 0, 0, 2}, link::kBroadcastMac, 0x8947, payload,
               host.wall_now());
  EXPECT_EQ(delivered, 0);
  EXPECT_EQ(synced.dropped_before_sync(), 1u);
  its.on_fix(kWorldStart);
  inner.inject(link::MacAddress{2, 0, 0, 0, 0, 2}, link::kBroadcastMac, 0x8947, payload,
               host.wall_now());
  EXPECT_EQ(delivered, 1);
  EXPECT_EQ(synced.dropped_before_sync(), 1u);
  // Sending is not gated here: before a fix the station has nothing to send.
  EXPECT_FALSE(synced.send(link::kBroadcastMac, 0x8947, payload));
  EXPECT_EQ(inner.sent().size(), 1u);
}

}  // namespace
}  // namespace tb::its::station
