// Range culling (issue 33): the medium's work per frame with 1000 stations of which about 100
// are within range of each sender, deciding every pair (before) or only the stations the grid
// finds within range (after). Stations on a ring, as tests/e2e/gen_scale_scenario.py places
// them: for radius R and range r the share within range is 2·asin(r/2R)/π, 0.1 here.
// Results in README.md ("Range culling").

#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "network-emulator/radio/medium.hpp"

namespace tb::emu::radio {
namespace {

constexpr int kStations = 1000;
constexpr double kRangeM = 300.0;
// 2·asin(r/2R)/π = 0.1  ⇒  R = r / (2·sin(0.05π)).
const double kRingM = kRangeM / (2.0 * std::sin(0.05 * std::numbers::pi));

struct CountingSink final : FrameSink {
  void transmit(std::span<const std::uint8_t>) override { ++frames; }
  std::uint64_t frames = 0;
};

std::array<double, 3> on_ring(int i, double turn = 0.0) {
  const double a = 2.0 * std::numbers::pi * i / kStations + turn;
  return {kRingM * std::cos(a), kRingM * std::sin(a), 0.0};
}

void BM_FramePerSender(benchmark::State& state) {
  const bool grid = state.range(0) != 0;
  clock::ManualRuntime rt;
  PositionTable positions;
  scenario::ChannelModel model;
  model.kind = scenario::ChannelModel::Kind::kRange;
  model.range_m = kRangeM;
  Channel channel(model, positions, 1);
  if (grid)
    positions.index_cells(*channel.max_range_m());
  Medium medium(rt, channel);
  medium.set_culling(grid);
  std::vector<CountingSink> sinks(kStations);
  for (int i = 0; i < kStations; ++i) {
    positions.set(static_cast<StationId>(i), {on_ring(i), 0});
    medium.attach(static_cast<StationId>(i), sinks[static_cast<std::size_t>(i)]);
  }
  const std::vector<std::uint8_t> frame(120, 0x47);
  // Every link once before timing: the per-link counters exist, as in a run under way.
  for (int i = 0; i < kStations; ++i)
    medium.on_frame(static_cast<StationId>(i), frame);
  const std::uint64_t sent_before = channel.totals().sent;
  const std::uint64_t delivered_before = medium.deliveries();
  int from = 0;
  for (auto _ : state) {
    medium.on_frame(static_cast<StationId>(from), frame);
    from = from + 1 == kStations ? 0 : from + 1;
  }
  const auto frames = static_cast<double>(state.iterations());
  state.counters["decisions_per_frame"] =
      static_cast<double>(channel.totals().sent - sent_before) / frames;
  state.counters["deliveries_per_frame"] =
      static_cast<double>(medium.deliveries() - delivered_before) / frames;
  state.SetLabel(grid ? "grid" : "all pairs");
}
BENCHMARK(BM_FramePerSender)->ArgName("grid")->Arg(0)->Arg(1);

// What the grid costs where positions arrive: 1000 states (one tick of every vehicle), each
// moving its station by a little, some across a cell border.
void BM_PositionTick(benchmark::State& state) {
  const bool grid = state.range(0) != 0;
  PositionTable positions;
  if (grid)
    positions.index_cells(kRangeM);
  wire::VehicleState s;
  std::int64_t t = 0;
  double turn = 0.0;
  for (auto _ : state) {
    ++t;
    turn += 1e-4;  // about 0.6 m per tick on the ring
    for (int i = 0; i < kStations; ++i) {
      s.station_id = static_cast<StationId>(i);
      s.sim_time_ns = t;
      s.position = on_ring(i, turn);
      positions.update(s);
    }
  }
  state.SetLabel(grid ? "grid" : "table only");
}
BENCHMARK(BM_PositionTick)->ArgName("grid")->Arg(0)->Arg(1);

}  // namespace
}  // namespace tb::emu::radio

BENCHMARK_MAIN();
