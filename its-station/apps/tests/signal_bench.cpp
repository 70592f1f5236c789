// Cost of the signal application per own fix: lane matching over a four-arm junction (eight
// ingress lanes of eleven nodes), RLVW and GLOSA; and each step alone.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <vector>

#include "common/clock/clock.hpp"
#include "common/geodesy/local_frame.hpp"
#include "its-station/apps/signal/signal_app.hpp"
#include "its-station/apps/tests/signal_fixture.hpp"

namespace {

using namespace tb::its::apps::signal;
using tb::its::apps::signal::testing::four_way_junction;

SignalPhase red_then_green(const tb::clock::Clock& clk, std::uint8_t group) {
  SignalPhase p;
  p.signal_group = group;
  p.current.state = MovementPhaseState::kStopAndRemain;
  p.current.likely_time = clk.wall_now() + std::chrono::seconds{8};
  p.upcoming = {{MovementPhaseState::kProtectedMovementAllowed, std::nullopt, std::nullopt,
                 std::nullopt, clk.wall_now() + std::chrono::seconds{28}}};
  p.received_at = clk.wall_now();
  return p;
}

// The whole per-fix work as the station runs it: geodetic → local frame, lane match on every
// ingress lane, the group's phases, RLVW, GLOSA, the status handed to a sink.
void BM_SignalAppPerFix(benchmark::State& state) {
  tb::clock::ManualClock clk;
  std::size_t statuses = 0;
  SignalAppConfig cfg;
  cfg.status_min_interval = {};
  SignalApplication app(
      clk, cfg, [&](const SignalStatus&) { ++statuses; }, nullptr);
  IntersectionTopology topo = four_way_junction();
  topo.received_at = clk.wall_now();
  (void)app.on_map(topo);
  std::vector<SignalPhase> groups;
  for (std::uint8_t g = 1; g <= 4; ++g) {
    groups.push_back(red_then_green(clk, g));
  }
  app.on_spat(1, groups);
  const tb::geodesy::LocalFrame frame(
      {testing::kJunctionLatitude, testing::kJunctionLongitude, 0.0});
  const tb::geodesy::Geodetic g = frame.to_geodetic({1.75, -90.0, 0.0});
  OwnKinematics own;
  own.station_id = 1001;
  own.latitude_deg = g.latitude_deg;
  own.longitude_deg = g.longitude_deg;
  own.heading_deg = 0.0;
  own.speed_mps = 12.0;
  own.time = clk.wall_now();
  for (auto _ : state) {
    app.update(own);
  }
  benchmark::DoNotOptimize(statuses);
}

void BM_LaneMatch(benchmark::State& state) {
  const IntersectionTopology topo = four_way_junction();
  IngressLaneMatcher m;
  const LocalPose pose{1.75, -90.0, 0.0, 12.0};
  for (auto _ : state) {
    benchmark::DoNotOptimize(m.update(topo, pose));
  }
}

void BM_RlvwAndGlosa(benchmark::State& state) {
  tb::clock::ManualClock clk;
  const SignalPhase p = red_then_green(clk, 1);
  const RlvwConfig rc;
  const GlosaConfig gc;
  for (auto _ : state) {
    const auto timeline = predict_phases(p, clk.wall_now());
    benchmark::DoNotOptimize(assess_rlvw(78.0, 12.0, timeline, rc));
    benchmark::DoNotOptimize(glosa_advice(78.0, std::nullopt, timeline, gc));
  }
}

double max_of(const std::vector<double>& v) {
  return *std::max_element(v.begin(), v.end());
}

BENCHMARK(BM_SignalAppPerFix)->ComputeStatistics("max", max_of);
BENCHMARK(BM_LaneMatch)->ComputeStatistics("max", max_of);
BENCHMARK(BM_RlvwAndGlosa)->ComputeStatistics("max", max_of);

}  // namespace

BENCHMARK_MAIN();
