// A full station's own CPU at 49 neighbours without its sockets (issue 33): one Station with
// LCRW and the MQTT mirror (into a sink that only counts) takes the CAMs of 49 others driving on
// a ring, and its own fix, every 100 ms of the world. The time per round ×10 is the stack's ms of
// CPU per station-second; what the system calls add (radio, gpsd, MQTT) is not in it.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "common/clock/gnss_disciplined_runtime.hpp"
#include "common/clock/runtime.hpp"
#include "common/geodesy/local_frame.hpp"
#include "common/mqtt/sink.hpp"
#include "its-station/link/test_link.hpp"
#include "its-station/station/station.hpp"

namespace {

using namespace tb;
using namespace tb::its;
using namespace std::chrono_literals;

const geodesy::Geodetic kOrigin{48.1351, 11.5820, 0.0};
constexpr double kRingRadius = 150.0;
constexpr double kSpeed = 15.0;  // the CA rules send about 3 CAMs a second (4 m moved)

link::MacAddress mac_of(std::uint32_t id) {
  return {0x02,
          0x00,
          static_cast<std::uint8_t>(id >> 24),
          static_cast<std::uint8_t>(id >> 16),
          static_cast<std::uint8_t>(id >> 8),
          static_cast<std::uint8_t>(id)};
}

class CountingSink final : public mqtt::MqttSink {
 public:
  void publish(std::string_view, std::string payload, mqtt::Qos, bool) override {
    ++messages;
    bytes += payload.size();
  }
  std::uint64_t messages = 0;
  std::uint64_t bytes = 0;
};

struct RingStation {
  RingStation(clock::ManualRuntime& host, std::uint32_t id, double phase, mqtt::MqttSink* sink)
      : its_clock(host), link(mac_of(id)), phase_rad(phase) {
    vehicle.id = "v" + std::to_string(id);
    vehicle.station_id = id;
    station = std::make_unique<station::Station>(
        station::StationPorts{host, its_clock, gnss, nullptr, link, nullptr, sink},
        station::make_station_config(id, nullptr, &vehicle, station::StationOverrides{}));
    station->start();
  }
  /// The fix on the ring at @p t_s seconds, counter-clockwise at kSpeed.
  void fix(const clock::ManualRuntime& host, double t_s) {
    const double a = phase_rad + kSpeed * t_s / kRingRadius;
    const auto g = geodesy::LocalFrame(kOrigin).to_geodetic(
        {kRingRadius * std::cos(a), kRingRadius * std::sin(a), 0.0});
    facilities::PositionFix f;
    f.time = host.wall_now();
    f.received = host.steady_now();
    f.latitude_deg = g.latitude_deg;
    f.longitude_deg = g.longitude_deg;
    f.speed_mps = kSpeed;
    // Counter-clockwise: the course is the radius' angle plus 90°, in ETSI degrees from north.
    const double math_deg = std::fmod(a * 180.0 / std::numbers::pi + 90.0, 360.0);
    f.course_deg = std::fmod(360.0 + 90.0 - math_deg, 360.0);
    f.heading_deg = f.course_deg;
    f.position_confidence = facilities::PositionFix::Ellipse{2.0, 2.0, 0.0};
    f.speed_confidence_mps = 0.1;
    f.heading_confidence_deg = 1.0;
    gnss.inject(f);
  }

  scenario::Vehicle vehicle;
  clock::GnssDisciplinedRuntime its_clock;
  facilities::InjectedPositionProvider gnss;
  link::TestLink link;
  double phase_rad;
  std::unique_ptr<station::Station> station;
};

/// One station with LCRW and the MQTT mirror and 49 others on the ring, every neighbour in its
/// LDM after two seconds of the world.
class Ring {
 public:
  static constexpr int kOthers = 49;
  Ring() : own(host, 1000, 0.0, &sink) {
    for (int i = 1; i <= kOthers; ++i)
      others.push_back(std::make_unique<RingStation>(
          host, 1000 + i, 2 * std::numbers::pi * i / (kOthers + 1), nullptr));
    for (int i = 0; i < 20; ++i) {
      round();
      feed_own();
    }
    sink.messages = 0;
  }
  /// 100 ms of the world: the others' fixes and the CAMs they send.
  void round() {
    host.advance(100ms);
    t_s += 0.1;
    air.clear();
    for (auto& o : others) {
      o->fix(host, t_s);
      for (auto& f : o->link.sent())
        air.push_back({o->link.address(), std::move(f)});
      o->link.sent().clear();
    }
  }
  /// The own station's fix of this round, and the CAMs of the round received.
  void feed_own() {
    own.fix(host, t_s);
    for (const auto& [source, f] : air)
      own.link.inject(source, f.destination, f.ethertype, f.payload, host.wall_now());
    own.link.sent().clear();
  }

  struct OnAir {
    link::MacAddress source;
    link::TestLink::SentFrame frame;
  };
  clock::ManualRuntime host;
  CountingSink sink;
  RingStation own;
  std::vector<std::unique_ptr<RingStation>> others;
  double t_s = 0.0;
  std::vector<OnAir> air;
};

void BM_StationAt49Neighbours(benchmark::State& state) {
  Ring ring;
  std::uint64_t cams = 0;
  for (auto _ : state) {
    state.PauseTiming();
    ring.round();
    state.ResumeTiming();
    ring.feed_own();
    cams += ring.air.size();
  }
  state.counters["cams_per_round"] =
      benchmark::Counter(static_cast<double>(cams) / static_cast<double>(state.iterations()));
  state.counters["neighbours"] = static_cast<double>(ring.own.station->ldm().neighbours().size());
  state.counters["mqtt_per_round"] = benchmark::Counter(static_cast<double>(ring.sink.messages),
                                                        benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_StationAt49Neighbours)->Unit(benchmark::kMicrosecond);

// What its-station's status file costs in user space each time it is written (every 0.5 s):
// Station::status() at 49 neighbours and its JSON text, without the file's system calls.
void BM_StatusAt49Neighbours(benchmark::State& state) {
  Ring ring;
  std::size_t bytes = 0;
  for (auto _ : state) {
    const std::string text = ring.own.station->status().dump();
    bytes = text.size();
    benchmark::DoNotOptimize(text.data());
  }
  state.counters["bytes"] = static_cast<double>(bytes);
  state.counters["neighbours"] = static_cast<double>(ring.own.station->ldm().neighbours().size());
}
BENCHMARK(BM_StatusAt49Neighbours)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
