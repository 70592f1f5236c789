// Per-update cost of the GNSS path: a vehicle state in, an epoch of NMEA out.
#include <benchmark/benchmark.h>

#include "network-emulator/gnss/gps_agent.hpp"

namespace tb::emu::gnss {
namespace {

void BM_GpsEpoch(benchmark::State& st) {
  const geodesy::LocalFrame frame({48.0, 11.0, 500.0});
  AgentConfig c;
  c.errors.ideal = st.range(0) == 0;
  c.errors.white_noise_m = 1.0;
  c.errors.bias_walk_m = 0.1;
  GpsAgent agent(c, frame);
  wire::VehicleState s;
  s.position = {120.0, 35.0, 0.5};
  s.velocity = {10.0f, 2.0f, 0.0f};
  std::size_t bytes = 0;
  for (auto _ : st) {
    s.sim_time_ns += agent.period_ns();  // every state makes an epoch
    s.position[0] += 1.0;
    const auto out = agent.on_state(s);
    bytes += out->size();
    benchmark::DoNotOptimize(out);
  }
  st.SetBytesProcessed(static_cast<std::int64_t>(bytes));
}
BENCHMARK(BM_GpsEpoch)->Arg(0)->Arg(1)->ArgNames({"noise"});

}  // namespace
}  // namespace tb::emu::gnss

BENCHMARK_MAIN();
