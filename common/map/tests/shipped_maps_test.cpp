// The project's own maps (scenarios/maps, made by generate.py) load into the model, join up
// where their roads meet, and have the junctions and lanes the scenarios on them rely on.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "common/map/opendrive/lane_graph.hpp"
#include "common/map/opendrive/mesh.hpp"
#include "common/map/opendrive/reader.hpp"

namespace tb::map::odr {
namespace {

namespace fs = std::filesystem;

fs::path maps_dir() {
  const char* root = std::getenv("TESTBED_ROOT");
  return fs::path(root != nullptr ? root : ".") / "scenarios" / "maps";
}

// The point where a lane node starts or ends in its direction of travel.
Vertex lane_end(const RoadNetwork& net, const LaneGraph& g, std::size_t node, bool at_exit) {
  const LaneNode& n = g.node(node);
  const auto pts =
      lane_centre(net.roads[static_cast<std::size_t>(n.road)], n.section, n.lane, 0.01);
  return (at_exit == n.forward) ? pts.back() : pts.front();
}

TEST(ShippedMaps, LoadWithoutWarningsAndJoinWhereTheLanesLink) {
  int maps = 0;
  for (const auto& e : fs::directory_iterator(maps_dir())) {
    if (e.path().extension() != ".xodr")
      continue;
    ++maps;
    const RoadNetwork net = load_opendrive(e.path().string());
    EXPECT_TRUE(net.warnings.empty()) << e.path() << ": " << net.warnings.front();
    const LaneGraph g(net);
    std::size_t joins = 0;
    for (std::size_t i = 0; i < g.size(); ++i) {
      for (std::size_t j : g.successors(i)) {
        const Vertex a = lane_end(net, g, i, true);
        const Vertex b = lane_end(net, g, j, false);
        EXPECT_LT(std::hypot(a.x - b.x, a.y - b.y), 0.01)
            << e.path().filename() << ": road " << net.roads[g.node(i).road].id << " lane "
            << g.node(i).lane << " to road " << net.roads[g.node(j).road].id << " lane "
            << g.node(j).lane;
        EXPECT_NEAR(a.z, b.z, 0.01) << e.path().filename();
        ++joins;
      }
    }
    EXPECT_GT(joins, 10u);
  }
  EXPECT_EQ(maps, 2);
}

TEST(ShippedMaps, FourWayJunctionHasEveryTurnAndNoDeadEnd) {
  const RoadNetwork net = load_opendrive((maps_dir() / "four_way_junction.xodr").string());
  ASSERT_EQ(net.junctions.size(), 1u);
  EXPECT_EQ(net.junctions[0].connections.size(), 12u);
  const LaneGraph g(net);
  // Every driving lane leads on: random routes drive for ever.
  for (std::size_t i = 0; i < g.size(); ++i) {
    if (g.node(i).drivable) {
      EXPECT_FALSE(g.successors(i).empty())
          << "road " << net.roads[g.node(i).road].id << " lane " << g.node(i).lane;
    }
  }
  // The loops climb: the map is not flat.
  double top = 0.0;
  for (const Road& r : net.roads)
    top = std::max(top, r.elevation.value(r.length / 2));
  EXPECT_GT(top, 5.0);
}

TEST(ShippedMaps, MotorwayMergeHasAnEndingAccelerationLaneAndNoDeadEnd) {
  const RoadNetwork net = load_opendrive((maps_dir() / "motorway_merge.xodr").string());
  EXPECT_EQ(net.junctions.size(), 2u);
  const LaneGraph g(net);
  int ending = 0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    const LaneNode& n = g.node(i);
    if (!n.drivable || !g.successors(i).empty())
      continue;
    // The only lane that ends is the acceleration lane, beside one that goes on.
    ++ending;
    const Road& r = net.roads[static_cast<std::size_t>(n.road)];
    EXPECT_EQ(r.sections[n.section].lane(n.lane)->type, "entry");
    bool merges = false;
    for (std::size_t nb : g.neighbours(i))
      merges = merges || !g.successors(nb).empty();
    EXPECT_TRUE(merges);
  }
  EXPECT_EQ(ending, 1);
  // From the ramp into the carriageway: a route through the entry and a lane change.
  const auto route = g.route({net.road_index("7"), -1}, 10.0, {net.road_index("3"), -1}, 400.0);
  ASSERT_TRUE(route);
  EXPECT_GE(route->lane_changes, 1u);
}

}  // namespace
}  // namespace tb::map::odr
