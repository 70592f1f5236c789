// The project's own maps (scenarios/maps, made by generate.py) load into the model, join up
// where their roads meet, and have the junctions and lanes the scenarios on them rely on.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <numbers>
#include <string>

#include "common/map/opendrive/lane_graph.hpp"
#include "common/map/opendrive/mesh.hpp"
#include "common/map/opendrive/queries.hpp"
#include "common/map/opendrive/reader.hpp"
#include "common/map/opendrive/road_objects.hpp"
#include "common/map/opendrive/signal_layout.hpp"

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
  EXPECT_EQ(maps, 3);
}

/// Each stop line (DE 294) lies across a drivable lane that runs towards the junction at the
/// road's near end, within 6 m of it, and spans that lane's width; returns how many.
int check_stop_lines(const RoadNetwork& net) {
  int lines = 0;
  for (const Road& r : net.roads) {
    for (const RoadSignal& g : r.signals) {
      if (!is_stop_line(g))
        continue;
      ++lines;
      SCOPED_TRACE("road " + r.id + " signal " + g.id);
      const std::size_t k = r.section_index(g.s);
      const int lane = lane_of(r, k, g.s, g.t);
      EXPECT_NE(lane, 0);
      if (lane == 0)
        continue;
      const Lane* l = r.sections[k].lane(lane);
      EXPECT_TRUE(l->drivable);
      // "-": for traffic against s, which reaches the start; "+": the end.
      const bool to_start = g.orientation == "-";
      EXPECT_EQ(r.forward(lane), !to_start);
      const auto& link = to_start ? r.predecessor : r.successor;
      EXPECT_TRUE(link.has_value() && link->to_junction);
      EXPECT_LT(to_start ? g.s : r.length - g.s, 6.0);
      const LaneBorders b = r.borders(k, g.s);
      EXPECT_NEAR(g.width, std::fabs(b.outer(lane) - b.inner(lane)), 0.01);
      EXPECT_NEAR(g.t, (b.outer(lane) + b.inner(lane)) / 2, 0.01);
    }
  }
  return lines;
}

TEST(ShippedMaps, FourWayJunctionHasAStopLineAndACrossingOnEveryArm) {
  const RoadNetwork net = load_opendrive((maps_dir() / "four_way_junction.xodr").string());
  EXPECT_EQ(check_stop_lines(net), 4);  // one per arm, on the lane towards the junction
  int crossings = 0;
  for (const Road& r : net.roads)
    for (const RoadObject& o : r.objects)
      crossings += o.type == "crosswalk" ? 1 : 0;
  EXPECT_EQ(crossings, 4);
}

TEST(ShippedMaps, TownIsTownSizedWithObjectsAlongItsStreets) {
  const RoadNetwork net = load_opendrive((maps_dir() / "town.xodr").string());
  // 5 x 5 junctions: 40 streets; 9 crossroads x 12 + 12 T-junctions x 6 + 4 corners x 2
  // connecting roads = 188.
  EXPECT_EQ(net.junctions.size(), 25u);
  EXPECT_EQ(net.roads.size(), 40u + 188u);
  const LaneGraph g(net);
  for (std::size_t i = 0; i < g.size(); ++i) {
    if (g.node(i).drivable) {
      EXPECT_FALSE(g.successors(i).empty()) << "road " << net.roads[g.node(i).road].id;
    }
  }
  // Per street (generate_town.py): two lamp rows, two crossings, two stop lines, two speed
  // limits; one tree row on every street but the park's, which has six trees and a hedge.
  std::map<std::string, int> objects, signals;
  for (const Road& r : net.roads) {
    for (const RoadObject& o : r.objects)
      ++objects[o.type];
    for (const RoadSignal& s : r.signals)
      ++signals[s.type];
  }
  EXPECT_EQ(objects["pole"], 80);
  EXPECT_EQ(objects["crosswalk"], 80);
  EXPECT_EQ(objects["tree"], 39 + 6);
  EXPECT_EQ(objects["vegetation"], 1);
  EXPECT_GT(objects["building"], 200);
  EXPECT_EQ(signals["274"], 80);
  EXPECT_EQ(check_stop_lines(net), 80);
  // No house stands on a lane: its centre is on no road.
  const LaneLocator where(net);
  for (const Road& r : net.roads) {
    for (const RoadObject& o : r.objects) {
      if (o.type != "building")
        continue;
      for (const PlacedObject& p : place_object(r, o))
        EXPECT_FALSE(where.locate(p.pose.x, p.pose.y).has_value()) << "house " << o.id;
    }
  }
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

/// generate.py's four-way junction: arm k (1..4) starts 12 m from the centre at angle
/// (k - 1) * 90 degrees and runs outwards, rising 3 m over 68 m (level at both ends); lane 1
/// (3.5 m) runs towards the junction on the arm's left.
struct ArmFrame {
  double phi;
  /// The point @p s along the arm and @p t left of its reference line, in the map.
  double x(double s, double t) const { return (12.0 + s) * std::cos(phi) - t * std::sin(phi); }
  double y(double s, double t) const { return (12.0 + s) * std::sin(phi) + t * std::cos(phi); }
  static double z(double s) {
    const double f = s / 68.0;
    return 3.0 * (3 * f * f - 2 * f * f * f);
  }
};

double angle_diff(double a, double b) {
  return std::remainder(a - b, 2 * std::numbers::pi);
}

TEST(ShippedMaps, FourWayJunctionHasALightPerArmRunByItsOwnSignalGroup) {
  const RoadNetwork net = load_opendrive((maps_dir() / "four_way_junction.xodr").string());
  const SignalLayout layout(net);
  ASSERT_EQ(layout.junctions().size(), 1u);
  EXPECT_EQ(layout.junctions()[0].intersection_id, 100);
  EXPECT_EQ(layout.junctions()[0].groups, (std::vector<int>{1, 2, 3, 4}));
  ASSERT_EQ(layout.heads().size(), 4u);
  ASSERT_EQ(layout.groups().size(), 4u);
  for (int arm = 1; arm <= 4; ++arm) {
    SCOPED_TRACE("arm " + std::to_string(arm));
    const ArmFrame f{(arm - 1) * std::numbers::pi / 2};
    const int road = net.road_index(std::to_string(arm));
    // One light, in the middle of the 2 m sidewalk beside lane 1, level with the stop line
    // (4.5 m into the arm), its lower edge 2.1 m above the road, facing the traffic that
    // comes towards the junction (heading: the arm's own turned round).
    const SignalGroup* g = layout.group(arm);
    ASSERT_NE(g, nullptr);
    ASSERT_EQ(g->heads.size(), 1u);
    const SignalHead& h = layout.heads()[g->heads[0]];
    EXPECT_EQ(h.road, road);
    EXPECT_EQ(h.signal->type, "1000001");
    EXPECT_EQ(h.orientation, "-");
    ASSERT_EQ(h.validity.size(), 1u);
    EXPECT_EQ(h.validity[0].from, 1);
    EXPECT_EQ(h.validity[0].to, 1);
    EXPECT_NEAR(h.pose.x, f.x(4.5, 4.5), 1e-9);
    EXPECT_NEAR(h.pose.y, f.y(4.5, 4.5), 1e-9);
    EXPECT_NEAR(h.pose.z, ArmFrame::z(4.5) + 2.1, 1e-9);
    EXPECT_NEAR(angle_diff(h.pose.heading, f.phi + std::numbers::pi), 0.0, 1e-9);
    EXPECT_EQ(h.height, 0.9);
    // The lane towards the junction stops at the stop line, on its centre; the lane away from
    // it has no light.
    const SignalApproach* a = layout.approach(road, 1);
    ASSERT_NE(a, nullptr);
    EXPECT_EQ(a->signal_group, arm);
    EXPECT_EQ(a->intersection_id, 100);
    EXPECT_EQ(net.junctions[a->junction].id, "100");
    EXPECT_TRUE(a->has_stop_line);
    EXPECT_DOUBLE_EQ(a->stop_s, 4.5);
    EXPECT_NEAR(a->stop.x, f.x(4.5, 1.75), 1e-9);
    EXPECT_NEAR(a->stop.y, f.y(4.5, 1.75), 1e-9);
    EXPECT_NEAR(a->stop.z, ArmFrame::z(4.5), 1e-9);
    EXPECT_NEAR(angle_diff(a->stop.heading, f.phi + std::numbers::pi), 0.0, 1e-9);
    EXPECT_EQ(layout.approach(road, -1), nullptr);
  }
  EXPECT_EQ(layout.approaches().size(), 4u);
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
