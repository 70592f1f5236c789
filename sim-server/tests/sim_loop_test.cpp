#include <gtest/gtest.h>

#include <deque>

#include "common/clock/runtime.hpp"
#include "sim-server/server/sim_loop.hpp"

namespace tb::server {
namespace {

using namespace std::chrono_literals;

struct SimLoopTest : ::testing::Test {
  physics::World world{scenario::MapSpec{}, physics::WorldOptions{.step_s = 0.01}};
  clock::ManualRuntime rt;
  std::deque<std::function<void()>> posted;
  SimLoop::Post post = [this](std::function<void()> f) { posted.push_back(std::move(f)); };
};

TEST_F(SimLoopTest, StepsAtAbsoluteInstants) {
  SimLoop loop(rt, world, nullptr, {}, post);
  loop.start();
  rt.advance(9ms);
  EXPECT_EQ(world.tick(), 0u);
  rt.advance(1ms);
  EXPECT_EQ(world.tick(), 1u);
  rt.advance(990ms);
  EXPECT_EQ(world.tick(), 100u);
  EXPECT_EQ(loop.late_steps(), 0u);
}

/// Fires timers the way a real event loop does after a stall: every timer that fell due
/// while the process was stalled runs at the instant it wakes up, not at its own due time.
class StallingRuntime final : public clock::Runtime {
 public:
  clock::SteadyTime steady_now() const override { return clock_.steady_now(); }
  clock::WallTime wall_now() const override { return clock_.wall_now(); }
  clock::TimerId schedule_at(clock::SteadyTime when, clock::TimerCallback cb) override {
    return queue_.push(when, std::move(cb));
  }
  void cancel(clock::TimerId id) override { queue_.cancel(id); }
  void wake_after(clock::Duration d) {
    clock_.advance(d);
    while (!queue_.empty() && queue_.next_due() <= clock_.steady_now())
      queue_.pop()();
  }

 private:
  clock::ManualClock clock_;
  clock::TimerQueue queue_;
};

TEST_F(SimLoopTest, CatchesUpAfterAStallWithoutDrift) {
  StallingRuntime srt;
  SimLoop loop(srt, world, nullptr, {}, post);
  loop.start();
  for (int i = 0; i < 10; ++i)
    srt.wake_after(10ms);
  ASSERT_EQ(world.tick(), 10u);
  EXPECT_EQ(loop.late_steps(), 0u);
  // Stalled for 55 ms: the steps due at 110..150 ms run at once at 155 ms.
  srt.wake_after(55ms);
  EXPECT_EQ(world.tick(), 15u);
  EXPECT_EQ(loop.late_steps(), 4u);  // 45, 35, 25 and 15 ms late; the last only 5 ms
  // The schedule stays on the original grid: step 20 is due at exactly 200 ms.
  srt.wake_after(44ms);
  EXPECT_EQ(world.tick(), 19u);
  srt.wake_after(1ms);
  EXPECT_EQ(world.tick(), 20u);
}

TEST_F(SimLoopTest, ResyncsAfterFallingFarBehind) {
  StallingRuntime srt;
  SimLoop loop(srt, world, nullptr, {}, post);
  loop.start();
  srt.wake_after(10ms);
  ASSERT_EQ(world.tick(), 1u);
  srt.wake_after(5s);
  // The late step, then a fresh schedule from now instead of 500 steps in a burst.
  EXPECT_LE(world.tick(), 3u);
  EXPECT_EQ(loop.resyncs(), 1u);
  const auto t0 = world.tick();
  for (int i = 0; i < 10; ++i)
    srt.wake_after(10ms);
  EXPECT_EQ(world.tick(), t0 + 10);
}

TEST_F(SimLoopTest, FastModeRunsThroughPostedStepsUntilTheDuration) {
  bool finished = false;
  SimLoop loop(rt, world, nullptr, {.fast = true, .duration_s = 2.0}, post,
               [&] { finished = true; });
  loop.start();
  int posts = 0;
  while (!posted.empty()) {
    auto f = std::move(posted.front());
    posted.pop_front();
    f();
    ++posts;
  }
  EXPECT_TRUE(finished);
  EXPECT_EQ(world.tick(), 200u);
  EXPECT_EQ(posts, 200);
  EXPECT_EQ(rt.steady_now(), clock::SteadyTime{}) << "fast mode does not wait for the clock";
}

TEST_F(SimLoopTest, StopCancelsTheNextStep) {
  SimLoop loop(rt, world, nullptr, {}, post);
  loop.start();
  rt.advance(30ms);
  loop.stop();
  rt.advance(100ms);
  EXPECT_EQ(world.tick(), 3u);
  EXPECT_EQ(rt.pending(), 0u);
}

}  // namespace
}  // namespace tb::server
