// sim-client against a server speaking the real protocol: the in-process stand-in
// (fake_sim_server.hpp) and, when $TESTBED_BIN holds it, the real sim-server.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include <boost/asio/ip/udp.hpp>

#include "common/mqtt/mosquitto_client.hpp"
#include "common/mqtt/tests/test_broker.hpp"
#include "sim-client/app/client_app.hpp"
#include "sim-client/app/tests/fake_sim_server.hpp"
#include "sim-client/app/tests/run_program.hpp"
#include "sim-client/view/tests/png_reader.hpp"
#include "sim-client/view3d/tests/xvfb.hpp"

namespace tb::client {
namespace {

namespace asio = boost::asio;
namespace sim = wire::sim;
using namespace std::chrono_literals;
using testing::Result;
using testing::run;

std::string bin() {
  const char* b = std::getenv("TESTBED_BIN");
  return b != nullptr ? b : "build/bin";
}

void push_key(SDL_Scancode code, bool down) {
  SDL_Event e{};
  e.type = down ? SDL_KEYDOWN : SDL_KEYUP;
  e.key.state = down ? SDL_PRESSED : SDL_RELEASED;
  e.key.keysym.scancode = code;
  ASSERT_EQ(SDL_PushEvent(&e), 1) << SDL_GetError();
}

// Runs the app's loop for @p d of real time.
void pump(asio::io_context& io, std::chrono::milliseconds d) {
  io.restart();
  io.run_for(d);
}

TEST(ClientApp, KeyboardEventsChangeTheControlsTheServerSees) {
  testing::FakeSimServer server;
  asio::io_context io;
  asio::ip::udp::socket rx(io, {asio::ip::address_v4::loopback(), 0});
  AppOptions o;
  o.server = "127.0.0.1:" + std::to_string(server.port());
  o.emulator = "127.0.0.1:" + std::to_string(rx.local_endpoint().port());
  o.session.vehicles = {"me"};
  o.session.client_name = "kbd-test";
  o.headless = true;
  ClientApp app(io, o);
  app.start();
  const auto wait_for = [&](auto cond) {
    for (int i = 0; i < 150 && !cond(); ++i)
      pump(io, 20ms);
    return cond();
  };
  ASSERT_TRUE(wait_for([&] { return server.last_controls(0).has_value(); }));
  EXPECT_FLOAT_EQ(server.last_controls(0)->controls.throttle, 0.0f);

  push_key(SDL_SCANCODE_W, true);
  push_key(SDL_SCANCODE_A, true);
  push_key(SDL_SCANCODE_Z, true);
  ASSERT_TRUE(wait_for([&] { return server.last_controls(0)->controls.throttle >= 1.0f; }));
  const auto c = *server.last_controls(0);
  EXPECT_LT(c.controls.steer, 0.0f);
  EXPECT_EQ(c.lights & wire::kIndicatorLeft, wire::kIndicatorLeft);
  push_key(SDL_SCANCODE_W, false);
  push_key(SDL_SCANCODE_SPACE, true);
  ASSERT_TRUE(wait_for([&] {
    const auto l = server.last_controls(0)->controls;
    return l.throttle == 0.0f && l.handbrake;
  }));

  // Every datagram forwarded decodes to a state the server sent for the driven car only.
  const auto sent = server.sent(1001);
  rx.non_blocking(true);
  int checked = 0;
  std::array<std::uint8_t, 2048> buf{};
  boost::system::error_code ec;
  std::vector<wire::VehicleState> states;
  for (std::size_t n = rx.receive(asio::buffer(buf), 0, ec); !ec;
       n = rx.receive(asio::buffer(buf), 0, ec)) {
    const auto count = wire::decode_batch(std::span<const std::uint8_t>(buf.data(), n), states);
    ASSERT_TRUE(count.has_value()) << wire::to_string(count.error());
    ASSERT_EQ(states.size(), 1u);  // one driven car: one state per tick
    auto& st = states[0];
    ASSERT_EQ(st.station_id, 1001u);
    const auto it = sent.find(st.tick);
    ASSERT_NE(it, sent.end());
    EXPECT_GE(st.send_wall_ns, it->second.step_wall_ns);
    st.send_wall_ns = it->second.send_wall_ns;
    EXPECT_EQ(st, it->second);
    ++checked;
  }
  EXPECT_GT(checked, 10);
  app.stop(0);
}

TEST(ClientApp, ReconnectsWhenTheServerIsLost) {
  testing::FakeSimServer server;
  asio::io_context io;
  AppOptions o;
  o.server = "127.0.0.1:" + std::to_string(server.port());
  o.forward = false;
  o.session.scripted = true;
  o.headless = true;
  ClientApp app(io, o);
  app.start();
  for (int i = 0; i < 100 && app.session().frames() < 5; ++i)
    pump(io, 20ms);
  ASSERT_GE(app.session().frames(), 5u);
  server.hang_up();
  for (int i = 0; i < 200 && server.accepted() < 2; ++i)
    pump(io, 20ms);
  EXPECT_EQ(server.accepted(), 2);
  const auto before = app.session().frames();
  for (int i = 0; i < 100 && app.session().frames() < before + 5; ++i)
    pump(io, 20ms);
  EXPECT_GE(app.session().frames(), before + 5);
  EXPECT_FALSE(app.stopped());
  // Both scripted cars were attached again on the new connection.
  int attaches = 0;
  for (const auto& m : server.received())
    attaches += std::holds_alternative<sim::Attach>(m) ? 1 : 0;
  EXPECT_EQ(attaches, 4);
  app.stop(0);
}

TEST(SimClientProgram, ListsVehicles) {
  testing::FakeSimServer server;
  const auto r = run(
      {bin() + "/sim-client", "--server", "127.0.0.1:" + std::to_string(server.port()), "--list"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("lane_follow"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1002"), std::string::npos) << r.out;
}

TEST(SimClientProgram, UnknownVehicleIsAClearError) {
  testing::FakeSimServer server;
  const auto r =
      run({bin() + "/sim-client", "--server", "127.0.0.1:" + std::to_string(server.port()),
           "--vehicle", "ghost", "--headless", "--no-forward"});
  EXPECT_EQ(r.code, kExitCannotDrive);
  EXPECT_NE(r.err.find("--vehicle ghost: the server's scenario has no such vehicle"),
            std::string::npos)
      << r.err;
}

TEST(SimClientProgram, BadMappingNamesFileAndField) {
  const std::string path = ::testing::TempDir() + "/simclient_bad_mapping.json";
  std::ofstream(path) << R"({"api": "joystick", "steer": {"axis": "leftx"}})";
  const auto r = run({bin() + "/sim-client", "--mapping", path, "--headless", "--duration", "1"});
  EXPECT_EQ(r.code, kExitUsage);
  EXPECT_NE(r.err.find(path + ": /steer/axis: must be an axis index"), std::string::npos) << r.err;
}

TEST(SimClientProgram, NoServerIsReportedAndRetriedNotAHang) {
  std::uint16_t port = 0;
  {
    asio::io_context io;
    asio::ip::tcp::acceptor probe(io, {asio::ip::address_v4::loopback(), 0});
    port = probe.local_endpoint().port();
  }
  const auto r = run({bin() + "/sim-client", "--server", "127.0.0.1:" + std::to_string(port),
                      "--headless", "--no-forward", "--duration", "1.5"});
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("cannot connect to sim-server 127.0.0.1:" + std::to_string(port)),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("retrying in"), std::string::npos) << r.err;
}

// The view, in a real window under Xvfb, written as a PNG.
TEST(SimClientProgram, ScreenshotUnderXvfb) {
  // Our own Xvfb rather than xvfb-run: xvfb-run exits 5 when it cannot remove its temporary
  // directory, whatever the program's exit code was.
  testing::Xvfb xvfb("1024x768x24");
  if (!xvfb.running())
    GTEST_SKIP() << "Xvfb did not start (scripts/install-deps installs xvfb)";
  testing::FakeSimServer server;
  const std::string png = ::testing::TempDir() + "/simclient_xvfb.png";
  std::remove(png.c_str());
  const auto r =
      run({bin() + "/sim-client", "--server", "127.0.0.1:" + std::to_string(server.port()),
           "--vehicle", "me", "--no-forward", "--view", "topdown", "--width", "800", "--height",
           "600", "--screenshot", png, "--after", "1", "--duration", "1.3"},
          40s,
          // Under CI's sanitizer run, D-Bus inside SDL's X11 backend leaks at exit;
          // the headless runs above keep leak checking of our own code.
          {{"ASAN_OPTIONS", "detect_leaks=0"}});
  ASSERT_EQ(r.code, 0) << r.err;
  testing::Image im;
  ASSERT_TRUE(testing::read_png(png, im)) << r.err;
  EXPECT_EQ(im.width, 800);
  EXPECT_EQ(im.height, 600);
  EXPECT_GT(testing::distinct_colours(im), 5);
  // The own car ("me", #d02020 in the fake scenario) sits at the view's anchor.
  EXPECT_GT(testing::count_near(im, 400, 360, 40, 0xd0, 0x20, 0x20), 200);
}

// The 3D view by default where there is a display; --headless --screenshot works for every
// camera (a hidden window: one GL context, no window on the screen).
TEST(SimClientProgram, Headless3dScreenshotOfEveryCamera) {
  testing::Xvfb xvfb;
  if (!xvfb.running())
    GTEST_SKIP() << "Xvfb did not start (scripts/install-deps installs xvfb)";
  testing::FakeSimServer server;
  std::vector<testing::Image> shots;
  for (const char* camera : {"chase", "cockpit", "top", "orbit"}) {
    SCOPED_TRACE(camera);
    const std::string png = ::testing::TempDir() + "/simclient_3d_" + camera + ".png";
    std::remove(png.c_str());
    const auto r =
        run({bin() + "/sim-client", "--server", "127.0.0.1:" + std::to_string(server.port()),
             "--vehicle", "me", "--no-forward", "--headless", "--camera", camera, "--width", "640",
             "--height", "360", "--screenshot", png, "--after", "0.8", "--duration", "1"},
            60s, {{"ASAN_OPTIONS", "detect_leaks=0"}});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("3D view: OpenGL"), std::string::npos) << r.err;
    testing::Image im;
    ASSERT_TRUE(testing::read_png(png, im)) << r.err;
    EXPECT_EQ(im.width, 640);
    EXPECT_EQ(im.height, 360);
    EXPECT_GT(testing::distinct_colours(im), 20);
    // The own car ("me", #d02020, lit by the sun) is in the picture, except from its own
    // driver's seat (above the dashboard, whose needles are red too).
    int red = 0;
    for (int y = 0; y < im.height * 3 / 4; ++y)
      for (int x = 0; x < im.width; ++x) {
        const auto* p = im.at(x, y);
        red += p[0] > p[1] + 80 && p[0] > p[2] + 80;
      }
    if (std::string(camera) == "cockpit")
      EXPECT_LT(red, 30);
    else
      EXPECT_GT(red, 100);
    for (const auto& other : shots)
      EXPECT_NE(other.rgba, im.rgba);
    shots.push_back(im);
  }
}

TEST(ClientApp, TabSwitchesTheCameraTheRenderThreadDraws) {
  testing::Xvfb xvfb;
  if (!xvfb.running())
    GTEST_SKIP() << "Xvfb did not start (scripts/install-deps installs xvfb)";
  testing::FakeSimServer server;
  asio::io_context io;
  AppOptions o;
  o.server = "127.0.0.1:" + std::to_string(server.port());
  o.forward = false;
  o.session.vehicles = {"me"};
  o.view = ViewKind::k3d;
  o.width = 480;
  o.height = 270;
  std::mutex mu;
  view3d::FrameStats last;
  o.frame_observer = [&](const view3d::FrameStats& s) {
    std::lock_guard l(mu);
    last = s;
  };
  ClientApp app(io, o);
  ASSERT_EQ(app.view(), ViewKind::k3d);
  app.start();
  const auto drawn = [&](view3d::CameraMode m) {
    for (int i = 0; i < 250; ++i) {
      pump(io, 20ms);
      std::lock_guard l(mu);
      if (last.camera == m && last.subject == 0)
        return true;
    }
    return false;
  };
  ASSERT_TRUE(drawn(view3d::CameraMode::kChase));
  for (auto m : {view3d::CameraMode::kCockpit, view3d::CameraMode::kTop, view3d::CameraMode::kOrbit,
                 view3d::CameraMode::kChase}) {
    push_key(SDL_SCANCODE_TAB, true);
    push_key(SDL_SCANCODE_TAB, false);
    EXPECT_TRUE(drawn(m)) << "camera " << view3d::to_string(m);
  }
  // The driving keys still drive while the view has its own.
  push_key(SDL_SCANCODE_W, true);
  for (int i = 0; i < 150 && server.last_controls(0)->controls.throttle < 1.0f; ++i)
    pump(io, 20ms);
  EXPECT_FLOAT_EQ(server.last_controls(0)->controls.throttle, 1.0f);
  push_key(SDL_SCANCODE_W, false);
  app.stop(0);
}

// --mqtt end to end in the program: the view reads the broker as the hmi user and the banner
// comes and goes with the own station's warning.
TEST(ClientApp, MqttWarningBannerComesAndGoes) {
  testing::Xvfb xvfb;
  if (!xvfb.running())
    GTEST_SKIP() << "Xvfb did not start (scripts/install-deps installs xvfb)";
  mqtt::testing::Broker broker("1001,1002");
  ASSERT_TRUE(broker.configured());
  ASSERT_TRUE(broker.start()) << broker.log();
  clock::SystemClock clk;
  mqtt::ClientConfig sc = broker.station_account(1001);
  mqtt::MosquittoClient station(clk, sc);
  station.start();

  testing::FakeSimServer server;
  asio::io_context io;
  AppOptions o;
  o.server = "127.0.0.1:" + std::to_string(server.port());
  o.forward = false;
  o.session.vehicles = {"me"};  // station 1001
  o.view = ViewKind::k3d;
  o.width = 480;
  o.height = 270;
  o.mqtt = "127.0.0.1:" + std::to_string(broker.port());
  std::mutex mu;
  std::string banner;
  o.frame_observer = [&](const view3d::FrameStats& s) {
    std::lock_guard l(mu);
    banner = s.banner;
  };
  ClientApp app(io, o);
  app.start();
  const auto shown = [&](auto pred) {
    for (int i = 0; i < 400; ++i) {
      pump(io, 20ms);
      std::lock_guard l(mu);
      if (pred(banner))
        return true;
    }
    return false;
  };
  const std::string raised =
      R"({"type":"lcrw_warning","message":{"station_id":1001,"other_station_id":1002,)"
      R"("event":"raised","collision_case":"rear_end","severity":"critical","ttc_s":1.2,)"
      R"("distance_m":14.0}})";
  // Raised (and raised again while the view's subscription is being set up), then updated.
  ASSERT_TRUE(shown([&](const std::string& b) {
    station.publish("its/1001/app/lcrw", raised, mqtt::Qos::kAtLeastOnce, false);
    return b.find("TTC 1.2 s") != std::string::npos;
  })) << "banner: "
      << banner;
  EXPECT_NE(banner.find("BRAKE"), std::string::npos) << banner;
  EXPECT_NE(banner.find("rear end"), std::string::npos) << banner;
  station.publish("its/1001/app/lcrw",
                  R"({"type":"lcrw_warning","message":{"station_id":1001,"other_station_id":1002,)"
                  R"("event":"cleared","clear_reason":"risk_ended"}})",
                  mqtt::Qos::kAtLeastOnce, false);
  EXPECT_TRUE(shown([](const std::string& b) { return b.empty(); })) << banner;
  app.stop(0);
  station.stop();
}

// Issue 34: the own lane's signal and the red-light warning through a real broker, as the
// station publishes them (signal QoS 0 at 10 Hz, RLVW QoS 1), into the frames the render
// thread draws: the panel's light and the banner come, and go with "lane": null and cleared.
// A watcher with --follow shows the HUD of the car it names, not the first car's: how the
// light → HUD measurement (tests/e2e/signal_hud_runs.py) sees a scripted car's signal panel.
TEST(ClientApp, WatcherFollowsTheCarItNamesAndShowsItsSignalPanel) {
  testing::Xvfb xvfb;
  if (!xvfb.running())
    GTEST_SKIP() << "Xvfb did not start (scripts/install-deps installs xvfb)";
  mqtt::testing::Broker broker("1001,1002");
  ASSERT_TRUE(broker.configured());
  ASSERT_TRUE(broker.start()) << broker.log();
  clock::SystemClock clk;
  mqtt::ClientConfig sc = broker.station_account(1002);
  mqtt::MosquittoClient station(clk, sc);
  station.start();
  mqtt::ClientConfig first = broker.station_account(1001);
  mqtt::MosquittoClient first_station(clk, first);
  first_station.start();

  testing::FakeSimServer server;
  asio::io_context io;
  AppOptions o;
  o.server = "127.0.0.1:" + std::to_string(server.port());
  o.forward = false;  // no --vehicle: watching
  o.follow = "tl";    // station 1002, the second car; the first, "me", is 1001
  o.view = ViewKind::k3d;
  o.width = 480;
  o.height = 270;
  o.mqtt = "127.0.0.1:" + std::to_string(broker.port());
  std::mutex mu;
  std::uint32_t station_shown = 0;
  std::string light;
  o.frame_observer = [&](const view3d::FrameStats& s) {
    std::lock_guard l(mu);
    station_shown = s.signal ? s.signal->station : 0;
    light = s.signal ? std::string(v2x::to_string(s.signal->light)) : std::string();
  };
  ClientApp app(io, o);
  app.start();
  const auto message = [](const char* state) {
    return std::string(R"({"type":"signal","message":{"intersection_id":1,"signal_group":2,)") +
           R"("lane_id":1,"state":")" + state +
           R"(","event_state":"stop-And-Remain","time_to_change_s":5,)"
           R"("likely_time_to_change_s":null,"distance_to_stop_line_m":30.0,"advice":null,)"
           R"("rlvw":false}})";
  };
  bool shown = false;
  for (int i = 0; i < 400 && !shown; ++i) {
    if (i % 5 == 0) {  // both stations on their lanes, every 100 ms
      first_station.publish("its/1001/app/signal", message("red"), mqtt::Qos::kAtMostOnce, false);
      station.publish("its/1002/app/signal", message("green"), mqtt::Qos::kAtMostOnce, false);
    }
    pump(io, 20ms);
    std::lock_guard l(mu);
    shown = station_shown != 0;
  }
  ASSERT_TRUE(shown) << "no signal panel drawn";
  {
    std::lock_guard l(mu);
    EXPECT_EQ(station_shown, 1002u);
    EXPECT_EQ(light, "green");
  }
  app.stop(0);
  station.stop();
  first_station.stop();
}

TEST(SimClientProgram, FollowingAnUnknownCarIsAClearError) {
  // Our own Xvfb: xvfb-run's exit code (5 when its clean-up fails) would hide the program's.
  testing::Xvfb xvfb("640x480x24");
  if (!xvfb.running())
    GTEST_SKIP() << "Xvfb did not start (scripts/install-deps installs xvfb)";
  testing::FakeSimServer server;
  const auto r = run({bin() + "/sim-client", "--server",
                      "127.0.0.1:" + std::to_string(server.port()), "--no-forward", "--view", "3d",
                      "--follow", "ghost", "--width", "320", "--height", "240", "--duration", "20"},
                     40s, {{"ASAN_OPTIONS", "detect_leaks=0"}});
  EXPECT_EQ(r.code, kExitUsage) << r.err;
  EXPECT_NE(r.err.find("--follow ghost: the scenario has no such vehicle (its vehicles: me, tl"),
            std::string::npos)
      << r.err;
}

TEST(ClientApp, MqttSignalPanelAndRedLightBannerComeAndGo) {
  testing::Xvfb xvfb;
  if (!xvfb.running())
    GTEST_SKIP() << "Xvfb did not start (scripts/install-deps installs xvfb)";
  mqtt::testing::Broker broker("1001,1002");
  ASSERT_TRUE(broker.configured());
  ASSERT_TRUE(broker.start()) << broker.log();
  clock::SystemClock clk;
  mqtt::ClientConfig sc = broker.station_account(1001);
  mqtt::MosquittoClient station(clk, sc);
  station.start();

  testing::FakeSimServer server;
  asio::io_context io;
  AppOptions o;
  o.server = "127.0.0.1:" + std::to_string(server.port());
  o.forward = false;
  o.session.vehicles = {"me"};  // station 1001
  o.view = ViewKind::k3d;
  o.width = 480;
  o.height = 270;
  o.mqtt = "127.0.0.1:" + std::to_string(broker.port());
  std::mutex mu;
  std::string light, rlvw;
  o.frame_observer = [&](const view3d::FrameStats& s) {
    std::lock_guard l(mu);
    light = s.signal ? std::string(v2x::to_string(s.signal->light)) : std::string();
    rlvw = s.rlvw_banner;
  };
  ClientApp app(io, o);
  app.start();
  const auto shown = [&](auto publish, auto pred) {
    for (int i = 0; i < 400; ++i) {
      if (i % 5 == 0)
        publish();  // every 100 ms, as the station does while on the lane
      pump(io, 20ms);
      std::lock_guard l(mu);
      if (pred())
        return true;
    }
    return false;
  };
  const std::string signal =
      R"({"type":"signal","message":{"intersection_id":1,"signal_group":2,"lane_id":1,)"
      R"("state":"amber","event_state":"protected-clearance","time_to_change_s":1.5,)"
      R"("likely_time_to_change_s":null,"distance_to_stop_line_m":30.0,"advice":null,)"
      R"("rlvw":true}})";
  const auto publish_signal = [&] {
    station.publish("its/1001/app/signal", signal, mqtt::Qos::kAtMostOnce, false);
  };
  ASSERT_TRUE(shown(publish_signal, [&] { return light == "amber"; })) << "light: " << light;
  const std::string raised =
      R"({"type":"rlvw_warning","message":{"station_id":1001,"intersection_id":1,)"
      R"("signal_group":2,"lane_id":1,"event":"raised","severity":"warning",)"
      R"("distance_to_stop_line_m":30.0,"speed_mps":16.7,"time_to_red_s":1.5,)"
      R"("stopping_distance_m":63.1}})";
  station.publish("its/1001/app/rlvw", raised, mqtt::Qos::kAtLeastOnce, false);
  EXPECT_TRUE(shown(publish_signal, [&] { return rlvw.find("RED LIGHT WARNING") == 0; }))
      << "banner: " << rlvw;
  station.publish("its/1001/app/rlvw",
                  R"({"type":"rlvw_warning","message":{"station_id":1001,"intersection_id":1,)"
                  R"("signal_group":2,"lane_id":1,"event":"cleared","clear_reason":"passed"}})",
                  mqtt::Qos::kAtLeastOnce, false);
  // Still on the lane, but the signal's flag no longer holds the warning.
  const std::string calm =
      R"({"type":"signal","message":{"intersection_id":1,"signal_group":2,"lane_id":1,)"
      R"("state":"red","event_state":"stop-And-Remain","time_to_change_s":20,)"
      R"("distance_to_stop_line_m":-2.0,"advice":null,"rlvw":false}})";
  EXPECT_TRUE(
      shown([&] { station.publish("its/1001/app/signal", calm, mqtt::Qos::kAtMostOnce, false); },
            [&] { return rlvw.empty() && light == "red"; }))
      << "banner: " << rlvw << ", light: " << light;
  station.publish("its/1001/app/signal", R"({"type":"signal","message":{"lane":null}})",
                  mqtt::Qos::kAtLeastOnce, false);
  EXPECT_TRUE(shown([] {}, [&] { return light.empty(); })) << "light: " << light;
  app.stop(0);
  station.stop();
}

}  // namespace
}  // namespace tb::client
