// Figures of issue 17: load + mesh of a large map (>= 2 MB, >= 250 roads), lane query from (x, y).
// The large map is stitched from the shared esmini maps: each file copied side by side on a
// 5 km grid with its ids prefixed, until both sizes are reached.

#include <benchmark/benchmark.h>

#include <pugixml.hpp>

#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "common/map/opendrive/mesh.hpp"
#include "common/map/opendrive/reader.hpp"
#include "common/map/opendrive/terrain.hpp"
#include "common/map/opendrive/tests/shared_maps.hpp"
#include "common/map/opendrive/tests/stitch.hpp"

namespace {

using namespace tb::map::odr;
namespace fs = std::filesystem;

std::string stitched_map() {
  static const std::string text = [] {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(tb::map::odr::test::shared_maps())) {
      if (e.path().extension() == ".xodr")
        files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    pugi::xml_document out;
    pugi::xml_node root = out.append_child("OpenDRIVE");
    pugi::xml_node header = root.append_child("header");
    header.append_attribute("revMajor") = 1;
    header.append_attribute("revMinor") = 6;
    std::size_t roads = 0;
    std::string result;
    for (int copy = 0; roads < 250 || result.size() < 2'000'000; ++copy) {
      for (std::size_t f = 0; f < files.size(); ++f) {
        pugi::xml_document in;
        in.load_file(files[f].c_str());
        const std::string p = std::to_string(copy) + "_" + std::to_string(f) + "_";
        roads += tb::map::odr::test::append_copy(root, in, p, 5000.0 * static_cast<double>(f),
                                                 5000.0 * copy);
      }
      std::ostringstream s;
      out.save(s, "  ");
      result = s.str();
    }
    return result;
  }();
  return text;
}

void BM_LoadAndMesh(benchmark::State& state) {
  const std::string text = stitched_map();
  std::size_t triangles = 0;
  std::size_t roads = 0;
  for (auto _ : state) {
    const RoadNetwork net = parse_opendrive(text, "stitched");
    const RoadMesh mesh = road_mesh(net, 0.02);
    triangles = mesh.triangles();
    roads = net.roads.size();
    benchmark::DoNotOptimize(mesh.vertices.data());
  }
  state.counters["bytes"] = static_cast<double>(text.size());
  state.counters["roads"] = static_cast<double>(roads);
  state.counters["triangles"] = static_cast<double>(triangles);
}
BENCHMARK(BM_LoadAndMesh)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);

void BM_BuildLaneIndex(benchmark::State& state) {
  const RoadNetwork net = parse_opendrive(stitched_map(), "stitched");
  for (auto _ : state) {
    LaneLocator loc(net);
    benchmark::DoNotOptimize(loc.pieces());
  }
}
BENCHMARK(BM_BuildLaneIndex)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);

void BM_LocateLane(benchmark::State& state) {
  static const RoadNetwork net = parse_opendrive(stitched_map(), "stitched");
  static const LaneLocator loc(net);
  // Points on random lanes at random s and offsets, fixed seed.
  std::vector<std::pair<double, double>> points;
  std::mt19937 rng(17);
  while (points.size() < 4096) {
    const int r = static_cast<int>(rng() % net.roads.size());
    const Road& road = net.roads[static_cast<std::size_t>(r)];
    const double s = std::uniform_real_distribution<double>(0, road.length)(rng);
    const LaneSection& ls = road.sections[road.section_index(s)];
    const bool left = !ls.left.empty() && (ls.right.empty() || rng() % 2 == 0);
    const auto& side = left ? ls.left : ls.right;
    const Lane& lane = side[rng() % side.size()];
    const SurfacePose p = lane_pose(net, r, lane.id, s, 0.0);
    points.emplace_back(p.x, p.y);
  }
  std::size_t i = 0;
  std::size_t hits = 0;
  for (auto _ : state) {
    const auto& [x, y] = points[i++ & 4095];
    const auto at = loc.locate(x, y);
    hits += at.has_value();
    benchmark::DoNotOptimize(at);
  }
  state.counters["hit_rate"] = static_cast<double>(hits) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_LocateLane)->Unit(benchmark::kNanosecond)->Repetitions(10)->ReportAggregatesOnly(true);

/// The terrain (terrain.hpp) from a road mesh at the physics' 2 cm: grid, pinning, solve.
/// Arguments: 0 the shipped four-way junction, 1 the shipped motorway merge, 2 the shared map
/// with the largest extent (e6mini-lht, 0.6 x 1.9 km with the margin), 3 the stitched map
/// (its copies 5 km apart: the cell grows to keep within max_nodes).
void BM_Terrain(benchmark::State& state) {
  static const std::vector<RoadMesh> meshes = [] {
    const fs::path shipped = TB_SHIPPED_MAPS_DIR;
    std::vector<RoadMesh> out;
    for (const fs::path& p : {shipped / "four_way_junction.xodr", shipped / "motorway_merge.xodr",
                              tb::map::odr::test::shared_maps() / "e6mini-lht.xodr"})
      out.push_back(road_mesh(load_opendrive(p.string()), 0.02));
    out.push_back(road_mesh(parse_opendrive(stitched_map(), "stitched"), 0.02));
    return out;
  }();
  const RoadMesh& mesh = meshes[static_cast<std::size_t>(state.range(0))];
  std::size_t nodes = 0;
  double cell = 0.0;
  for (auto _ : state) {
    const Terrain t(mesh);
    nodes = t.columns() * t.rows();
    cell = t.cell();
    benchmark::DoNotOptimize(t.node(0, 0));
  }
  state.counters["road_triangles"] = static_cast<double>(mesh.triangles());
  state.counters["nodes"] = static_cast<double>(nodes);
  state.counters["cell_m"] = cell;
  // Heights (8 B) and the pinned flags (1 B) per node; the build's peak adds a copy of each.
  state.counters["MB"] = static_cast<double>(nodes) * 9.0 / 1e6;
}
BENCHMARK(BM_Terrain)
    ->DenseRange(0, 3)
    ->Unit(benchmark::kMillisecond)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true);

}  // namespace

BENCHMARK_MAIN();
