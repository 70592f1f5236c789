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

void BM_PublishCam(benchmark::State& state) {
  tb::clock::ManualClock clk;
  NullSink sink;
  mqtt::StationPublisher pub(clk, sink, mqtt::PublisherConfig{"its", 1001, {}});
  mqtt::ReceivedCam c;
  c.station_id = 1002;
  c.kinematics.latitude_deg = 48.1;
  c.kinematics.longitude_deg = 11.5;
  c.kinematics.heading_deg = 90.0;
  c.kinematics.speed_mps = 13.9;
  c.kinematics.length_m = 4.3;
  c.kinematics.width_m = 1.8;
  for (auto _ : state) {
    pub.publish_cam(c);
  }
  benchmark::DoNotOptimize(sink.bytes);
}
BENCHMARK(BM_PublishCam)->ComputeStatistics("max", max_of);

}  // namespace

BENCHMARK_MAIN();
