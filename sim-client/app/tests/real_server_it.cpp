// sim-client against the real sim-server process from $TESTBED_BIN: the lane-following driver
// on the server's Bullet vehicle, and keyboard input reaching the server's physics.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include <boost/asio/ip/udp.hpp>

#include "common/map/builtin_network.hpp"
#include "common/map/opendrive/queries.hpp"
#include "sim-client/app/client_app.hpp"
#include "sim-client/app/tests/run_program.hpp"
#include "sim-client/app/tests/sim_server_process.hpp"

namespace tb::client {
namespace {

namespace asio = boost::asio;
using namespace std::chrono_literals;

constexpr const char* kScenario = R"({
  "name": "sim-client-it",
  "map": { "type": "straight", "lanes": 2, "lane_width": 3.5, "length": 2000 },
  "origin": { "lat": 41.1, "lon": 29.0, "alt": 60 },
  "vehicles": [
    { "id": "me", "station_id": 2001, "color": "#20a040",
      "spawn": { "lane": 0, "s": 20, "speed": 0 }, "driver": "human" },
    { "id": "lf", "station_id": 2002, "color": "#d02020",
      "spawn": { "lane": 0, "s": 200, "speed": 8 },
      "driver": { "type": "lane_follow", "speed_profile": [ { "t": 0, "speed": 12 } ] } }
  ]
})";

// Two seconds of sim time, no warm-up: the server says "scenario finished" soon after the
// scripted car has its driver.
constexpr const char* kShortScenario = R"({
  "name": "short",
  "duration_s": 2,
  "warmup_s": 0,
  "map": { "type": "straight", "lanes": 1, "lane_width": 3.5, "length": 500 },
  "origin": { "lat": 41.1, "lon": 29.0, "alt": 60 },
  "vehicles": [
    { "id": "lf", "station_id": 2101, "spawn": { "lane": 0, "s": 20, "speed": 5 },
      "driver": { "type": "lane_follow", "speed_profile": [ { "t": 0, "speed": 8 } ] } }
  ]
})";

std::string bin_dir() {
  const char* b = std::getenv("TESTBED_BIN");
  return b != nullptr ? b : "build/bin";
}

void pump(asio::io_context& io, std::chrono::milliseconds d) {
  io.restart();
  io.run_for(d);
}

TEST(RealSimServer, LaneFollowerHoldsTargetSpeedInLaneAndKeysDriveTheCar) {
  auto server = testing::SimServerProcess::with_text(kScenario);
  if (!server.available())
    GTEST_SKIP() << "no sim-server in $TESTBED_BIN";
  ASSERT_NE(server.port(), 0) << server.log();

  asio::io_context io;
  asio::ip::udp::socket rx(io, {asio::ip::address_v4::loopback(), 0});
  rx.non_blocking(true);
  AppOptions o;
  o.server = "127.0.0.1:" + std::to_string(server.port());
  o.emulator = "127.0.0.1:" + std::to_string(rx.local_endpoint().port());
  o.session.vehicles = {"me"};
  o.session.scripted = true;
  o.headless = true;
  ClientApp app(io, o);
  app.start();

  scenario::MapSpec spec;
  spec.length = 2000.0;
  const map::odr::RoadNetwork road = map::generate_network(spec);
  const map::odr::LaneLocator lanes(road);
  const double margin = (3.5 - scenario::VehicleModel{}.width_m) / 2.0;
  std::size_t forwarded = 0, checked = 0;
  double max_lateral = 0.0;
  bool pressed = false;
  float me_throttle = 0.0f, me_speed = 0.0f;
  std::array<std::uint8_t, 2048> buf{};
  std::vector<wire::VehicleState> states;
  const auto deadline = std::chrono::steady_clock::now() + 40s;
  double lf_time = 0.0;
  while (lf_time < 12.0 && std::chrono::steady_clock::now() < deadline && !app.stopped()) {
    pump(io, 20ms);
    if (!pressed && app.session().frames() > 10) {
      SDL_Event e{};
      e.type = SDL_KEYDOWN;
      e.key.state = SDL_PRESSED;
      e.key.keysym.scancode = SDL_SCANCODE_W;
      ASSERT_EQ(SDL_PushEvent(&e), 1);
      pressed = true;
    }
    boost::system::error_code ec;
    for (std::size_t n = rx.receive(asio::buffer(buf), 0, ec); !ec;
         n = rx.receive(asio::buffer(buf), 0, ec)) {
      const auto count = wire::decode_batch(std::span<const std::uint8_t>(buf.data(), n), states);
      ASSERT_TRUE(count.has_value()) << to_string(count.error());
      // The driven cars' states of a tick share one datagram (one car until both attached).
      ASSERT_GE(states.size(), 1u);
      ASSERT_LE(states.size(), 2u);
      for (const auto& state : states) {
        const wire::VehicleState* st = &state;
        ++forwarded;
        if (st->station_id == 2001) {
          me_throttle = st->controls.throttle;  // what the server applied
          me_speed = st->speed;
          continue;
        }
        ASSERT_EQ(st->station_id, 2002u);
        lf_time = st->sim_time_ns * 1e-9;
        // Off the centre of the built-in lane 0 (OpenDRIVE lane -1).
        const auto at = lanes.locate(st->position[0], st->position[1]);
        ASSERT_TRUE(at && at->ref.lane == -1) << "left its lane at sim time " << lf_time << " s";
        max_lateral = std::max(max_lateral,
                               std::abs(at->t - map::odr::lane_centre_t(road.roads[0], -1, at->s)));
        if (lf_time > 6.0) {
          ASSERT_NEAR(st->speed, 12.0, 0.5) << "at sim time " << lf_time << " s";
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 100u) << server.log();
  EXPECT_LT(max_lateral, margin);
  EXPECT_GT(forwarded, 1000u);
  // W held for seconds: the server applies full throttle and the car moves.
  EXPECT_FLOAT_EQ(me_throttle, 1.0f);
  EXPECT_GT(me_speed, 5.0f);
  app.stop(0);
}

TEST(RealSimServer, ScriptedHeadlessClientExitsZeroWhenTheScenarioFinishes) {
  auto server = testing::SimServerProcess::with_text(kShortScenario);
  if (!server.available())
    GTEST_SKIP() << "no sim-server in $TESTBED_BIN";
  ASSERT_NE(server.port(), 0) << server.log();
  const auto started = std::chrono::steady_clock::now();
  // The program, as the launcher runs it; 30 s is far beyond 2 s of sim time: a client that
  // reconnected for ever would be killed at the limit and report -1.
  const auto r = testing::run(
      {bin_dir() + "/sim-client", "--server", "127.0.0.1:" + std::to_string(server.port()),
       "--scripted", "--headless", "--no-forward", "--name", "finish-test"},
      30s);
  const double took =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  EXPECT_EQ(r.code, 0) << r.err << server.log();
  EXPECT_NE(r.err.find("the scenario finished"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("reconnecting"), std::string::npos) << r.err;
  // It ran the scenario (2 s of sim time in real time) rather than leaving at once.
  EXPECT_GE(took, 1.9);
  EXPECT_NE(server.log().find("scenario finished"), std::string::npos) << server.log();
}

TEST(RealSimServer, WithReconnectTheClientOutlivesTheFinishedScenario) {
  auto server = testing::SimServerProcess::with_text(kShortScenario);
  if (!server.available())
    GTEST_SKIP() << "no sim-server in $TESTBED_BIN";
  ASSERT_NE(server.port(), 0) << server.log();
  asio::io_context io;
  AppOptions o;
  o.server = "127.0.0.1:" + std::to_string(server.port());
  o.forward = false;
  o.session.scripted = true;
  o.session.reconnect = true;
  o.headless = true;
  ClientApp app(io, o);
  app.start();
  // Until the server has finished (its log says so and the connection is gone), then 3 s more.
  const auto deadline = std::chrono::steady_clock::now() + 30s;
  bool finished = false;
  while (!finished && std::chrono::steady_clock::now() < deadline && !app.stopped()) {
    pump(io, 50ms);
    finished = app.session().frames() > 0 &&
               server.log().find("scenario finished") != std::string::npos &&
               app.session().phase() == SimSession::Phase::kDisconnected;
  }
  ASSERT_TRUE(finished) << server.log();
  for (int i = 0; i < 60 && !app.stopped(); ++i)
    pump(io, 50ms);
  EXPECT_FALSE(app.stopped()) << "exited with " << app.exit_code();
  EXPECT_NE(app.session().phase(), SimSession::Phase::kFinished);
  app.stop(0);
}

}  // namespace
}  // namespace tb::client
