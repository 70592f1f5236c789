// Per-update cost of the CAN path: a vehicle state in, the due frames out.
#include <benchmark/benchmark.h>

#include "network-emulator/can/can_feeder.hpp"

namespace tb::emu::can {
namespace {

void BM_CanUpdate(benchmark::State& st) {
  const auto db = tb::can::Database::load(TESTBED_VEHICLE_DBC);
  auto feeder = CanFeeder::create(*db, {});
  wire::VehicleState s;
  s.speed = 13.0f;
  s.wheel_speeds = {13.0f, 13.1f, 12.9f, 13.0f};
  std::size_t frames = 0;
  for (auto _ : st) {
    s.sim_time_ns += 10'000'000;  // 100 Hz states: 5 dynamics frames, a body frame every 10th
    frames += feeder->on_state(s).size();
    benchmark::DoNotOptimize(frames);
  }
  st.counters["frames/update"] = static_cast<double>(frames) / static_cast<double>(st.iterations());
}
BENCHMARK(BM_CanUpdate);

}  // namespace
}  // namespace tb::emu::can

BENCHMARK_MAIN();
