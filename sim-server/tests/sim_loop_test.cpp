#include <gtest/gtest.h>

#include <deque>

#include "common/clock/runtime.hpp"
#include "common/scenario/loader.hpp"
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

/// A client link that takes every frame and counts the State frames among them.
struct CountingLink final : ClientLink {
  std::size_t frames = 0;
  bool send(SharedBytes, FrameKind) override {
    ++frames;
    return true;
  }
  void close() override {}
};

/// A human-driven car rolling at 5 m/s and a scripted one; 5 steps (50 ms) of warm-up.
struct SimLoopStartTest : ::testing::Test {
  scenario::Scenario sc = scenario::parse(R"({
    "name": "start", "map": {"type": "straight"}, "origin": {"lat": 48.1, "lon": 11.5},
    "warmup_s": 0.05,
    "vehicles": [
      {"id": "human", "station_id": 1, "spawn": {"lane": 0, "s": 50, "speed": 5}},
      {"id": "script", "station_id": 2, "spawn": {"lane": 0, "s": 100},
       "driver": {"type": "timeline", "steps": [{"t": 0, "throttle": 0.5}]}}
    ]})",
                                          "start.json");
  physics::World world{sc, physics::WorldOptions{.step_s = 0.01, .warmup_steps = 5}};
  clock::ManualRuntime rt;
  Hub hub{world, sc, "{}", rt};
  std::deque<std::function<void()>> posted;
  SimLoop::Post post = [this](std::function<void()> f) { posted.push_back(std::move(f)); };

  void send(Hub::ClientId id, const wire::sim::ClientMessage& m) {
    hub.receive(id, wire::sim::encode(m));
  }
};

TEST_F(SimLoopStartTest, WaitsForTheScriptedDriversThenWarmsUpWithoutApplyingControls) {
  SimLoop loop(rt, world, &hub, {.fast = false, .duration_s = std::nullopt, .start_timeout = 30s},
               post);
  loop.start();
  CountingLink link;
  const auto id = hub.connect(link, "test");
  send(id, wire::sim::Hello{"scripts"});
  send(id, wire::sim::Attach{wire::sim::Role::kWatcher, 0});
  rt.advance(2s);
  EXPECT_TRUE(loop.waiting_for_drivers());
  EXPECT_EQ(world.tick(), 0u) << "no step before the scripted car has its driver";
  EXPECT_EQ(hub.scripted_without_driver(), std::vector<std::string>{"script"});
  const std::size_t before = link.frames;

  send(id, wire::sim::Attach{wire::sim::Role::kDriver, 1});
  EXPECT_TRUE(hub.scripted_without_driver().empty());
  rt.advance(10ms);  // the next look sees it and starts the schedule
  EXPECT_FALSE(loop.waiting_for_drivers());
  rt.advance(10ms);
  ASSERT_EQ(world.tick(), 1u);
  EXPECT_EQ(world.sim_time_ns(), -40'000'000);
  EXPECT_GT(link.frames, before) << "warm-up states go out like any other";
  // The driver's controls wait for the physics, and so does the hub's brake-to-stop of the
  // car nobody drives.
  send(id, wire::sim::ControlsMsg{1, {1.0f, 0.0f, 0.0f, false, false}, 0, 0});
  rt.advance(40ms);
  ASSERT_EQ(world.tick(), 5u);
  EXPECT_EQ(world.sim_time_ns(), 0);
  EXPECT_FLOAT_EQ(world.controls(0).brake, 0.0f);
  EXPECT_FLOAT_EQ(world.states()[1].speed, 0.0f);
  rt.advance(10ms);  // the first physics step: both apply
  ASSERT_EQ(world.tick(), 6u);
  EXPECT_FLOAT_EQ(world.controls(0).brake, Hub::kStopBrake);
  EXPECT_FLOAT_EQ(world.states()[1].controls.throttle, 1.0f);
}

TEST_F(SimLoopStartTest, StartsWithoutAMissingDriverAfterTheTimeout) {
  SimLoop loop(rt, world, &hub, {.fast = false, .duration_s = std::nullopt, .start_timeout = 3s},
               post);
  loop.start();
  rt.advance(2990ms);
  EXPECT_TRUE(loop.waiting_for_drivers());
  rt.advance(10ms);
  EXPECT_FALSE(loop.waiting_for_drivers());
  EXPECT_EQ(world.tick(), 0u);
  rt.advance(10ms);
  EXPECT_EQ(world.tick(), 1u);
  EXPECT_EQ(world.sim_time_ns(), -40'000'000);
}

TEST_F(SimLoopStartTest, NoTimeoutStartsAtOnce) {
  SimLoop loop(rt, world, &hub, {}, post);
  loop.start();
  EXPECT_FALSE(loop.waiting_for_drivers());
  rt.advance(10ms);
  EXPECT_EQ(world.tick(), 1u);
}

}  // namespace
}  // namespace tb::server
