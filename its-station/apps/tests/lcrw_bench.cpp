// Cost of one LCRW evaluation against N neighbours (the station runs it at every own update).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <vector>

#include "common/clock/clock.hpp"
#include "its-station/apps/lcrw/lcrw.hpp"

namespace {

void BM_LcrwEvaluate(benchmark::State& state) {
  using tb::its::apps::VehicleKinematics;
  tb::clock::ManualClock clk;
  tb::its::apps::Lcrw lcrw(clk, {});
  std::vector<VehicleKinematics> n;
  for (int i = 0; i < state.range(0); ++i) {
    VehicleKinematics v;
    v.station_id = static_cast<std::uint32_t>(i + 2);
    v.x = (i % 3 - 1) * 3.5;
    v.y = 20.0 + 7.0 * i;
    v.heading_deg = (i % 2) ? 180.0 : 0.0;
    v.speed_mps = 10.0 + i % 7;
    v.longitudinal_accel_mps2 = 0.5;
    v.time = clk.wall_now();
    n.push_back(v);
  }
  VehicleKinematics own;
  own.station_id = 1;
  own.speed_mps = 20.0;
  own.time = clk.wall_now();
  for (auto _ : state) {
    benchmark::DoNotOptimize(lcrw.evaluate(own, n));
  }
}
double max_of(const std::vector<double>& v) {
  return *std::max_element(v.begin(), v.end());
}

BENCHMARK(BM_LcrwEvaluate)->Arg(1)->Arg(10)->Arg(100)->ComputeStatistics("max", max_of);

}  // namespace

BENCHMARK_MAIN();
