#include <gtest/gtest.h>

#include <algorithm>

#include "sim-client/net/session.hpp"
#include "sim-client/net/tests/fake_server.hpp"

namespace tb::client {
namespace {

namespace sim = wire::sim;
using testing::decode_all;

class CaptureSink final : public DatagramSink {
 public:
  bool send(std::span<const std::uint8_t> d) override {
    sent.emplace_back(d.begin(), d.end());
    return true;
  }
  std::vector<std::vector<std::uint8_t>> sent;
};

class SessionTest : public ::testing::Test {
 protected:
  SimSession make(SessionOptions o) {
    return SimSession(
        std::move(o),
        [this](std::vector<std::uint8_t> b) { out.insert(out.end(), b.begin(), b.end()); }, &fwd,
        tracer, &clk);
  }
  // Feeds a server message one byte at a time, as a slow socket might deliver it.
  template <class M>
  bool feed(SimSession& s, const M& m, bool bytewise = false) {
    const auto bytes = sim::encode(m);
    if (!bytewise)
      return s.on_bytes(bytes);
    for (std::uint8_t b : bytes) {
      if (!s.on_bytes(std::span<const std::uint8_t>(&b, 1)))
        return false;
    }
    return true;
  }
  std::vector<sim::ClientMessage> take() {
    auto m = decode_all(out);
    out.clear();
    return m;
  }

  std::vector<std::uint8_t> out;
  clock::ManualClock clk;
  CaptureSink sink;
  trace::Tracer tracer;
  StateForwarder fwd{clk, sink, tracer};
};

TEST_F(SessionTest, HelloAttachControlsAndForwarding) {
  SessionOptions o;
  o.client_name = "alice";
  o.vehicles = {"me"};
  o.scripted = true;
  SimSession s = make(o);
  s.on_connected();
  auto msgs = take();
  ASSERT_EQ(msgs.size(), 1u);
  EXPECT_EQ(std::get<sim::Hello>(msgs[0]).client_name, "alice");

  ASSERT_TRUE(feed(s, testing::welcome(), true));
  EXPECT_EQ(s.phase(), SimSession::Phase::kRunning);
  ASSERT_NE(s.network(), nullptr);
  msgs = take();
  ASSERT_EQ(msgs.size(), 3u);
  for (std::uint16_t i = 0; i < 3; ++i)
    EXPECT_EQ(std::get<sim::Attach>(msgs[i]), (sim::Attach{sim::Role::kDriver, i}));

  for (std::uint16_t i = 0; i < 3; ++i)
    ASSERT_TRUE(feed(s, sim::AttachResult{sim::Role::kDriver, i, sim::AttachStatus::kOk, ""}));
  EXPECT_EQ(s.driven(), (std::vector<std::uint16_t>{0, 1, 2}));
  EXPECT_TRUE(s.human_driven(0));
  EXPECT_FALSE(s.human_driven(1));

  DriverCommand human;
  human.controls.throttle = 0.7f;
  human.controls.reverse = true;
  human.lights = wire::kIndicatorRight;
  const auto sampled = clk.wall_now() - std::chrono::milliseconds(3);
  s.set_human_command(human, sampled);
  clk.advance(std::chrono::milliseconds(1));
  ASSERT_TRUE(feed(s, testing::frame(5)));
  msgs = take();
  // The three vehicles' controls for this step leave in one ControlsBatch, in vehicle order.
  ASSERT_EQ(msgs.size(), 1u);
  const auto& batch = std::get<sim::ControlsBatch>(msgs[0]).entries;
  ASSERT_EQ(batch.size(), 3u);
  const auto& c0 = batch[0];
  EXPECT_EQ(c0.vehicle, 0);
  EXPECT_EQ(c0.controls, human.controls);
  EXPECT_EQ(c0.lights, wire::kIndicatorRight);
  // t1 starts when the input was read: the controller sample for the human, now for a script.
  EXPECT_EQ(c0.input_ns, clock::to_unix_ns(sampled));
  const auto& c1 = batch[1];
  EXPECT_EQ(c1.vehicle, 1);
  EXPECT_FLOAT_EQ(c1.controls.throttle, 0.25f);  // the timeline's step
  EXPECT_FLOAT_EQ(c1.controls.steer, 0.5f);
  // A scripted vehicle's lights are the scenario's switches: this one's light bar and siren.
  EXPECT_EQ(c1.lights, wire::kLightBar | wire::kSiren);
  EXPECT_EQ(c1.input_ns, clock::to_unix_ns(clk.wall_now()));
  const auto& c2 = batch[2];
  EXPECT_EQ(c2.vehicle, 2);
  EXPECT_GT(c2.controls.throttle, 0.0f);  // lane follower speeds up from 5 towards 10 m/s

  // The tick's three states leave in one batch datagram, in vehicle order.
  ASSERT_EQ(sink.sent.size(), 1u);
  std::vector<wire::VehicleState> states;
  const auto count = wire::decode_batch(sink.sent[0], states);
  ASSERT_TRUE(count.has_value()) << wire::to_string(count.error());
  ASSERT_EQ(states.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    auto want = testing::frame(5).vehicles[i];
    want.send_wall_ns = clock::to_unix_ns(clk.wall_now());
    EXPECT_EQ(states[i], want);
  }
  EXPECT_EQ(s.latest()->tick, 5u);
}

TEST_F(SessionTest, WatcherWhenNothingToDriveAndDriverChangesShow) {
  SimSession s = make({});
  s.on_connected();
  take();
  ASSERT_TRUE(feed(s, testing::welcome()));
  auto msgs = take();
  ASSERT_EQ(msgs.size(), 1u);
  EXPECT_EQ(std::get<sim::Attach>(msgs[0]).role, sim::Role::kWatcher);
  ASSERT_TRUE(feed(s, sim::DriverChanged{1, "bob"}));
  EXPECT_EQ(s.welcome()->vehicles[1].driver, "bob");
  ASSERT_TRUE(feed(s, testing::frame(1)));
  EXPECT_TRUE(take().empty());  // no controls, no forwarding
  EXPECT_TRUE(sink.sent.empty());
}

TEST_F(SessionTest, ForwardsTheVehiclesNobodyDrivesWhenAsked) {
  SessionOptions o;
  o.scripted = true;
  o.forward_undriven = true;
  SimSession s = make(o);
  s.on_connected();
  ASSERT_TRUE(feed(s, testing::welcome()));
  for (std::uint16_t i = 1; i < 3; ++i)
    ASSERT_TRUE(feed(s, sim::AttachResult{sim::Role::kDriver, i, sim::AttachStatus::kOk, ""}));
  // "me" (human) has no driver: its state goes with the scripted ones, once each.
  auto forwarded = [&] {
    std::vector<std::uint32_t> ids;
    for (const auto& d : sink.sent) {
      std::vector<wire::VehicleState> states;
      EXPECT_TRUE(wire::decode_batch(d, states).has_value());
      for (const auto& st : states)
        ids.push_back(st.station_id);
    }
    sink.sent.clear();
    std::sort(ids.begin(), ids.end());
    return ids;
  };
  ASSERT_TRUE(feed(s, testing::frame(1)));
  EXPECT_EQ(forwarded(), (std::vector<std::uint32_t>{1001, 1002, 1003}));
  // Its driver comes: their client forwards it now, this one no longer.
  ASSERT_TRUE(feed(s, sim::DriverChanged{0, "driver-me"}));
  ASSERT_TRUE(feed(s, testing::frame(2)));
  EXPECT_EQ(forwarded(), (std::vector<std::uint32_t>{1002, 1003}));
  // They leave (the window closed): the server brakes the car, and its station hears of it.
  ASSERT_TRUE(feed(s, sim::DriverChanged{0, ""}));
  ASSERT_TRUE(feed(s, testing::frame(3)));
  EXPECT_EQ(forwarded(), (std::vector<std::uint32_t>{1001, 1002, 1003}));
}

TEST_F(SessionTest, UnknownVehicleIsFatalAndNamesTheKnownOnes) {
  SessionOptions o;
  o.vehicles = {"nope"};
  SimSession s = make(o);
  s.on_connected();
  EXPECT_FALSE(feed(s, testing::welcome()));
  EXPECT_EQ(s.phase(), SimSession::Phase::kFailed);
  EXPECT_EQ(s.fatal_error(),
            "--vehicle nope: the server's scenario has no such vehicle (it has me, tl, lf)");
}

TEST_F(SessionTest, RefusedAttachIsFatalWhenNothingElseIsDriven) {
  SessionOptions o;
  o.vehicles = {"me"};
  SimSession s = make(o);
  s.on_connected();
  ASSERT_TRUE(feed(s, testing::welcome()));
  EXPECT_FALSE(feed(
      s, sim::AttachResult{sim::Role::kDriver, 0, sim::AttachStatus::kAlreadyDriven, "carol"}));
  EXPECT_EQ(s.phase(), SimSession::Phase::kFailed);
}

TEST_F(SessionTest, AfterReconnectionWaitsForItsOldVehicleToBeFreed) {
  SessionOptions o;
  o.vehicles = {"me"};
  SimSession s = make(o);
  s.on_connected();
  ASSERT_TRUE(feed(s, testing::welcome()));
  ASSERT_TRUE(feed(s, sim::AttachResult{sim::Role::kDriver, 0, sim::AttachStatus::kOk, ""}));
  s.on_disconnected();
  EXPECT_TRUE(s.driven().empty());
  s.on_connected();
  ASSERT_TRUE(feed(s, testing::welcome()));
  take();
  // The server still sees the old connection as the driver: not fatal this time.
  ASSERT_TRUE(feed(
      s, sim::AttachResult{sim::Role::kDriver, 0, sim::AttachStatus::kAlreadyDriven, "me-old"}));
  EXPECT_EQ(s.phase(), SimSession::Phase::kRunning);
  ASSERT_TRUE(feed(s, sim::DriverChanged{1, ""}));  // another vehicle: no attach
  EXPECT_TRUE(take().empty());
  ASSERT_TRUE(feed(s, sim::DriverChanged{0, ""}));
  const auto msgs = take();
  ASSERT_EQ(msgs.size(), 1u);
  EXPECT_EQ(std::get<sim::Attach>(msgs[0]), (sim::Attach{sim::Role::kDriver, 0}));
  ASSERT_TRUE(feed(s, sim::AttachResult{sim::Role::kDriver, 0, sim::AttachStatus::kOk, ""}));
  EXPECT_EQ(s.driven(), (std::vector<std::uint16_t>{0}));
}

TEST_F(SessionTest, ListStopsAfterWelcome) {
  SessionOptions o;
  o.list_only = true;
  SimSession s = make(o);
  s.on_connected();
  auto w = testing::welcome();
  w.vehicles[0].driver = "alice";
  EXPECT_FALSE(feed(s, w));
  EXPECT_EQ(s.phase(), SimSession::Phase::kListed);
  const std::string list = format_vehicle_list(*s.welcome());
  EXPECT_NE(list.find("me"), std::string::npos);
  EXPECT_NE(list.find("alice"), std::string::npos);
  EXPECT_NE(list.find("lane_follow"), std::string::npos);
}

TEST_F(SessionTest, ProtocolErrorsAndClosingEndTheConnection) {
  SimSession s = make({});
  s.on_connected();
  const std::vector<std::uint8_t> junk{'X', 'Y', 1, 0x81, 0, 0, 0, 0};
  EXPECT_FALSE(s.on_bytes(junk));
  EXPECT_EQ(s.last_error(), "malformed data from the server: " +
                                std::string(to_string(sim::ProtocolError::kBadMagic)));

  // A new connection starts a fresh parser; Closing is reported with its reason.
  s.on_disconnected();
  s.on_connected();
  ASSERT_TRUE(feed(s, testing::welcome()));
  EXPECT_FALSE(feed(s, sim::Closing{sim::CloseReason::kShutdown, "bye"}));
  EXPECT_NE(s.last_error().find("bye"), std::string::npos);
  EXPECT_EQ(s.phase(), SimSession::Phase::kRunning);  // until the link reports the close
  s.on_disconnected();
  EXPECT_EQ(s.phase(), SimSession::Phase::kDisconnected);
}

TEST_F(SessionTest, TheEndOfTheScenarioEndsTheSessionUnlessItReconnects) {
  SimSession s = make({});
  s.on_connected();
  ASSERT_TRUE(feed(s, testing::welcome()));
  EXPECT_FALSE(feed(s, sim::Closing{sim::CloseReason::kScenarioFinished, "scenario finished"}));
  EXPECT_EQ(s.phase(), SimSession::Phase::kFinished);
  EXPECT_TRUE(s.ended());
  // The link's close and a later connection change nothing: nothing more will come.
  s.on_disconnected();
  s.on_connected();
  EXPECT_EQ(s.phase(), SimSession::Phase::kFinished);

  SessionOptions again;
  again.reconnect = true;
  SimSession r = make(again);
  r.on_connected();
  ASSERT_TRUE(feed(r, testing::welcome()));
  EXPECT_FALSE(feed(r, sim::Closing{sim::CloseReason::kScenarioFinished, "scenario finished"}));
  EXPECT_FALSE(r.ended());
  r.on_disconnected();
  EXPECT_EQ(r.phase(), SimSession::Phase::kDisconnected);
  // A server that stops (kShutdown) never ends a session.
  SimSession t = make({});
  t.on_connected();
  ASSERT_TRUE(feed(t, testing::welcome()));
  EXPECT_FALSE(feed(t, sim::Closing{sim::CloseReason::kShutdown, "SIGTERM"}));
  EXPECT_FALSE(t.ended());
}

TEST_F(SessionTest, StateBeforeWelcomeIsAnError) {
  SimSession s = make({});
  s.on_connected();
  EXPECT_FALSE(feed(s, testing::frame(1)));
  EXPECT_EQ(s.last_error(), "the server sent a message before Welcome");
}

TEST_F(SessionTest, KeepsTheLatestSignalStatesPerJunction) {
  SessionOptions o;
  o.client_name = "watcher";
  SimSession s = make(o);
  s.on_connected();
  ASSERT_TRUE(feed(s, testing::welcome()));
  EXPECT_TRUE(s.signals().empty());
  const std::int64_t t = 1'795'000'000'000;
  using P = sim::MovementPhaseState;
  ASSERT_TRUE(feed(s, sim::SignalStates{t,
                                        {{7, 1, P::kProtectedMovementAllowed, t + 900, t + 900},
                                         {100, 1, P::kProtectedClearance, t + 2000, t + 2000},
                                         {100, 2, P::kStopAndRemain, t + 5000, t + 5000}}}));
  ASSERT_EQ(s.signals().size(), 2u);
  EXPECT_EQ(s.signals().at(100).groups.size(), 2u);
  EXPECT_EQ(s.signals().at(100).groups[0].state, P::kProtectedClearance);
  EXPECT_EQ(s.signals().at(7).world_time_ms, t);
  // The scripted drivers' view of them: dated on the Welcome's world clock.
  const std::int64_t start = s.welcome()->world_start_ns;
  EXPECT_EQ(s.lights().aspect_of(100, 1, t * 1'000'000 - start), LightAspect::kAmber);
  EXPECT_EQ(s.lights().aspect_of(7, 1, t * 1'000'000 - start), LightAspect::kGo);
  // The next message replaces them: junction 7 gone, 100's states moved on.
  ASSERT_TRUE(feed(s,
                   sim::SignalStates{t + 2000,
                                     {{100, 1, P::kStopAndRemain, t + 30000, t + 30000},
                                      {100, 2, P::kStopAndRemain, t + 5000, t + 5000}}},
                   true));
  ASSERT_EQ(s.signals().size(), 1u);
  EXPECT_EQ(s.signals().at(100).groups[0].state, P::kStopAndRemain);
  EXPECT_EQ(s.signals().at(100).world_time_ms, t + 2000);
  EXPECT_EQ(s.lights().aspect_of(100, 1, (t + 2000) * 1'000'000 - start), LightAspect::kStop);
  EXPECT_EQ(s.lights().aspect_of(7, 1, (t + 2000) * 1'000'000 - start), LightAspect::kNone);
}

TEST_F(SessionTest, ForwardsEverySignalStatesAsOneFrameToTheEmulator) {
  SessionOptions o;
  o.client_name = "forwarder";
  SimSession s = make(o);
  CaptureSink signal_sink;
  trace::Tracer off;
  SignalForwarder signals(signal_sink, off);
  s.set_signal_forwarder(&signals);
  s.on_connected();
  ASSERT_TRUE(feed(s, testing::welcome()));
  const std::int64_t t = 1'795'000'000'000;
  using P = sim::MovementPhaseState;
  const sim::SignalStates first{t,
                                {{7, 1, P::kProtectedMovementAllowed, t + 900, t + 900},
                                 {100, 1, P::kProtectedClearance, t + 2000, t + 2000}}};
  const sim::SignalStates second{t + 100, {{100, 1, P::kStopAndRemain, t + 30000, t + 30000}}};
  // The second arrives a byte at a time: it leaves once, when its frame is complete.
  ASSERT_TRUE(feed(s, first));
  ASSERT_TRUE(feed(s, second, true));
  ASSERT_EQ(signal_sink.sent.size(), 2u);
  // Each datagram is exactly the sim-protocol frame, all junctions' groups as the server sent
  // them (the emulator picks each RSU's junction).
  EXPECT_EQ(signal_sink.sent[0], sim::encode(first));
  EXPECT_EQ(signal_sink.sent[1], sim::encode(second));
  EXPECT_EQ(signals.sent(), 2u);
  // The vehicle-state sink got none of them.
  EXPECT_TRUE(sink.sent.empty());
}

TEST_F(SessionTest, AClientThatForwardsNothingSendsNoSignals) {
  SessionOptions o;
  o.client_name = "watcher";
  SimSession s = make(o);  // no signal forwarder, as with --no-forward or --list
  s.on_connected();
  ASSERT_TRUE(feed(s, testing::welcome()));
  ASSERT_TRUE(feed(s, sim::SignalStates{5, {}}));
  EXPECT_TRUE(sink.sent.empty());
  EXPECT_TRUE(s.signals().empty());
}

}  // namespace
// An OpenDRIVE map travels in Welcome: a client on another computer has no copy of the file.
constexpr const char* kOpenDriveScenario = R"({
  "name": "opendrive-session",
  "map": { "type": "opendrive", "file": "maps/only-on-the-server.xodr" },
  "origin": { "lat": 41.1, "lon": 29.0, "alt": 60 },
  "vehicles": [
    { "id": "me", "station_id": 1001, "spawn": { "road": "12", "lane": -1, "s": 10 } },
    { "id": "tl", "station_id": 1002, "spawn": { "road": "12", "lane": 1, "s": 90 },
      "driver": { "type": "timeline", "steps": [ { "t": 0, "throttle": 0.25 } ] } }
  ]
})";
constexpr const char* kOpenDriveMap =
    R"(<OpenDRIVE><header revMajor="1" revMinor="6"/><road id="12" length="100" junction="-1">
<planView><geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry></planView>
<lanes><laneSection s="0"><left><lane id="1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></left>
<center><lane id="0" type="none"/></center><right><lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></right>
</laneSection></lanes></road></OpenDRIVE>)";

sim::Welcome opendrive_welcome(std::string map_text) {
  sim::Welcome w = testing::welcome();
  w.vehicles.resize(2);
  w.scenario_json = kOpenDriveScenario;
  w.map_text = std::move(map_text);
  return w;
}

TEST_F(SessionTest, AnOpenDriveMapArrivesWithTheWelcome) {
  SessionOptions o;
  o.vehicles = {"me"};
  o.scripted = true;
  SimSession s = make(o);
  s.on_connected();
  ASSERT_TRUE(feed(s, opendrive_welcome(kOpenDriveMap))) << s.fatal_error();
  ASSERT_NE(s.network(), nullptr);
  ASSERT_EQ(s.network()->roads.size(), 1u);
  EXPECT_EQ(s.network()->roads[0].id, "12");
  ASSERT_NE(s.map(), nullptr);
  EXPECT_EQ(s.map()->origin().source, "scenario origin");
  const auto msgs = take();
  ASSERT_EQ(msgs.size(), 3u);  // Hello, then the human car and the timeline
  EXPECT_EQ(std::get<sim::Attach>(msgs[1]), (sim::Attach{sim::Role::kDriver, 0}));
  EXPECT_EQ(std::get<sim::Attach>(msgs[2]), (sim::Attach{sim::Role::kDriver, 1}));
  EXPECT_FALSE(s.human_driven(1));
}

TEST_F(SessionTest, AnOpenDriveScenarioWithoutItsMapTextIsAFatalErrorNamingTheFile) {
  SimSession s = make(SessionOptions{});
  s.on_connected();
  EXPECT_FALSE(feed(s, opendrive_welcome("")));
  EXPECT_EQ(s.phase(), SimSession::Phase::kFailed);
  EXPECT_NE(s.fatal_error().find("/map/file: maps/only-on-the-server.xodr: no such file"),
            std::string::npos)
      << s.fatal_error();
}

}  // namespace tb::client
