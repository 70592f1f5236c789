// The host's receive fan-out: one CAM frame read from the air and handed to N pooled stations,
// each a complete stack (GN router and location table, BTP, CA service, LDM), as station-host
// runs them. ns per station per frame times the frames a station hears per second (N in range
// × their CAM rate) is the CPU a pooled station costs per second for receiving.

#include <benchmark/benchmark.h>
#include <spdlog/spdlog.h>

#include <memory>
#include <vector>

#include "common/clock/gnss_disciplined_runtime.hpp"
#include "common/clock/runtime.hpp"
#include "common/geodesy/local_frame.hpp"
#include "its-station/station/station.hpp"
#include "station-host/link/pooled_links.hpp"

namespace {

using namespace std::chrono_literals;
namespace station = tb::its::station;
namespace facilities = tb::its::facilities;

const tb::geodesy::Geodetic kOrigin{48.1351, 11.5820, 0.0};

struct Capture final : tb::host::FrameOutput {
  std::vector<std::vector<std::uint8_t>> frames;
  bool keep = true;
  std::error_code send_frame(std::span<const std::uint8_t> f) override {
    if (keep)
      frames.emplace_back(f.begin(), f.end());
    return {};
  }
};

/// One pooled station over a host's links, fed fixes by hand.
struct Pooled {
  Pooled(tb::clock::ManualRuntime& rt, tb::host::PooledLinks& links, std::uint32_t id)
      : its_clock(rt),
        station(
            station::StationPorts{rt, its_clock, gnss, nullptr, links.link(id), nullptr, nullptr},
            make_config(id)) {
    station.start();
  }
  static station::StationConfig make_config(std::uint32_t id) {
    tb::scenario::Vehicle v;
    v.id = "v" + std::to_string(id);
    v.station_id = id;
    // A pooled vehicle's defaults: no LCRW, no MQTT mirror.
    v.station_kind = tb::scenario::StationKind::kPooled;
    v.station_lcrw = false;
    v.station_mqtt = false;
    return station::make_station_config(id, nullptr, &v, station::StationOverrides{});
  }
  void fix(const tb::clock::ManualRuntime& rt, double east, double north, double course_deg,
           double speed) {
    const auto g = tb::geodesy::LocalFrame(kOrigin).to_geodetic({east, north, 0.0});
    facilities::PositionFix f;
    f.time = rt.wall_now();
    f.received = rt.steady_now();
    f.latitude_deg = g.latitude_deg;
    f.longitude_deg = g.longitude_deg;
    f.speed_mps = speed;
    f.course_deg = course_deg;
    f.heading_deg = course_deg;
    f.position_confidence = facilities::PositionFix::Ellipse{2.0, 2.0, 0.0};
    f.speed_confidence_mps = 0.1;
    f.heading_confidence_deg = 1.0;
    gnss.inject(f);
  }
  tb::clock::GnssDisciplinedRuntime its_clock;
  facilities::InjectedPositionProvider gnss;
  station::Station station;
};

void BM_ReceiveFanOut(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  spdlog::set_level(spdlog::level::warn);  // hundreds of stations say when their fix came
  tb::clock::ManualRuntime rt;
  Capture host_out;
  host_out.keep = false;
  tb::host::PooledLinks host(host_out, rt, false, {});
  std::vector<std::unique_ptr<Pooled>> receivers;
  for (std::size_t i = 0; i < n; ++i)
    receivers.push_back(std::make_unique<Pooled>(rt, host, 3000 + static_cast<std::uint32_t>(i)));

  // CAMs of 16 other stations on a ring road, 10 Hz for 2 s: distinct senders and positions,
  // as a station hears them.
  Capture air_out;
  tb::host::PooledLinks air(air_out, rt, false, {});
  std::vector<std::unique_ptr<Pooled>> senders;
  for (std::uint32_t i = 0; i < 16; ++i)
    senders.push_back(std::make_unique<Pooled>(rt, air, 9000 + i));
  for (int k = 0; k < 20; ++k) {
    for (std::size_t i = 0; i < receivers.size(); ++i)
      receivers[i]->fix(rt, 3.0 * static_cast<double>(i % 100), 4.0 * static_cast<double>(i / 100),
                        90.0, 0.0);
    for (std::size_t i = 0; i < senders.size(); ++i)
      // Course changes > 4° each 100 ms: a CAM every fix (EN 302 637-2, 6.1.3).
      senders[i]->fix(rt, 10.0 * static_cast<double>(i), 20.0, std::fmod(5.0 * k, 360.0), 15.0);
    rt.advance(100ms);
  }
  if (air_out.frames.empty()) {
    state.SkipWithError("the senders sent no CAM");
    return;
  }
  std::size_t k = 0;
  for (auto _ : state) {
    host.on_frame(air_out.frames[k], rt.wall_now());
    k = (k + 1) % air_out.frames.size();
  }
  const auto received = receivers.front()->station.ca().counters().received;
  if (received == 0)
    state.SkipWithError("the receivers took no CAM in");
  // Seconds of CPU per (frame × receiving station), shown with an SI prefix (e.g. 1.5u).
  state.counters["per_station_frame"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate |
                                                     benchmark::Counter::kInvert);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * n));
  state.counters["cams_taken_in"] = static_cast<double>(received);
  state.counters["frames"] = static_cast<double>(air_out.frames.size());
}
BENCHMARK(BM_ReceiveFanOut)->Arg(30)->Arg(300)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
