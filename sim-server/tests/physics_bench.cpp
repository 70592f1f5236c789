// Cost of one physics step for 1, 10, 100 and 1000 cars on the road mesh, driving (throttle,
// gentle steering), with the wheels cast against the flat ground or against the mesh; and for
// 100 cars on junctions with elevation (issue 17): simple_4way_intersection.xodr tiled 3 x 3
// with every road lifted onto rolling terrain (elevation and superelevation following it).

#include <benchmark/benchmark.h>
#include <time.h>

#include <pugixml.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <vector>

#include "common/map/opendrive/reader.hpp"
#include "common/map/opendrive/tests/shared_maps.hpp"
#include "common/map/opendrive/tests/stitch.hpp"
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
/// Rolling terrain: up to 7 m high, slopes up to about 12 %.
double terrain(double x, double y) {
  return 4.0 * std::sin(x / 60.0) + 3.0 * std::cos(y / 45.0);
}

/// A cubic over [s0, s0 + len] through values v0, v1 with slopes m0, m1 (Hermite).
map::odr::CubicRecord hermite(double s0, double len, double v0, double v1, double m0, double m1) {
  const double dv = (v1 - v0) / len;
  return {s0, v0, m0, (3.0 * dv - 2.0 * m0 - m1) / len, (m0 + m1 - 2.0 * dv) / (len * len)};
}

/// Lifts every road onto the terrain: elevation = terrain under the reference line, and a
/// superelevation that follows the terrain's slope across the road, so that roads meeting in a
/// junction meet at the same height.
void lift(map::odr::RoadNetwork& net) {
  constexpr double kStep = 10.0, kH = 0.01;
  for (auto& road : net.roads) {
    std::vector<map::odr::CubicRecord> elevation, superelevation;
    const int n = std::max(1, static_cast<int>(std::ceil(road.length / kStep)));
    auto sample = [&](double s, double& z, double& dz, double& roll, double& droll) {
      auto at = [&](double q, double& h, double& across) {
        const auto p = road.reference(std::clamp(q, 0.0, road.length));
        h = terrain(p.x, p.y);
        const double nx = -std::sin(p.hdg), ny = std::cos(p.hdg);
        across = std::atan((terrain(p.x + kH * nx, p.y + kH * ny) - h) / kH);
      };
      double h0, h1, a0, a1;
      at(s, z, roll);
      at(s - kH, h0, a0);
      at(s + kH, h1, a1);
      dz = (h1 - h0) / (2 * kH);
      droll = (a1 - a0) / (2 * kH);
    };
    for (int i = 0; i < n; ++i) {
      const double s0 = road.length * i / n, s1 = road.length * (i + 1) / n;
      double z0, dz0, r0, dr0, z1, dz1, r1, dr1;
      sample(s0, z0, dz0, r0, dr0);
      sample(s1, z1, dz1, r1, dr1);
      elevation.push_back(hermite(s0, s1 - s0, z0, z1, dz0, dz1));
      superelevation.push_back(hermite(s0, s1 - s0, r0, r1, dr0, dr1));
    }
    road.elevation = map::odr::CubicProfile(std::move(elevation));
    road.superelevation = map::odr::CubicProfile(std::move(superelevation));
  }
}

std::shared_ptr<const map::ScenarioMap> hilly_junctions() {
  pugi::xml_document in;
  in.load_file((map::odr::test::shared_maps() / "simple_4way_intersection.xodr").c_str());
  pugi::xml_document out;
  pugi::xml_node root = out.append_child("OpenDRIVE");
  pugi::xml_node header = root.append_child("header");
  header.append_attribute("revMajor") = 1;
  header.append_attribute("revMinor") = 6;
  // The junction's arms end 112.5 m from its centre: tiles 225 m apart meet arm to arm.
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      map::odr::test::append_copy(root, in, std::to_string(i) + std::to_string(j) + "_", 225.0 * i,
                                  225.0 * j);
    }
  }
  std::ostringstream text;
  out.save(text);
  auto net = map::odr::parse_opendrive(text.str(), "hilly junctions");
  lift(net);
  return std::make_shared<const map::ScenarioMap>(
      std::make_shared<const map::odr::RoadNetwork>(std::move(net)),
      geodesy::Geodetic{48.0, 11.0, 500.0});
}

/// 100 cars on the arms (not in the junctions) of the tiled map, driving straight on at 10 m/s
/// with some throttle; settled on their springs.
std::unique_ptr<World> make_junction_world(int cars) {
  auto w = std::make_unique<World>(hilly_junctions(), WorldOptions{.step_s = 0.01});
  const auto& net = w->map().network();
  for (double s : {15.0, 55.0, 85.0, 35.0}) {
    for (const auto& road : net.roads) {
      if (road.junction != "-1")
        continue;
      for (int lane : {-1, 1}) {
        if (static_cast<int>(w->size()) >= cars)
          break;
        scenario::Spawn spawn;
        spawn.where = scenario::RoadSpawn{road.id, lane, s, 0.0, false};
        spawn.speed = 10.0;
        w->add_vehicle(scenario::VehicleModel{}, 1000 + static_cast<std::uint32_t>(w->size()),
                       spawn_pose(w->map(), spawn));
      }
    }
  }
  for (std::size_t i = 0; i < w->size(); ++i)
    w->set_controls(i, {0.2f, 0.0f, 0.0f, false, false}, 0);
  for (int k = 0; k < 50; ++k)
    w->step();
  return w;
}

void BM_PhysicsStepJunctionsWithElevation(benchmark::State& state) {
  auto w = make_junction_world(static_cast<int>(state.range(0)));
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
  state.counters["cars"] = static_cast<double>(w->size());
  state.counters["triangles"] = static_cast<double>(w->ground_triangles());
  state.counters["off_road"] = static_cast<double>(w->off_road().departures());
  state.counters["wall_p50_us"] = quantile(wall, 0.5);
  state.counters["wall_p99_us"] = quantile(wall, 0.99);
  state.counters["cpu_p50_us"] = quantile(cpu, 0.5);
  state.counters["cpu_p99_us"] = quantile(cpu, 0.99);
  state.counters["cpu_max_us"] = quantile(cpu, 1.0);
}
BENCHMARK(BM_PhysicsStepJunctionsWithElevation)
    ->Arg(100)
    ->ArgName("cars")
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(0.5);

BENCHMARK(BM_PhysicsStep)
    ->ArgsProduct({{1, 10, 100, 1000}, {0, 1}})
    ->ArgNames({"cars", "mesh_cast"})
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(0.5);

}  // namespace
}  // namespace tb::server::physics

BENCHMARK_MAIN();
