// Cost of turning an LCRW warning and a received CAM into their MQTT JSON envelopes (done on
// the station's thread for every event) — the broker round trip is measured separately.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <vector>

#include "its-station/apps/mqtt/publisher.hpp"

namespace {

using namespace tb::its::apps;

class NullSink : public tb::mqtt::MqttSink {
 public:
  void publish(std::string_view, std::string payload, tb::mqtt::Qos, bool) override {
    bytes += payload.size();
  }
  std::size_t bytes = 0;
};

double max_of(const std::vector<double>& v) {
  return *std::max_element(v.begin(), v.end());
}

void BM_PublishWarning(benchmark::State& state) {
  tb::clock::ManualClock clk;
  NullSink sink;
  mqtt::StationPublisher pub(clk, sink, mqtt::PublisherConfig{"its", 1001});
  LcrwWarning w;
  w.station_id = 1001;
  w.other_station_id = 1002;
  w.ttc_s = 2.4;
  w.distance_m = 36.0;
  w.relative_speed_mps = 15.0;
  for (auto _ : state) {
    pub.publish_warning(w);
  }
  benchmark::DoNotOptimize(sink.bytes);
}
BENCHMARK(BM_PublishWarning)->ComputeStatistics("max", max_of);

mqtt::ReceivedCam bench_cam() {
  mqtt::ReceivedCam c;
  c.station_id = 1002;
  c.generation_delta_time = 4242;
  c.kinematics.latitude_deg = 48.1;
  c.kinematics.longitude_deg = 11.5;
  c.kinematics.altitude_m = 520.0;
  c.kinematics.heading_deg = 90.0;
  c.kinematics.speed_mps = 13.9;
  c.kinematics.longitudinal_accel_mps2 = 0.4;
  c.kinematics.length_m = 4.3;
  c.kinematics.width_m = 1.8;
  return c;
}

void BM_PublishCam(benchmark::State& state) {
  tb::clock::ManualClock clk;
  NullSink sink;
  mqtt::StationPublisher pub(clk, sink, mqtt::PublisherConfig{"its", 1001, {}});
  const mqtt::ReceivedCam c = bench_cam();
  for (auto _ : state) {
    clk.advance(std::chrono::milliseconds{200});  // past the per-source limit: every CAM is sent
    pub.publish_cam(c);
  }
  benchmark::DoNotOptimize(sink.bytes);
}
BENCHMARK(BM_PublishCam)->ComputeStatistics("max", max_of);

// The received-CAM payload as a JSON tree and as the publisher writes it (issue 21): the same
// text, side by side in one run. The tree's containers have been parsed from the writer's text
// since (one definition); the tree built member by member took 10.9 µs (docs/latency.md).
void BM_CamPayloadTree(benchmark::State& state) {
  const mqtt::ReceivedCam c = bench_cam();
  const tb::clock::WallTime now{std::chrono::milliseconds{1'700'000'000'000}};
  for (auto _ : state) {
    std::string s = mqtt::envelope("cam", "remote", 1001, now, mqtt::cam_message(c)).dump();
    benchmark::DoNotOptimize(s);
  }
}
BENCHMARK(BM_CamPayloadTree)->ComputeStatistics("max", max_of);

void BM_CamPayloadWritten(benchmark::State& state) {
  const mqtt::ReceivedCam c = bench_cam();
  const tb::clock::WallTime now{std::chrono::milliseconds{1'700'000'000'000}};
  for (auto _ : state) {
    std::string s = mqtt::received_cam_payload(1001, now, c);
    benchmark::DoNotOptimize(s);
  }
}
BENCHMARK(BM_CamPayloadWritten)->ComputeStatistics("max", max_of);

}  // namespace

BENCHMARK_MAIN();
