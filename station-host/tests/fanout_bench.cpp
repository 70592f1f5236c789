// The host's receive fan-out: one CAM frame read from the air and handed to N pooled stations,
// each a complete stack (GN router and location table, BTP, CA service, LDM), as station-host
// runs them. ns per station per frame times the frames a station hears per second (N in range
// × their CAM rate) is the CPU a pooled station costs per second for receiving.

#include <benchmark/benchmark.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "common/clock/gnss_disciplined_runtime.hpp"
#include "common/clock/runtime.hpp"
#include "common/geodesy/local_frame.hpp"
#include "its-station/security/pki.hpp"
#include "its-station/security/security_entity.hpp"
#include "its-station/security/time.hpp"
#include "its-station/station/station.hpp"
#include "station-host/feed/state_feed.hpp"
#include "station-host/link/pooled_links.hpp"

namespace {

using namespace std::chrono_literals;
namespace station = tb::its::station;
namespace facilities = tb::its::facilities;
namespace geonet = tb::its::geonet;

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
  Pooled(tb::clock::ManualRuntime& rt, tb::host::PooledLinks& links, std::uint32_t id,
         std::unique_ptr<tb::its::security::SecurityEntity> sec = nullptr)
      : its_clock(rt),
        security(std::move(sec)),
        station(station::StationPorts{rt, its_clock, gnss, nullptr, links.link(id), security.get(),
                                      nullptr},
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
  std::unique_ptr<tb::its::security::SecurityEntity> security;
  station::Station station;
};

/// A root, an AA and an AT per station, valid around @p now: the scenario's test PKI.
class BenchPki {
 public:
  explicit BenchPki(tb::clock::WallTime now) : now_(now) {
    namespace sec = tb::its::security;
    start_ = sec::to_time32(now) - 3600;
    root_ = sec::make_root(root_key_, "root", {start_, sec::DurationUnit::kHours, 100});
    aa_ = sec::make_authority(aa_key_, "aa", {start_, sec::DurationUnit::kHours, 100}, root_,
                              root_key_);
  }
  std::unique_ptr<tb::its::security::SecurityEntity> entity() {
    namespace sec = tb::its::security;
    sec::EcKey k = sec::EcKey::generate(sec::EccCurve::kNistP256);
    sec::Certificate at =
        sec::make_ticket(k, {start_, sec::DurationUnit::kHours, 10}, aa_, aa_key_);
    sec::Verifier v({root_});
    v.add_authority(aa_, sec::to_time64(now_));
    return std::make_unique<sec::SecurityEntity>(
        sec::SecurityMode::kSigned, sec::Signer(std::move(at), std::move(k), aa_), std::move(v));
  }

 private:
  tb::clock::WallTime now_;
  tb::its::security::Time32 start_ = 0;
  tb::its::security::EcKey root_key_ =
      tb::its::security::EcKey::generate(tb::its::security::EccCurve::kNistP256);
  tb::its::security::EcKey aa_key_ =
      tb::its::security::EcKey::generate(tb::its::security::EccCurve::kNistP256);
  tb::its::security::Certificate root_, aa_;
};

void BM_ReceiveFanOut(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const bool signed_mode = state.range(1) != 0;
  spdlog::set_level(spdlog::level::warn);  // hundreds of stations say when their fix came
  tb::clock::ManualRuntime rt;
  std::optional<BenchPki> pki;
  if (signed_mode)
    pki.emplace(rt.wall_now());
  auto entity = [&] { return pki ? pki->entity() : nullptr; };
  Capture host_out;
  host_out.keep = false;
  tb::host::PooledLinks host(host_out, rt, false, {});
  // One decoded CAM per frame for all the host's stations, as station-host's main shares it.
  facilities::SharedCamDecoder cam_decoder;
  geonet::SharedPacketParser packet_parser;
  std::vector<std::unique_ptr<Pooled>> receivers;
  for (std::size_t i = 0; i < n; ++i) {
    receivers.push_back(
        std::make_unique<Pooled>(rt, host, 3000 + static_cast<std::uint32_t>(i), entity()));
    receivers.back()->station.share_cam_decoder(cam_decoder);
    receivers.back()->station.share_packet_parser(packet_parser);
  }

  // CAMs of 16 other stations on a ring road, 10 Hz for 2 s: distinct senders and positions,
  // as a station hears them.
  Capture air_out;
  tb::host::PooledLinks air(air_out, rt, false, {});
  std::vector<std::unique_ptr<Pooled>> senders;
  for (std::uint32_t i = 0; i < 16; ++i)
    senders.push_back(std::make_unique<Pooled>(rt, air, 9000 + i, entity()));
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
// {stations, signed}. Signed: every station verifies every CAM (no verification on demand);
// frames heard again after the first round are verified too (the verifier checks the signature
// before it looks for replays) and then dropped as replays.
BENCHMARK(BM_ReceiveFanOut)
    ->Args({30, 0})
    ->Args({300, 0})
    ->Args({30, 1})
    ->Unit(benchmark::kMicrosecond);

/// The rest of a pooled station's second: its states (100 Hz physics) through the GPS agent and
/// FixAssembler at 10 Hz, the CA service's generation and the CAMs it sends, for N stations
/// driving a ring at 14 m/s (a CAM every ~0.3 s by the 4 m rule). No reception: see above.
void BM_StationSecondWithoutReception(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  spdlog::set_level(spdlog::level::warn);
  tb::clock::ManualRuntime rt;
  Capture out;
  out.keep = false;
  tb::host::PooledLinks links(out, rt, false, {});
  tb::scenario::Scenario scenario;
  scenario.name = "bench";
  for (std::size_t i = 0; i < n; ++i) {
    tb::scenario::Vehicle v;
    v.id = "v" + std::to_string(i);
    v.station_id = 3000 + static_cast<std::uint32_t>(i);
    v.station_kind = tb::scenario::StationKind::kPooled;
    v.station_lcrw = false;
    v.station_mqtt = false;
    scenario.vehicles.push_back(v);
  }
  const tb::geodesy::LocalFrame frame(kOrigin);
  tb::host::StateFeed feed(scenario, frame, rt, 1);
  std::vector<std::unique_ptr<tb::clock::GnssDisciplinedRuntime>> clocks;
  std::vector<std::unique_ptr<station::Station>> stations;
  for (const auto& v : scenario.vehicles) {
    auto& src = feed.add(v.station_id);
    clocks.push_back(std::make_unique<tb::clock::GnssDisciplinedRuntime>(rt));
    stations.push_back(std::make_unique<station::Station>(
        station::StationPorts{rt, *clocks.back(), *src.gnss, src.vehicle.get(),
                              links.link(v.station_id), nullptr, nullptr},
        station::make_station_config(v.station_id, nullptr, &v, station::StationOverrides{})));
    stations.back()->start();
  }
  const std::int64_t world_start = tb::clock::to_unix_ns(rt.wall_now());
  std::vector<tb::wire::VehicleState> batch(n);
  std::vector<std::uint8_t> bytes;
  std::int64_t tick = 0;
  auto step = [&] {
    const double t = static_cast<double>(tick) * 0.01;
    for (std::size_t i = 0; i < n; ++i) {
      // Each on its own 200 m circle, 14 m/s.
      const double a = 14.0 * t / 200.0 + static_cast<double>(i);
      auto& s = batch[i];
      s.station_id = 3000 + static_cast<std::uint32_t>(i);
      s.tick = static_cast<std::uint64_t>(tick);
      s.sim_time_ns = tick * 10'000'000;
      s.position = {200.0 * std::cos(a), 200.0 * std::sin(a), 0.0};
      s.velocity = {static_cast<float>(-14.0 * std::sin(a)), static_cast<float>(14.0 * std::cos(a)),
                    0.0f};
      s.yaw = static_cast<float>(a + 1.5707963);
      s.speed = 14.0f;
      s.gear = 1;
    }
    // Datagrams as the emulator forwards them: at most an Ethernet MTU each (9 states).
    const std::size_t per = tb::wire::states_per_batch(tb::wire::kDefaultBatchDatagramSize);
    for (std::size_t first = 0; first < n; first += per) {
      const auto count = std::min(per, n - first);
      bytes.resize(tb::wire::batch_datagram_size(count));
      tb::wire::encode_batch(std::span(batch).subspan(first, count), bytes, world_start);
      feed.handle_datagram(bytes);
    }
    rt.advance(10ms);
    ++tick;
  };
  for (int k = 0; k < 300; ++k)  // warm up: fixes, first CAMs
    step();
  if (feed.counters().states == 0 || links.counters().sent == 0) {
    state.SkipWithError("no states taken in or no CAM sent");
    return;
  }
  const auto sent_before = links.counters().sent;
  std::int64_t seconds = 0;
  for (auto _ : state) {
    for (int k = 0; k < 100; ++k)
      step();
    ++seconds;
  }
  state.counters["per_station_second"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate |
                                                     benchmark::Counter::kInvert);
  state.counters["cams_per_station_second"] =
      static_cast<double>(links.counters().sent - sent_before) /
      (static_cast<double>(seconds) * static_cast<double>(n));
}
BENCHMARK(BM_StationSecondWithoutReception)->Arg(300)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
