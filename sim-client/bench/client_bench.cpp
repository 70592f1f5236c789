// Speed of the client's per-tick work: one state frame in (decode, forward, scripted driver,
// controls out), the lane-following driver alone, one frame of the view, and a signal message
// from MQTT to what the HUD's panel shows (issue 34).
#include <benchmark/benchmark.h>

#include "common/map/builtin_network.hpp"
#include "sim-client/driver/scripted_driver.hpp"
#include "sim-client/net/session.hpp"
#include "sim-client/net/tests/fake_server.hpp"
#include "sim-client/v2x/monitor.hpp"
#include "sim-client/v2x/signal_panel.hpp"
#include "sim-client/view/scene.hpp"

namespace tb::client {
namespace {

class NullSink final : public DatagramSink {
 public:
  bool send(std::span<const std::uint8_t> d) override {
    benchmark::DoNotOptimize(d.data());
    return true;
  }
};

// A state frame with 3 vehicles, all driven by this client (one human, two scripted).
void BM_StateFrameToControlsAndForward(benchmark::State& st) {
  clock::SystemClock clk;
  NullSink sink;
  trace::Tracer off;
  StateForwarder fwd(clk, sink, off);
  std::size_t out = 0;
  SessionOptions o;
  o.vehicles = {"me"};
  o.scripted = true;
  SimSession s(
      o, [&](std::vector<std::uint8_t> b) { out += b.size(); }, &fwd, off);
  s.on_connected();
  s.on_bytes(wire::sim::encode(testing::welcome()));
  for (std::uint16_t i = 0; i < 3; ++i) {
    s.on_bytes(wire::sim::encode(
        wire::sim::AttachResult{wire::sim::Role::kDriver, i, wire::sim::AttachStatus::kOk, ""}));
  }
  std::vector<std::vector<std::uint8_t>> frames;
  for (std::uint64_t t = 1; t <= 1000; ++t)
    frames.push_back(wire::sim::encode(testing::frame(t)));
  std::size_t i = 0;
  for (auto _ : st) {
    s.on_bytes(frames[i++ % frames.size()]);
  }
  benchmark::DoNotOptimize(out);
  st.counters["datagrams"] = static_cast<double>(fwd.sent());
}
BENCHMARK(BM_StateFrameToControlsAndForward);

// One state forwarded through a real UDP socket on loopback (the syscall included).
void BM_ForwardStateUdp(benchmark::State& st) {
  boost::asio::io_context io;
  boost::asio::ip::udp::socket rx(io, {boost::asio::ip::address_v4::loopback(), 0});
  UdpSink sink(io, "127.0.0.1:" + std::to_string(rx.local_endpoint().port()));
  clock::SystemClock clk;
  trace::Tracer off;
  StateForwarder fwd(clk, sink, off);
  const wire::VehicleState s = testing::frame(1).vehicles[0];
  for (auto _ : st)
    fwd.forward(s);
  st.counters["failed"] = static_cast<double>(fwd.failed());
}
BENCHMARK(BM_ForwardStateUdp);

void BM_LaneFollowUpdate(benchmark::State& st) {
  scenario::MapSpec spec;
  spec.type = scenario::MapType::kRing;
  const DriveMap map(std::make_shared<const map::ScenarioMap>(spec, std::nullopt));
  scenario::LaneFollowDriver d;
  d.profile = {{0, 10}, {100, 15}};
  const map::LaneStart start{0, -1, 10.0, false};
  LaneFollowDriver driver(d, scenario::VehicleModel{}, map,
                          map::RoutePlan(map.network(), map.graph(), d.route, start, 1));
  wire::VehicleState s;
  const auto p = map::odr::lane_pose(map.network(), 0, -1, 10.0);
  s.position = {p.x, p.y, 0};
  s.yaw = static_cast<float>(p.heading);
  s.speed = 10.0f;
  for (auto _ : st) {
    s.sim_time_ns += 10'000'000;
    benchmark::DoNotOptimize(driver.update(s));
  }
}
BENCHMARK(BM_LaneFollowUpdate);

// One frame of the 1024×768 view drawn with SDL's software renderer (the slowest renderer;
// a window uses the GPU one when there is one).
void BM_ViewFrameSoftware(benchmark::State& st) {
  auto canvas = Canvas::offscreen(1024, 768);
  scenario::MapSpec spec;
  spec.type = scenario::MapType::kStraight;
  spec.length = 2000;
  const map::odr::RoadNetwork road = map::generate_network(spec);
  ViewScene scene;
  scene.network = &road;
  for (int i = 0; i < 8; ++i) {
    ViewVehicle v;
    v.state.station_id = 1001 + i;
    v.state.position = {100.0 + 12.0 * i, i % 2 ? 1.75 : -1.75, 0};
    v.state.yaw = i % 2 ? 3.14159f : 0.0f;
    v.own = i == 0;
    scene.vehicles.push_back(v);
  }
  scene.connection = "connected to 127.0.0.1:2000";
  scene.input = "keyboard";
  SceneRenderer r(canvas->renderer(), 1024, 768);
  for (auto _ : st) {
    r.draw(scene);
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_ViewFrameSoftware)->Unit(benchmark::kMicrosecond);

// One `its/<id>/app/signal` message (the contract's payload, as a station publishes it) parsed
// and checked, then the picture and the panel the render thread makes of it.
void BM_SignalMessageToPanel(benchmark::State& st) {
  v2x::V2xMonitor m;
  const std::string payload =
      R"({"type":"signal","origin":"on_board_application","version":"1.0.0",)"
      R"("source_uuid":"its-station-1001","timestamp":1795000000000,"message":)"
      R"({"intersection_id":1,"signal_group":2,"lane_id":1,"state":"amber",)"
      R"("event_state":"protected-clearance","time_to_change_s":2.5,)"
      R"("likely_time_to_change_s":2.5,"distance_to_stop_line_m":38.4,)"
      R"("advice":{"min_speed_kmh":28.0,"max_speed_kmh":45.5},"rlvw":true}})";
  clock::SteadyTime now{std::chrono::seconds{100}};
  for (auto _ : st) {
    now += std::chrono::milliseconds{100};
    benchmark::DoNotOptimize(m.on_message("its/1001/app/signal", payload, now));
    const auto panel = v2x::signal_panel(m.picture(now), 1001);
    benchmark::DoNotOptimize(panel);
  }
}
BENCHMARK(BM_SignalMessageToPanel);

}  // namespace
}  // namespace tb::client

BENCHMARK_MAIN();
