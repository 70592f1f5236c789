// libFuzzer target: the OpenDRIVE importer on arbitrary text. Anything it accepts must evaluate
// without crashing anywhere on its roads, and go through what every program does with a map:
// the lane index and queries on and off its lanes, the lane graph and a route, the surface
// mesh, the traffic lights' index (signal_layout.hpp). Anything it refuses must be a MapError.

#include <cmath>
#include <cstdint>
#include <string_view>

#include "common/map/opendrive/lane_graph.hpp"
#include "common/map/opendrive/mesh.hpp"
#include "common/map/opendrive/reader.hpp"
#include "common/map/opendrive/signal_layout.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tb::map::odr;
  try {
    const RoadNetwork net =
        parse_opendrive(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz");
    double total = 0.0;
    for (const Road& r : net.roads) {
      total += r.length;
      for (int i = 0; i <= 4; ++i) {
        const double s = r.length * i / 4.0;
        (void)r.surface(s, 1.0);
        (void)r.borders(r.section_index(s), s);
        (void)r.curvature(s);
      }
    }
    // The reader's caps bound the index and the mesh; keep each input's time to the fuzzer's
    // budget all the same (a few km of road is plenty of geometry to break things with).
    if (total > 5000.0)
      return 0;
    const LaneLocator locator(net);
    for (const Road& r : net.roads) {
      for (double f : {0.0, 0.3, 1.0}) {
        const double s = r.length * f;
        const SurfacePose p = r.surface(s, 0.0);
        for (double t : {-7.0, -1.5, 0.0, 1.5, 7.0}) {
          const double x = p.x - t * std::sin(p.heading), y = p.y + t * std::cos(p.heading);
          (void)locator.locate(x, y);
          (void)locator.locate(x, y, p.z + t);
          (void)locator.locate_all(x, y);
        }
      }
    }
    (void)locator.locate(1e9, -1e9);
    (void)locator.locate(NAN, 0.0);
    const LaneGraph graph(net);
    if (graph.size() >= 2) {
      const LaneNode& a = graph.node(0);
      const LaneNode& b = graph.node(graph.size() - 1);
      try {
        (void)graph.route({a.road, a.lane}, 0.0, {b.road, b.lane},
                          net.roads[static_cast<std::size_t>(b.road)].length);
      } catch (const MapError&) {
      }
    }
    (void)road_mesh(net, 0.05);
    // The traffic lights' index, and every lane's query on it.
    const SignalLayout signals(net);
    for (std::size_t i = 0; i < graph.size(); ++i)
      (void)signals.approach(graph.node(i).road, graph.node(i).lane);
  } catch (const MapError&) {
  }
  return 0;
}
