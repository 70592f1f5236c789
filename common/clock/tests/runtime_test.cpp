#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include <boost/asio/post.hpp>

#include "common/clock/asio_runtime.hpp"
#include "common/clock/held_clock_runtime.hpp"
#include "common/clock/runtime.hpp"

namespace tb::clock {
namespace {

using namespace std::chrono_literals;

TEST(ManualRuntime, FiresTimersInOrderEachAtItsOwnInstant) {
  ManualRuntime rt;
  const SteadyTime start = rt.steady_now();
  std::vector<std::pair<int, Duration>> fired;
  rt.schedule_in(30ms, [&] { fired.emplace_back(3, rt.steady_now() - start); });
  rt.schedule_in(10ms, [&] { fired.emplace_back(1, rt.steady_now() - start); });
  rt.schedule_in(10ms, [&] { fired.emplace_back(2, rt.steady_now() - start); });
  rt.advance(25ms);
  ASSERT_EQ(fired.size(), 2u);
  EXPECT_EQ(fired[0], std::make_pair(1, Duration{10ms}));
  EXPECT_EQ(fired[1], std::make_pair(2, Duration{10ms}));
  EXPECT_EQ(rt.steady_now() - start, 25ms);
  rt.advance(5ms);
  ASSERT_EQ(fired.size(), 3u);
  EXPECT_EQ(fired[2], std::make_pair(3, Duration{30ms}));
}

TEST(ManualRuntime, CallbacksCanRescheduleAndCancel) {
  ManualRuntime rt;
  int ticks = 0;
  std::function<void()> periodic = [&] {
    ++ticks;
    rt.schedule_in(100ms, periodic);
  };
  rt.schedule_in(100ms, periodic);
  const TimerId doomed = rt.schedule_in(250ms, [&] { ticks += 1000; });
  rt.schedule_in(200ms, [&] { rt.cancel(doomed); });
  rt.advance(1s);
  EXPECT_EQ(ticks, 10);
}

TEST(ManualRuntime, WallTimeMovesWithSteadyTime) {
  ManualRuntime rt(WallTime{std::chrono::seconds{1'000}});
  rt.advance(1500ms);
  EXPECT_EQ(to_unix_ns(rt.wall_now()), 1'001'500'000'000);
}

TEST(ManualRuntime, TimerInThePastFiresOnNextAdvance) {
  ManualRuntime rt;
  rt.advance(1s);
  bool fired = false;
  rt.schedule_at(rt.steady_now() - 1ms, [&] { fired = true; });
  rt.run_due();
  EXPECT_TRUE(fired);
}

TEST(UnixNanoseconds, RoundTrip) {
  const std::int64_t ns = 1'732'233'600'123'456'789;
  EXPECT_EQ(to_unix_ns(from_unix_ns(ns)), ns);
}

// The one test that uses real time: the Asio runtime must fire in due order with a real
// io_context. It waits for at most a few tens of milliseconds.
TEST(AsioRuntime, FiresInOrderAndHonoursCancel) {
  boost::asio::io_context io;
  AsioRuntime rt(io);
  std::vector<int> order;
  // Each callback checks that it did not fire before the instant it was due.
  auto at = [&](Duration delay, int id) {
    const SteadyTime due = rt.steady_now() + delay;
    return rt.schedule_at(due, [&order, due, id] {
      EXPECT_GE(SteadyClock::now(), due) << "timer " << id << " fired early";
      order.push_back(id);
    });
  };
  at(20ms, 2);
  const TimerId cancelled = at(5ms, 99);
  at(1ms, 1);
  rt.cancel(cancelled);
  io.run_for(2s);
  EXPECT_EQ(order, (std::vector<int>{1, 2}));
}

// A timer moved later (cancelled and scheduled again) must not wake the thread at its old
// instant. Real time again, at most a few tens of milliseconds.
TEST(AsioRuntime, ATimerMovedLaterDoesNotWakeAtItsOldInstant) {
  boost::asio::io_context io;
  AsioRuntime rt(io);
  int fired = 0;
  const TimerId first = rt.schedule_in(5ms, [&] { ++fired; });
  rt.cancel(first);
  rt.schedule_in(30ms, [&] { ++fired; });
  io.run_for(2s);
  EXPECT_EQ(fired, 1);
  EXPECT_EQ(rt.wakeups(), 1u) << "woken at the cancelled timer's instant";
}

// Callbacks of one wake-up that each schedule a successor set the timer once between them, not
// once each (each setting is a system call). The case: timers at distinct instants that one
// wake-up fires together (here the thread is busy until all are due), where each popped timer
// moved the next due instant. Real time, about 25 ms.
TEST(AsioRuntime, OneTimerSettingPerWakeUp) {
  boost::asio::io_context io;
  AsioRuntime rt(io);
  constexpr int kPeriodic = 50;
  int fired = 0;
  const SteadyTime start = rt.steady_now();
  for (int i = 0; i < kPeriodic; ++i)
    rt.schedule_at(start + 1ms + i * 10us, [&] {
      ++fired;
      rt.schedule_at(start + 20ms, [&] { ++fired; });
    });
  boost::asio::post(io, [&] {
    while (SteadyClock::now() < start + 5ms) {
    }
  });
  io.run_for(2s);
  ASSERT_EQ(fired, 2 * kPeriodic);
  // One setting before the thread was busy, then at most one per wake-up (about 50 when each
  // callback set it).
  EXPECT_LE(rt.rearms(), 1u + rt.wakeups()) << "set once per callback";
}

}  // namespace
}  // namespace tb::clock

namespace tb::clock {
namespace {

TEST(HeldClockRuntime, HeldClocksStandStillAndFollowAgainWhenReleased) {
  ManualRuntime inner;
  HeldClockRuntime rt(inner);
  const SteadyTime s0 = inner.steady_now();
  const WallTime w0 = inner.wall_now();
  {
    auto hold = rt.hold();
    inner.advance(5ms);
    EXPECT_EQ(rt.steady_now(), s0);
    EXPECT_EQ(rt.wall_now(), w0);
    {
      auto inner_hold = rt.hold();  // nested: keeps the outer instant
      inner.advance(5ms);
      EXPECT_EQ(rt.steady_now(), s0);
    }
    EXPECT_EQ(rt.steady_now(), s0) << "released by the inner hold";
  }
  EXPECT_EQ(rt.steady_now(), s0 + 10ms);
  EXPECT_EQ(rt.wall_now(), w0 + 10ms);
}

TEST(HeldClockRuntime, HeldAtAnArrivalInstantBothClocksStandThere) {
  ManualRuntime inner;
  HeldClockRuntime rt(inner);
  const WallTime arrived = inner.wall_now();
  const SteadyTime arrived_steady = inner.steady_now();
  inner.advance(60ms);  // the process gets to the datagram 60 ms after the kernel stamped it
  {
    const auto held = rt.hold_at(arrived);
    EXPECT_EQ(rt.wall_now(), arrived);
    EXPECT_EQ(rt.steady_now(), arrived_steady);
    inner.advance(5ms);
    EXPECT_EQ(rt.steady_now(), arrived_steady);
  }
  EXPECT_EQ(rt.steady_now(), arrived_steady + 65ms);
  // A stamp not yet past (a wall clock stepped back) holds now.
  const auto held = rt.hold_at(inner.wall_now() + 1s);
  EXPECT_EQ(rt.wall_now(), inner.wall_now());
  EXPECT_EQ(rt.steady_now(), inner.steady_now());
}

TEST(HeldClockRuntime, TimersAreTheInnerRuntimes) {
  ManualRuntime inner;
  HeldClockRuntime rt(inner);
  int fired = 0;
  rt.schedule_in(10ms, [&] { ++fired; });
  const TimerId cancelled = rt.schedule_in(5ms, [&] { fired += 100; });
  rt.cancel(cancelled);
  inner.advance(9ms);
  EXPECT_EQ(fired, 0);
  inner.advance(1ms);
  EXPECT_EQ(fired, 1);
}

}  // namespace
}  // namespace tb::clock
