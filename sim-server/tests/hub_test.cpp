#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <map>

#include "common/clock/runtime.hpp"
#include "common/scenario/loader.hpp"
#include "sim-server/server/hub.hpp"
#include "sim-server/server/sim_loop.hpp"

namespace tb::server {
namespace {

namespace sim = wire::sim;
using namespace std::chrono_literals;

/// A client's end of the link: decodes what the hub sends; can play a full queue.
struct FakeLink final : ClientLink {
  std::vector<sim::ServerMessage> got;
  bool closed = false;
  bool full = false;
  sim::FrameParser parser{sim::Sender::kServer};

  bool send(SharedBytes frame, FrameKind kind) override {
    if (full && kind == FrameKind::kState)
      return false;
    std::span<const std::uint8_t> data(*frame);
    while (!data.empty()) {
      auto r = parser.parse(data);
      EXPECT_TRUE(r) << sim::to_string(r.error());
      if (!r)
        return true;
      if (*r == sim::FrameParser::Status::kFrame) {
        auto m = sim::decode_server(parser.frame());
        EXPECT_TRUE(m) << sim::to_string(m.error());
        if (m)
          got.push_back(*m);
      }
    }
    return true;
  }
  void close() override { closed = true; }

  template <typename T>
  std::vector<T> all() const {
    std::vector<T> out;
    for (const auto& m : got) {
      if (const auto* x = std::get_if<T>(&m))
        out.push_back(*x);
    }
    return out;
  }
};

struct HubTest : ::testing::Test {
  scenario::Scenario sc = scenario::load_file("sim-server/tests/scenarios/three-cars.json");
  physics::World world{sc, physics::WorldOptions{.step_s = 0.01}};
  clock::ManualRuntime rt;
  Hub hub{world, sc, "{\"json\":1}", rt};

  void send(Hub::ClientId id, const sim::ClientMessage& m) {
    const auto b = sim::encode(m);
    hub.receive(id, b);
  }
  Hub::ClientId join(FakeLink& link, const std::string& name) {
    const auto id = hub.connect(link, "test:" + name);
    send(id, sim::Hello{name});
    return id;
  }
  void step(int n = 1) {
    for (int i = 0; i < n; ++i) {
      hub.before_step();
      world.step();
      hub.after_step();
      rt.advance(10ms);
    }
  }
};

TEST_F(HubTest, HelloGetsWelcomeWithVehiclesAndScenario) {
  FakeLink a;
  join(a, "alice");
  auto w = a.all<sim::Welcome>();
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].step_ns, 10'000'000);
  EXPECT_EQ(w[0].scenario_json, "{\"json\":1}");
  ASSERT_EQ(w[0].vehicles.size(), 3u);
  EXPECT_EQ(w[0].vehicles[1].id, "b");
  EXPECT_EQ(w[0].vehicles[1].station_id, 102u);
  EXPECT_EQ(w[0].vehicles[0].driver, "");
}

TEST_F(HubTest, SecondDriverIsRefusedWithTheFirstOnesName) {
  FakeLink a, b;
  const auto ida = join(a, "alice");
  const auto idb = join(b, "bob");
  send(ida, sim::Attach{sim::Role::kDriver, 0});
  send(idb, sim::Attach{sim::Role::kDriver, 0});
  const auto ra = a.all<sim::AttachResult>();
  const auto rb = b.all<sim::AttachResult>();
  ASSERT_EQ(ra.size(), 1u);
  EXPECT_EQ(ra[0].status, sim::AttachStatus::kOk);
  ASSERT_EQ(rb.size(), 1u);
  EXPECT_EQ(rb[0].status, sim::AttachStatus::kAlreadyDriven);
  EXPECT_NE(rb[0].reason.find("alice"), std::string::npos) << rb[0].reason;
  EXPECT_FALSE(b.closed);
  EXPECT_EQ(hub.driver_of(0), ida);
  // Welcome for a later client names the driver.
  FakeLink c;
  join(c, "carol");
  EXPECT_EQ(c.all<sim::Welcome>().at(0).vehicles[0].driver, "alice");
  // Unknown vehicle.
  send(idb, sim::Attach{sim::Role::kDriver, 9});
  EXPECT_EQ(b.all<sim::AttachResult>().back().status, sim::AttachStatus::kUnknownVehicle);
}

TEST_F(HubTest, ControlsBeforeAttachCloseOnlyThatClient) {
  FakeLink a, b;
  const auto ida = join(a, "alice");
  const auto idb = join(b, "bob");
  send(idb, sim::Attach{sim::Role::kWatcher, 0});
  send(ida, sim::ControlsMsg{0, {1.0f, 0, 0, false, false}, 0});
  EXPECT_TRUE(a.closed);
  ASSERT_FALSE(a.all<sim::Closing>().empty());
  EXPECT_EQ(a.all<sim::Closing>()[0].reason, sim::CloseReason::kProtocolError);
  EXPECT_EQ(hub.stats().protocol_errors, 1u);
  EXPECT_FALSE(b.closed);
  step();
  EXPECT_EQ(b.all<sim::StateFrame>().size(), 1u);
  EXPECT_EQ(hub.clients(), 1u);
}

TEST_F(HubTest, GarbageAndOversizedFramesCloseTheConnection) {
  FakeLink a, b;
  const auto ida = hub.connect(a, "garbage");
  const std::string junk = "GET / HTTP/1.1\r\n\r\n";
  hub.receive(ida, std::span(reinterpret_cast<const std::uint8_t*>(junk.data()), junk.size()));
  EXPECT_TRUE(a.closed);
  const auto idb = join(b, "bob");
  // A Hello header claiming 1 MiB.
  const std::uint8_t big[] = {'S', 'P', 1, 0x01, 0, 0, 0x10, 0};
  hub.receive(idb, big);
  EXPECT_TRUE(b.closed);
  EXPECT_EQ(hub.stats().protocol_errors, 2u);
  EXPECT_EQ(hub.clients(), 0u);
}

TEST_F(HubTest, OutOfRangeControlsAreClampedAndCounted) {
  FakeLink a;
  const auto id = join(a, "alice");
  send(id, sim::Attach{sim::Role::kDriver, 1});
  send(id, sim::ControlsMsg{1, {2.0f, -1.0f, 5.0f, false, false}, wire::kLowBeam});
  EXPECT_FALSE(a.closed);
  EXPECT_EQ(hub.stats().clamped_values, 3u);
  EXPECT_EQ(world.controls(1).throttle, 1.0f);
  EXPECT_EQ(world.controls(1).brake, 0.0f);
  EXPECT_EQ(world.controls(1).steer, 1.0f);
  step();
  const auto s = a.all<sim::StateFrame>().back().vehicles[1];
  EXPECT_EQ(s.controls.throttle, 1.0f);
  EXPECT_TRUE(s.lights & wire::kLowBeam);
}

TEST_F(HubTest, SilentDriverBrakesToAStopAndResumesWithControls) {
  FakeLink a;
  const auto id = join(a, "alice");
  send(id, sim::Attach{sim::Role::kDriver, 0});
  // 400 ms of controls every 100 ms: the car drives.
  for (int i = 0; i < 40; ++i) {
    if (i % 10 == 0)
      send(id, sim::ControlsMsg{0, {0.6f, 0, 0, false, false}, 0});
    step();
  }
  EXPECT_EQ(world.controls(0).throttle, 0.6f);
  // Then nothing: the watchdog acts once 500 ms have passed since the last controls.
  // The last controls came at 300 ms; steps at 400..780 ms are within the timeout.
  step(39);
  EXPECT_EQ(world.controls(0).throttle, 0.6f) << "braked before the timeout";
  EXPECT_EQ(hub.stats().watchdog_stops, 0u);
  step(3);  // 790, 800, 810 ms: 510 ms of silence at the last one
  EXPECT_EQ(world.controls(0).throttle, 0.0f);
  EXPECT_EQ(world.controls(0).brake, Hub::kStopBrake);
  EXPECT_EQ(hub.stats().watchdog_stops, 1u);
  step(300);
  EXPECT_LT(std::abs(world.states()[0].speed), 0.05f);
  EXPECT_TRUE(world.states()[0].lights & wire::kHazard);
  // The driver is still attached and takes over again.
  send(id, sim::ControlsMsg{0, {0.5f, 0, 0, false, false}, 0});
  step();
  EXPECT_EQ(world.controls(0).throttle, 0.5f);
}

TEST_F(HubTest, ControlsBatchDrivesEachOfItsVehicles) {
  FakeLink a;
  const auto id = join(a, "alice");
  send(id, sim::Attach{sim::Role::kDriver, 0});
  send(id, sim::Attach{sim::Role::kDriver, 2});
  send(id, sim::ControlsBatch{{
               sim::ControlsMsg{2, {0.3f, 0, -0.2f, false, false}, wire::kFogLight},
               sim::ControlsMsg{0, {2.0f, 0, 0, false, false}, 0},  // clamped, counted
           }});
  EXPECT_FALSE(a.closed);
  EXPECT_EQ(world.controls(0).throttle, 1.0f);
  EXPECT_EQ(world.controls(2).throttle, 0.3f);
  EXPECT_EQ(world.controls(2).steer, -0.2f);
  EXPECT_EQ(hub.stats().clamped_values, 1u);
  // A vehicle listed twice gets its later entry.
  send(id, sim::ControlsBatch{{sim::ControlsMsg{0, {0.1f, 0, 0, false, false}, 0},
                               sim::ControlsMsg{0, {0.4f, 0, 0, false, false}, 0}}});
  EXPECT_EQ(world.controls(0).throttle, 0.4f);
  step();
  const auto s = a.all<sim::StateFrame>().back().vehicles;
  EXPECT_EQ(s[2].controls.throttle, 0.3f);
  EXPECT_TRUE(s[2].lights & wire::kFogLight);
  // Vehicle 1 nobody drives: still braking.
  EXPECT_GE(world.controls(1).brake, Hub::kStopBrake);
  EXPECT_EQ(world.controls(1).throttle, 0.0f);
}

TEST_F(HubTest, BatchNamingAVehicleNotDrivenIsRefusedWhole) {
  FakeLink a, b;
  const auto ida = join(a, "alice");
  const auto idb = join(b, "bob");
  send(ida, sim::Attach{sim::Role::kDriver, 0});
  send(idb, sim::Attach{sim::Role::kDriver, 1});
  // Bob's vehicle in alice's batch, after one of her own: nothing of it is applied, and only
  // alice is closed, as with a single Controls for a vehicle she does not drive.
  send(ida, sim::ControlsBatch{{sim::ControlsMsg{0, {0.9f, 0, 0, false, false}, 0},
                                sim::ControlsMsg{1, {0.9f, 0, 0, false, false}, 0}}});
  EXPECT_TRUE(a.closed);
  ASSERT_FALSE(a.all<sim::Closing>().empty());
  EXPECT_EQ(a.all<sim::Closing>().back().reason, sim::CloseReason::kProtocolError);
  EXPECT_NE(a.all<sim::Closing>().back().text.find("ControlsBatch"), std::string::npos)
      << a.all<sim::Closing>().back().text;
  EXPECT_EQ(hub.stats().protocol_errors, 1u);
  EXPECT_NE(world.controls(0).throttle, 0.9f);
  EXPECT_NE(world.controls(1).throttle, 0.9f);
  EXPECT_FALSE(b.closed);
  EXPECT_EQ(hub.driver_of(1), idb);
  // A malformed batch (an entry with NaN) closes the connection too.
  send(idb, sim::ControlsBatch{{sim::ControlsMsg{1, {NAN, 0, 0, false, false}, 0}}});
  EXPECT_TRUE(b.closed);
  EXPECT_EQ(hub.stats().protocol_errors, 2u);
}

TEST_F(HubTest, WatchdogWaitsForAClientStillAttachingItsVehicles) {
  FakeLink a;
  const auto id = join(a, "alice");
  send(id, sim::Attach{sim::Role::kDriver, 0});
  send(id, sim::ControlsMsg{0, {0.6f, 0, 0, false, false}, 0});
  step();
  // Vehicle 0 falls silent while its client takes 900 ms to attach the others, one every
  // 300 ms: no stop while the attachments come, then one after 500 ms without either.
  for (std::uint16_t v : {1, 2, 1}) {
    step(30);
    send(id, sim::Attach{sim::Role::kDriver, v});
  }
  EXPECT_EQ(hub.stats().watchdog_stops, 0u);
  EXPECT_EQ(world.controls(0).throttle, 0.6f);
  step(49);
  EXPECT_EQ(hub.stats().watchdog_stops, 0u);
  step(3);
  EXPECT_EQ(world.controls(0).brake, Hub::kStopBrake);
  EXPECT_EQ(hub.stats().watchdog_stops, 1u);  // 1 and 2 never drove: braking all along
}

TEST_F(HubTest, DisconnectedDriverReleasesItsVehicleWhichStops) {
  FakeLink a, w;
  const auto id = join(a, "alice");
  send(join(w, "watcher"), sim::Attach{sim::Role::kWatcher, 0});
  send(id, sim::Attach{sim::Role::kDriver, 2});
  for (int i = 0; i < 100; ++i) {
    send(id, sim::ControlsMsg{2, {0.5f, 0, 0, false, false}, 0});
    step();
  }
  EXPECT_GT(world.states()[2].speed, 4.0f);
  hub.disconnect(id);
  EXPECT_EQ(hub.driver_of(2), 0u);
  EXPECT_EQ(world.controls(2).brake, Hub::kStopBrake);
  const auto changes = w.all<sim::DriverChanged>();
  ASSERT_GE(changes.size(), 2u);
  EXPECT_EQ(changes.back().vehicle, 2);
  EXPECT_EQ(changes.back().driver, "");
  step(300);
  EXPECT_LT(std::abs(world.states()[2].speed), 0.05f);
  // Another client may now drive it.
  FakeLink b;
  const auto idb = join(b, "bob");
  send(idb, sim::Attach{sim::Role::kDriver, 2});
  EXPECT_EQ(b.all<sim::AttachResult>().at(0).status, sim::AttachStatus::kOk);
}

// A scripted client claims all its vehicles at once, and the answers and announcements come
// back faster than it reads them: they must not count as a stream it cannot keep up with (a
// client of 300 vehicles was dropped while attaching, issue 33).
TEST_F(HubTest, RepliesAreQueuedWhateverTheStateQueueHolds) {
  FakeLink a;
  a.full = true;
  const auto id = join(a, "claims-all");
  for (std::uint16_t v = 0; v < 3; ++v)
    send(id, sim::Attach{sim::Role::kDriver, v});
  EXPECT_FALSE(a.closed);
  EXPECT_EQ(a.all<sim::AttachResult>().size(), 3u);
  EXPECT_EQ(a.all<sim::DriverChanged>().size(), 3u);
  step(1);
  EXPECT_TRUE(a.closed) << "a state it cannot take still drops it";
  EXPECT_EQ(hub.stats().slow_drops, 1u);
}

TEST_F(HubTest, SlowClientIsDroppedOthersKeepTheirStream) {
  FakeLink a, b;
  const auto ida = join(a, "slow");
  const auto idb = join(b, "fast");
  send(ida, sim::Attach{sim::Role::kDriver, 0});
  send(idb, sim::Attach{sim::Role::kWatcher, 0});
  step(3);
  a.full = true;
  step(3);
  EXPECT_TRUE(a.closed);
  EXPECT_EQ(hub.stats().slow_drops, 1u);
  EXPECT_EQ(hub.driver_of(0), 0u) << "a dropped driver releases its vehicle";
  EXPECT_FALSE(b.closed);
  EXPECT_EQ(b.all<sim::StateFrame>().size(), 6u);
  EXPECT_EQ(b.all<sim::StateFrame>().back().tick, world.tick());
}

TEST_F(HubTest, StateStreamOnlyAfterAttach) {
  FakeLink a;
  const auto id = join(a, "alice");
  step(2);
  EXPECT_TRUE(a.all<sim::StateFrame>().empty());
  send(id, sim::Attach{sim::Role::kWatcher, 0});
  step(2);
  const auto frames = a.all<sim::StateFrame>();
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[1].tick, frames[0].tick + 1);
  EXPECT_EQ(frames[1].vehicles.size(), 3u);
  EXPECT_EQ(frames[1].vehicles[2].station_id, 103u);
  EXPECT_EQ(frames[1].vehicles[0].send_wall_ns, clock::to_unix_ns(rt.wall_now() - 10ms));
}

TEST_F(HubTest, ShutdownSendsClosingToEveryone) {
  FakeLink a, b;
  join(a, "alice");
  join(b, "bob");
  hub.shutdown("SIGTERM");
  EXPECT_TRUE(a.closed);
  EXPECT_TRUE(b.closed);
  EXPECT_EQ(a.all<sim::Closing>().at(0).reason, sim::CloseReason::kShutdown);
  EXPECT_EQ(hub.clients(), 0u);
}

TEST_F(HubTest, TheEndOfTheScenarioIsItsOwnReason) {
  FakeLink a;
  join(a, "alice");
  hub.shutdown("scenario finished", sim::CloseReason::kScenarioFinished);
  EXPECT_TRUE(a.closed);
  EXPECT_EQ(a.all<sim::Closing>().at(0).reason, sim::CloseReason::kScenarioFinished);
}

TEST_F(HubTest, FastLoopWaitsForEveryDriversControls) {
  // Lockstep: in fast mode a step follows a State frame only once every driver has answered it,
  // so that a scripted driver sees every state; a driver that falls silent is waited for at
  // most the driver timeout, then braked and no longer waited for.
  std::deque<std::function<void()>> posted;
  SimLoop loop(rt, world, &hub, {.fast = true, .duration_s = 10.0},
               [&](std::function<void()> f) { posted.push_back(std::move(f)); });
  FakeLink a, b;
  const auto ida = join(a, "alice");
  const auto idb = join(b, "bob");
  send(ida, sim::Attach{sim::Role::kDriver, 0});
  send(idb, sim::Attach{sim::Role::kDriver, 1});
  const auto run_posted = [&] {
    while (!posted.empty()) {
      auto f = std::move(posted.front());
      posted.pop_front();
      f();
    }
  };
  // Before their first controls the drivers are not waited for (their cars stand braked).
  loop.start();
  run_posted();
  EXPECT_EQ(world.tick(), 1000u);
  EXPECT_TRUE(hub.drivers_answered());
  loop.stop();
  SimLoop again(rt, world, &hub, {.fast = true, .duration_s = 20.0},
                [&](std::function<void()> f) { posted.push_back(std::move(f)); });
  send(ida, sim::ControlsMsg{0, {0.3f, 0, 0, false, false}, 0});
  send(idb, sim::ControlsMsg{1, {0.3f, 0, 0, false, false}, 0});
  again.start();
  run_posted();
  EXPECT_EQ(world.tick(), 1001u) << "stepped without waiting for the drivers";
  EXPECT_FALSE(hub.drivers_answered());
  send(ida, sim::ControlsMsg{0, {0.3f, 0, 0, false, false}, 0});
  run_posted();
  EXPECT_EQ(world.tick(), 1001u) << "stepped before bob answered";
  send(idb, sim::ControlsMsg{1, {0.3f, 0, 0, false, false}, 0});
  run_posted();
  EXPECT_EQ(world.tick(), 1002u);
  // Bob falls silent: the loop waits 500 ms of real time, then steps without him; once the
  // watchdog has braked his car he is no longer waited for.
  send(ida, sim::ControlsMsg{0, {0.3f, 0, 0, false, false}, 0});
  run_posted();
  EXPECT_EQ(world.tick(), 1002u);
  rt.advance(Hub::kDriverTimeout + SimLoop::kWaitMargin);
  EXPECT_EQ(world.tick(), 1003u);
  EXPECT_EQ(again.driver_waits_timed_out(), 1u);
  EXPECT_EQ(hub.stats().watchdog_stops, 1u);
  send(ida, sim::ControlsMsg{0, {0.3f, 0, 0, false, false}, 0});
  run_posted();
  EXPECT_EQ(world.tick(), 1004u);
}

TEST_F(HubTest, FastLoopStartsOnceTheScriptedVehiclesHaveDrivers) {
  // Vehicle 1 runs a script: the fast loop does not run ahead of the client that runs it.
  scenario::Scenario scripted = sc;
  scripted.vehicles[1].driver = scenario::TimelineDriver{{{0.0, 0.5}}};
  Hub h(world, scripted, "{}", rt);
  std::deque<std::function<void()>> posted;
  SimLoop loop(rt, world, &h, {.fast = true, .duration_s = 1.0, .start_timeout = 10s},
               [&](std::function<void()> f) { posted.push_back(std::move(f)); });
  loop.start();
  rt.advance(SimLoop::kDriverPoll * 3);
  EXPECT_TRUE(posted.empty());
  FakeLink a;
  const auto id = h.connect(a, "test:scripts");
  h.receive(id, sim::encode(sim::Hello{"scripts"}));
  h.receive(id, sim::encode(sim::Attach{sim::Role::kDriver, 1}));
  rt.advance(SimLoop::kDriverPoll);
  ASSERT_EQ(posted.size(), 1u) << "did not start when the script's driver attached";
  posted.front()();
  EXPECT_EQ(world.tick(), 1u);

  // Nobody comes: it starts without them after the start timeout.
  Hub alone(world, scripted, "{}", rt);
  SimLoop late(rt, world, &alone, {.fast = true, .duration_s = 2.0, .start_timeout = 10s},
               [&](std::function<void()> f) { posted.push_back(std::move(f)); });
  posted.clear();
  late.start();
  rt.advance(10s - 2 * SimLoop::kDriverPoll);
  EXPECT_TRUE(posted.empty());
  rt.advance(3 * SimLoop::kDriverPoll);
  ASSERT_EQ(posted.size(), 1u) << "did not start without them after the start timeout";
  posted.front()();
  EXPECT_EQ(world.tick(), 2u);
}

TEST(HubSignals, TheLightsGoOutAfterWelcomeOnEveryChangeAndEverySecond) {
  // scenarios/signals-junction.json: groups 1+3 and 2+4 of junction 100, 20 s each, amber 3 s,
  // all-red 2 s, red+amber 1 s, offset 31 s: at sim time 0 groups 1 and 3 are amber until
  // 2 s; 2 and 4 turn red+amber at 4 s and green at 5 s (docs/scenario.md).
  const scenario::Scenario sc = scenario::load_file("scenarios/signals-junction.json");
  physics::World world{sc, physics::WorldOptions{.step_s = 0.01}};
  clock::ManualRuntime rt;
  Hub hub{world, sc, "{}", rt};
  FakeLink a;
  const auto id = hub.connect(a, "test:a");
  hub.receive(id, sim::encode(sim::Hello{"a"}));
  ASSERT_EQ(a.got.size(), 2u);
  ASSERT_TRUE(std::holds_alternative<sim::Welcome>(a.got[0]));
  const std::int64_t t0 = hub.world_start_ns() / 1'000'000;
  using P = sim::MovementPhaseState;
  auto states = [](const sim::SignalStates& s) {
    std::vector<P> out;
    for (const auto& g : s.groups) {
      EXPECT_EQ(g.intersection_id, 100);
      out.push_back(g.state);
    }
    return out;
  };
  const auto& first = std::get<sim::SignalStates>(a.got[1]);
  EXPECT_EQ(first.world_time_ms, t0);
  EXPECT_EQ(states(first), (std::vector<P>{P::kProtectedClearance, P::kStopAndRemain,
                                           P::kProtectedClearance, P::kStopAndRemain}));
  EXPECT_EQ(first.groups[0].next_change_ms, t0 + 2000);
  EXPECT_EQ(first.groups[1].next_change_ms, t0 + 4000);

  hub.receive(id, sim::encode(sim::Attach{sim::Role::kWatcher, 0}));
  for (int i = 0; i < 600; ++i) {
    hub.before_step();
    world.step();
    hub.after_step();
    rt.advance(10ms);
  }
  const auto got = a.all<sim::SignalStates>();
  std::map<std::int64_t, std::vector<P>> by_time;
  for (std::size_t i = 1; i < got.size(); ++i) {
    EXPECT_LE(got[i].world_time_ms - got[i - 1].world_time_ms, Hub::kSignalStatesPeriodMs);
    by_time[got[i].world_time_ms - t0] = states(got[i]);
  }
  // The changes, each in the step it happens in: 1 and 3 red at 2 s, 2 and 4 red+amber at 4 s
  // and green at 5 s.
  ASSERT_TRUE(by_time.count(2000));
  EXPECT_EQ(by_time[2000], (std::vector<P>{P::kStopAndRemain, P::kStopAndRemain, P::kStopAndRemain,
                                           P::kStopAndRemain}));
  ASSERT_TRUE(by_time.count(4000));
  EXPECT_EQ(by_time[4000], (std::vector<P>{P::kStopAndRemain, P::kPreMovement, P::kStopAndRemain,
                                           P::kPreMovement}));
  ASSERT_TRUE(by_time.count(5000));
  EXPECT_EQ(by_time[5000], (std::vector<P>{P::kStopAndRemain, P::kProtectedMovementAllowed,
                                           P::kStopAndRemain, P::kProtectedMovementAllowed}));
  EXPECT_EQ(by_time.rbegin()->first, 6000);
  // Nothing else changed: between the changes only the once-a-second repeats (a handful).
  EXPECT_LE(got.size(), 10u);
}

}  // namespace
}  // namespace tb::server
