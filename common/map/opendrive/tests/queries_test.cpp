// Lane positions to poses and back through the spatial index, the lane graph and routes.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <tuple>

#include "common/map/opendrive/lane_graph.hpp"
#include "common/map/opendrive/queries.hpp"
#include "common/map/opendrive/reader.hpp"
#include "common/map/opendrive/tests/shared_maps.hpp"

namespace tb::map::odr {
namespace {

namespace fs = std::filesystem;

using test::shared_maps;

TEST(LanePose, StraightRoadWithOffsetAndElevation) {
  const RoadNetwork net = parse_opendrive(
      R"(<OpenDRIVE><road id="r" length="100" junction="-1">
      <planView><geometry s="0" x="10" y="20" hdg="1.5707963267948966" length="100"><line/></geometry></planView>
      <elevationProfile><elevation s="0" a="5" b="0.1"/></elevationProfile>
      <lateralProfile><superelevation s="0" a="0.1"/></lateralProfile>
      <lanes><laneOffset s="0" a="0.5"/><laneSection s="0">
        <left><lane id="1" type="driving"><width sOffset="0" a="3"/></lane></left>
        <right><lane id="-1" type="driving"><width sOffset="0" a="3.5"/></lane><lane id="-2" type="shoulder"><width sOffset="0" a="2"/></lane></right>
      </laneSection></lanes></road></OpenDRIVE>)",
      "t.xodr");
  // Road runs north; lane -1's centre is 0.5 - 1.75 = -1.25 m left, i.e. 1.25 m east.
  const SurfacePose p = lane_pose(net, 0, -1, 30, 0);
  EXPECT_NEAR(p.x, 10 + 1.25, 1e-9);
  EXPECT_NEAR(p.y, 50, 1e-9);
  EXPECT_NEAR(p.z, 5 + 3 - 1.25 * std::tan(0.1), 1e-9);
  EXPECT_NEAR(p.heading, M_PI / 2, 1e-9);
  EXPECT_NEAR(p.pitch, std::atan(0.1), 1e-12);
  EXPECT_NEAR(p.roll, 0.1, 1e-12);
  const SurfacePose q = lane_pose(net, 0, -2, 30, 0.5);  // centre -4.0, half a metre left
  EXPECT_NEAR(q.x, 10 + 3.5, 1e-9);

  LaneLocator loc(net);
  const auto at = loc.locate(10 + 4.0, 50);
  ASSERT_TRUE(at);
  EXPECT_EQ(at->ref, (LaneRef{0, -2}));
  EXPECT_NEAR(at->s, 30, 1e-9);
  EXPECT_NEAR(at->t, -4.0, 1e-9);
  EXPECT_FALSE(loc.locate(10 + 6.6, 50));  // beyond the shoulder
  EXPECT_FALSE(loc.locate(10, 19));        // before the road
  EXPECT_FALSE(loc.locate(NAN, 19));
  EXPECT_EQ(loc.locate(10 - 2, 50)->ref, (LaneRef{0, 1}));
}

TEST(LanePose, NamedErrorsForPositionsThatDoNotExist) {
  const RoadNetwork net =
      load_opendrive((shared_maps() / "simple_4way_intersection.xodr").string());
  const int r0 = net.road_index("0");
  auto message = [&](int road, int lane, double s) {
    try {
      (void)lane_pose(net, road, lane, s);
    } catch (const MapError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(r0, -1, 100.5).find("road[@id='0']: s 100.5"), std::string::npos);
  EXPECT_NE(message(r0, -3, 10).find("road[@id='0']: lane -3 does not exist"), std::string::npos);
  EXPECT_NE(message(99, -1, 10).find("road does not exist"), std::string::npos);
}

TEST(LaneLocator, RoundTripsEveryLaneOfEverySharedMapWithinACentimetre) {
  int checked = 0;
  for (const auto& e : fs::directory_iterator(shared_maps())) {
    if (e.path().extension() != ".xodr")
      continue;
    const RoadNetwork net = load_opendrive(e.path().string());
    const LaneLocator loc(net);
    for (std::size_t ri = 0; ri < net.roads.size(); ++ri) {
      const Road& r = net.roads[ri];
      for (std::size_t k = 0; k < r.sections.size(); ++k) {
        const LaneSection& ls = r.sections[k];
        for (const auto* side : {&ls.left, &ls.right}) {
          for (const Lane& lane : *side) {
            for (double f : {0.1, 0.5, 0.9}) {
              const double s = ls.s + f * (ls.s_end - ls.s);
              const LaneBorders b = r.borders(k, s);
              if (std::fabs(b.outer(lane.id) - b.inner(lane.id)) < 0.2)
                continue;
              for (double frac : {0.0, 0.3, -0.3}) {
                const double offset = frac * std::fabs(b.outer(lane.id) - b.inner(lane.id));
                const SurfacePose p = lane_pose(net, static_cast<int>(ri), lane.id, s, offset);
                const LaneRef want{static_cast<int>(ri), lane.id};
                const auto got = loc.locate(p.x, p.y, p.z, std::span<const LaneRef>(&want, 1));
                ASSERT_TRUE(got) << e.path().filename() << " road " << r.id << " lane " << lane.id
                                 << " s " << s;
                EXPECT_EQ(got->ref, want) << e.path().filename() << " road " << r.id << " s " << s;
                const SurfacePose back = r.surface(got->s, got->t);
                EXPECT_LT(std::hypot(back.x - p.x, back.y - p.y), 0.01);
                EXPECT_NEAR(got->s, s, 0.01) << e.path().filename() << " road " << r.id;
                ++checked;
              }
            }
          }
        }
      }
    }
  }
  EXPECT_GT(checked, 1000);
}

TEST(LaneLocator, HeightPicksTheRoadOnABridge) {
  const RoadNetwork net = parse_opendrive(
      R"(<OpenDRIVE>
      <road id="low" length="100" junction="-1"><planView><geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry></planView>
        <lanes><laneSection s="0"><right><lane id="-1" type="driving"><width sOffset="0" a="4"/></lane></right></laneSection></lanes></road>
      <road id="high" length="100" junction="-1"><planView><geometry s="0" x="50" y="-50" hdg="1.5707963267948966" length="100"><line/></geometry></planView>
        <elevationProfile><elevation s="0" a="8"/></elevationProfile>
        <lanes><laneSection s="0"><left><lane id="1" type="driving"><width sOffset="0" a="4"/></lane></left></laneSection></lanes></road>
      </OpenDRIVE>)",
      "bridge.xodr");
  const LaneLocator loc(net);
  EXPECT_EQ(loc.locate_all(48, -2).size(), 2u);
  EXPECT_EQ(loc.locate(48, -2, 0.3)->ref.road, 0);
  EXPECT_EQ(loc.locate(48, -2, 8.2)->ref.road, 1);
  const LaneRef high{1, 1};
  EXPECT_EQ(loc.locate(48, -2, std::nullopt, std::span<const LaneRef>(&high, 1))->ref.road, 1);
}

using Edge = std::tuple<std::string, int, std::string, int>;  // road, lane -> road, lane

TEST(LaneGraph, FourWayIntersectionHasExactlyTheFilesConnections) {
  const RoadNetwork net =
      load_opendrive((shared_maps() / "simple_4way_intersection.xodr").string());
  const LaneGraph g(net);
  // Expected: every laneLink of every connection, as an unordered pair of lanes.
  std::set<std::pair<std::pair<std::string, int>, std::pair<std::string, int>>> expected;
  for (const Connection& c : net.junctions.at(0).connections) {
    for (const LaneLink& ll : c.lane_links) {
      auto a = std::make_pair(c.incoming, ll.from);
      auto b = std::make_pair(c.connecting, ll.to);
      expected.insert({std::min(a, b), std::max(a, b)});
    }
  }
  ASSERT_EQ(expected.size(), 24u);
  std::set<std::pair<std::pair<std::string, int>, std::pair<std::string, int>>> actual;
  std::size_t edges = 0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    const LaneNode& n = g.node(i);
    const Road& from = net.roads[static_cast<std::size_t>(n.road)];
    for (std::size_t j : g.successors(i)) {
      const LaneNode& m = g.node(j);
      const Road& to = net.roads[static_cast<std::size_t>(m.road)];
      if ((from.junction == "-1") == (to.junction == "-1"))
        continue;  // not across the border
      ++edges;
      auto a = std::make_pair(from.id, n.lane);
      auto b = std::make_pair(to.id, m.lane);
      actual.insert({std::min(a, b), std::max(a, b)});
      // Direction: the lane's exit meets the next lane's entry (within 1 cm), so the edge
      // runs the way traffic does.
      const double exit_s = n.forward ? from.length : 0.0;
      const double entry_s = m.forward ? 0.0 : to.length;
      const SurfacePose p = lane_pose(net, n.road, n.lane, exit_s);
      const SurfacePose q = lane_pose(net, m.road, m.lane, entry_s);
      EXPECT_LT(std::hypot(p.x - q.x, p.y - q.y), 0.01)
          << from.id << ":" << n.lane << " -> " << to.id << ":" << m.lane;
    }
  }
  EXPECT_EQ(edges, 24u);
  EXPECT_EQ(actual, expected);
}

TEST(LaneGraph, RouteThroughTheJunctionAndLaneChanges) {
  const RoadNetwork net =
      load_opendrive((shared_maps() / "simple_4way_intersection.xodr").string());
  const LaneGraph g(net);
  const int r0 = net.road_index("0");
  const int r2 = net.road_index("2");
  const auto route = g.route({r0, -1}, 50, {r2, -1}, 30);
  ASSERT_TRUE(route);
  ASSERT_EQ(route->nodes.size(), 3u);
  const LaneNode& via = g.node(route->nodes[1]);
  const Road& conn = net.roads[static_cast<std::size_t>(via.road)];
  EXPECT_EQ(conn.junction, "1");
  // The connecting road taken is one whose connection leads from road 0 to road 2.
  EXPECT_TRUE((conn.predecessor && conn.predecessor->id == "0" && conn.successor->id == "2") ||
              (conn.successor && conn.successor->id == "0" && conn.predecessor->id == "2"));
  EXPECT_NEAR(route->length, 50 + conn.length + 30, 1e-9);
  // Against the direction of travel there is no way from lane -1 to a point behind it.
  EXPECT_FALSE(g.route({r0, -1}, 50, {r0, -1}, 20));
  EXPECT_NEAR(g.route({r0, -1}, 20, {r0, -1}, 50)->length, 30, 1e-9);

  const RoadNetwork hw = load_opendrive((shared_maps() / "highway_merge.xodr").string());
  const LaneGraph hg(hw);
  const int in0 = hw.road_index("0");
  const auto lc = hg.find(in0, -1, 10);
  ASSERT_TRUE(lc);
  ASSERT_EQ(hg.neighbours(*lc).size(), 1u);
  EXPECT_EQ(hg.node(hg.neighbours(*lc)[0]).lane, -2);
  const auto r = hg.route({in0, -1}, 10, {in0, -2}, 90);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->lane_changes, 1u);
  EXPECT_NEAR(r->length, 80, 1e-9);
}

}  // namespace
}  // namespace tb::map::odr

namespace tb::map::odr {
namespace {

std::string spawn_error(const RoadNetwork& net, const LaneSpawn& s) {
  try {
    (void)spawn_pose(net, s);
  } catch (const MapError& e) {
    return e.what();
  }
  return "no error";
}

TEST(SpawnPose, FacesTheLanesDirectionOfTravel) {
  const RoadNetwork net =
      load_opendrive((shared_maps() / "simple_4way_intersection.xodr").string());
  const SurfacePose right = spawn_pose(net, {"0", -1, 30, 0});
  EXPECT_NEAR(right.x, 30, 1e-9);
  EXPECT_NEAR(right.y, -1.5, 1e-9);
  EXPECT_NEAR(right.heading, 0, 1e-9);
  const SurfacePose left = spawn_pose(net, {"0", 1, 30, 0});
  EXPECT_NEAR(left.y, 1.5, 1e-9);
  EXPECT_NEAR(std::fabs(left.heading), M_PI, 1e-9);
}

TEST(SpawnPose, NamedErrors) {
  const RoadNetwork net =
      load_opendrive((shared_maps() / "simple_4way_intersection.xodr").string());
  EXPECT_NE(spawn_error(net, {"12", -1, 30, 0}).find("road[@id='12']: road does not exist"),
            std::string::npos);
  EXPECT_NE(spawn_error(net, {"0", -1, 130, 0}).find("road[@id='0']: s 130 past the road's end"),
            std::string::npos);
  EXPECT_NE(spawn_error(net, {"0", -2, 30, 0}).find("road[@id='0']: lane -2 does not exist"),
            std::string::npos);
  const RoadNetwork tw = parse_opendrive(
      R"(<OpenDRIVE><road id="r" length="100" junction="-1">
      <planView><geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry></planView>
      <lanes><laneSection s="0"><right>
        <lane id="-1" type="driving"><width sOffset="0" a="0" b="0.05"/></lane>
        <lane id="-2" type="sidewalk"><width sOffset="0" a="2"/></lane>
      </right></laneSection></lanes></road></OpenDRIVE>)",
      "w.xodr");
  EXPECT_NE(spawn_error(tw, {"r", -1, 10, 0})
                .find("lane -1 (driving, 0.5 m wide) is not drivable at s 10"),
            std::string::npos);
  EXPECT_NO_THROW(spawn_pose(tw, {"r", -1, 60, 0}));
  EXPECT_NE(spawn_error(tw, {"r", -2, 60, 0}).find("lane -2 (sidewalk"), std::string::npos);
}

}  // namespace
}  // namespace tb::map::odr
