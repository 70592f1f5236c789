// Cost of one physics step for 1, 10, 100 and 1000 cars on the road mesh, driving (throttle,
// gentle steering), with the wheels cast against the flat ground or against the mesh.

#include <benchmark/benchmark.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <vector>

#include "sim-server/physics/world.hpp"

namespace tb::server::physics {
namespace {

std::unique_ptr<World> make_world(int cars, GroundCast cast) {
  // Four lanes of 5 km: 1000 cars stand 20 m apart.
  scenario::MapSpec map{
      .type = scenario::MapType::kStraight, .lanes = 4, .oncoming_lanes = 0, .length = 5000.0};
  auto w = std::make_unique<World>(map, WorldOptions{.step_s = 0.01, .ground_cast = cast});
  for (int i = 0; i < cars; ++i) {
    const int lane = i % 4;
    const double s = 10.0 + (i / 4) * 20.0;
    w->add_vehicle(scenario::VehicleModel{}, 1000 + i, SpawnPose{s, -1.75 - 3.5 * lane, 0.0, 10.0});
  }
  for (std::size_t i = 0; i < w->size(); ++i)
    w->set_controls(i, {0.3f, 0.0f, (i % 3 == 0) ? 0.02f : -0.01f, false, false}, 0);
  // Settle on the suspension before measuring.
  for (int k = 0; k < 50; ++k)
    w->step();
  return w;
}

double thread_cpu_us() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e6 + ts.tv_nsec * 1e-3;
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * v.size()))];
}

/// Besides Google Benchmark's mean, each step is timed on its own (wall and this thread's CPU
/// time, which other processes on the shared machine do not inflate) for its median and p99.
void BM_PhysicsStep(benchmark::State& state) {
  const auto cast = state.range(1) == 0 ? GroundCast::kFlat : GroundCast::kMesh;
  auto w = make_world(static_cast<int>(state.range(0)), cast);
  std::vector<double> wall, cpu;
  for (auto _ : state) {
    const auto w0 = std::chrono::steady_clock::now();
    const double c0 = thread_cpu_us();
    w->step();
    cpu.push_back(thread_cpu_us() - c0);
    wall.push_back(
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - w0).count());
    benchmark::DoNotOptimize(w->states().data());
  }
  state.counters["wall_p50_us"] = quantile(wall, 0.5);
  state.counters["wall_p99_us"] = quantile(wall, 0.99);
  state.counters["cpu_p50_us"] = quantile(cpu, 0.5);
  state.counters["cpu_p99_us"] = quantile(cpu, 0.99);
  state.counters["cpu_max_us"] = quantile(cpu, 1.0);
}
BENCHMARK(BM_PhysicsStep)
    ->ArgsProduct({{1, 10, 100, 1000}, {0, 1}})
    ->ArgNames({"cars", "mesh_cast"})
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(0.5);

}  // namespace
}  // namespace tb::server::physics

BENCHMARK_MAIN();
