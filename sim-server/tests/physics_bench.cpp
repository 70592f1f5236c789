// Cost of one physics step for 1, 10, 100 and 1000 cars on the road mesh, driving (throttle,
// gentle steering), with the wheels cast against the flat ground or against the mesh.

#include <benchmark/benchmark.h>

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

void BM_PhysicsStep(benchmark::State& state) {
  const auto cast = state.range(1) == 0 ? GroundCast::kFlat : GroundCast::kMesh;
  auto w = make_world(static_cast<int>(state.range(0)), cast);
  for (auto _ : state) {
    w->step();
    benchmark::DoNotOptimize(w->states().data());
  }
  state.counters["cars"] = static_cast<double>(state.range(0));
}
BENCHMARK(BM_PhysicsStep)
    ->ArgsProduct({{1, 10, 100, 1000}, {0, 1}})
    ->ArgNames({"cars", "mesh_cast"})
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(0.5);

}  // namespace
}  // namespace tb::server::physics

BENCHMARK_MAIN();
