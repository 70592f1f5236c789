// Cost of the traffic lights per physics step (issue 34): SignalSet::step() for the shipped
// four-way junction (one junction, four groups) and for a town of 25 such junctions (the
// town map's size), and the SignalStates encoding the Hub sends on a change.

#include <benchmark/benchmark.h>

#include "common/wire/sim_protocol.hpp"
#include "sim-server/signals/signal_set.hpp"

namespace tb::server {
namespace {

std::vector<scenario::SignalPlan> plans(int junctions) {
  std::vector<scenario::SignalPlan> out;
  for (int j = 0; j < junctions; ++j) {
    scenario::SignalPlan p;
    p.junction = std::to_string(100 + j);
    p.red_amber_s = 1.0;
    p.offset_s = j * 1.7;
    p.phases = {{{1, 3}, 20.0}, {{2, 4}, 20.0}};
    p.groups = {1, 2, 3, 4};
    out.push_back(p);
  }
  return out;
}

void BM_SignalSetStep(benchmark::State& state) {
  SignalSet set(plans(static_cast<int>(state.range(0))), 1'795'000'000'000);
  std::int64_t t = 1'795'000'000'000;
  for (auto _ : state) {
    benchmark::DoNotOptimize(set.step(t));
    t += 10;  // one 100 Hz physics step
  }
}
BENCHMARK(BM_SignalSetStep)->Arg(1)->Arg(25);

void BM_SignalStatesEncode(benchmark::State& state) {
  SignalSet set(plans(static_cast<int>(state.range(0))), 1'795'000'000'000);
  set.step(1'795'000'000'000);
  for (auto _ : state)
    benchmark::DoNotOptimize(wire::sim::encode(set.latest()));
}
BENCHMARK(BM_SignalStatesEncode)->Arg(1)->Arg(25);

}  // namespace
}  // namespace tb::server
BENCHMARK_MAIN();
