// Route plans on the lane graph: start lanes, random successors (reproducible), lists of roads,
// goals, and a named error for every route the network cannot give.

#include "common/map/route_plan.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <set>

#include "common/map/builtin_network.hpp"
#include "common/map/opendrive/reader.hpp"
#include "common/map/opendrive/tests/shared_maps.hpp"

namespace tb::map {
namespace {

using Kind = scenario::DriveRoute::Kind;

odr::RoadNetwork four_way() {
  return odr::load_opendrive((odr::test::shared_maps() / "simple_4way_intersection.xodr").string());
}

scenario::MapSpec builtin(scenario::MapType type, int lanes, int oncoming) {
  scenario::MapSpec s;
  s.type = type;
  s.lanes = lanes;
  s.oncoming_lanes = oncoming;
  s.length = 500;
  s.radius = 100;
  s.arm_length = 150;
  return s;
}

scenario::DriveRoute route_of(Kind kind, std::vector<std::string> roads = {}) {
  scenario::DriveRoute r;
  r.kind = kind;
  r.roads = std::move(roads);
  return r;
}

LaneStart start_at(const odr::RoadNetwork& net, const std::string& road, int lane, double s) {
  return LaneStart{net.road_index(road), lane, s, false};
}

// Every step of a plan is an edge of the graph: a successor, or a neighbour when it says so.
std::vector<PlanStep> drive(RoutePlan& plan, const odr::LaneGraph& g, std::size_t limit) {
  std::vector<PlanStep> steps;
  std::size_t at = plan.start_node();
  while (steps.size() < limit) {
    const auto step = plan.next();
    if (!step)
      break;
    const auto& next = step->lane_change ? g.neighbours(at) : g.successors(at);
    EXPECT_NE(std::find(next.begin(), next.end(), step->node), next.end())
        << "step " << steps.size() << " is no edge of the lane graph";
    EXPECT_TRUE(g.node(step->node).drivable);
    at = step->node;
    steps.push_back(*step);
  }
  return steps;
}

std::string field_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const RouteError& e) {
    return e.field() + ": " + e.what();
  }
  return "no error";
}

TEST(LaneStart, PicksTheLaneUnderThePointAndTheDirection) {
  const odr::RoadNetwork net = four_way();
  const odr::LaneLocator loc(net);
  const int r0 = net.road_index("0");
  const odr::SurfacePose p = odr::lane_pose(net, r0, -1, 40.0);
  const auto with = lane_start(net, loc, p.x, p.y, p.heading);
  ASSERT_TRUE(with);
  EXPECT_EQ(with->road, r0);
  EXPECT_EQ(with->lane, -1);
  EXPECT_NEAR(with->s, 40.0, 1e-6);
  EXPECT_FALSE(with->against);
  const auto against = lane_start(net, loc, p.x, p.y, p.heading + std::numbers::pi);
  ASSERT_TRUE(against);
  EXPECT_EQ(against->lane, -1);
  EXPECT_TRUE(against->against);
  EXPECT_FALSE(lane_start(net, loc, p.x, p.y + 500.0, 0.0));
}

TEST(RoutePlan, RandomRoutesRepeatWithTheSeedAndTakeEveryTurn) {
  const odr::RoadNetwork net = four_way();
  const odr::LaneGraph g(net);
  std::set<std::string> exits;
  std::set<std::vector<std::size_t>> distinct;
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    std::vector<std::size_t> nodes[2];
    for (auto& run : nodes) {
      RoutePlan plan(net, g, route_of(Kind::kRandom), start_at(net, "0", -1, 50.0),
                     vehicle_seed(seed, 7));
      for (const PlanStep& st : drive(plan, g, 100))
        run.push_back(st.node);
    }
    EXPECT_EQ(nodes[0], nodes[1]) << "seed " << seed;
    // Arm 0's inbound lane, a connecting road, then an outbound arm lane that ends.
    ASSERT_EQ(nodes[0].size(), 2u);
    EXPECT_NE(net.roads[static_cast<std::size_t>(g.node(nodes[0][0]).road)].junction, "-1");
    exits.insert(net.roads[static_cast<std::size_t>(g.node(nodes[0][1]).road)].id);
    distinct.insert(nodes[0]);
  }
  // Road 0's inbound lane turns into each of the other three arms.
  EXPECT_EQ(exits.size(), 3u);
  EXPECT_EQ(distinct.size(), 3u);
  EXPECT_NE(vehicle_seed(1, 7), vehicle_seed(1, 8));
  EXPECT_NE(vehicle_seed(1, 7), vehicle_seed(2, 7));
}

TEST(RoutePlan, OwnLaneGoesOnForeverOnTheRingAndEndsOnTheStraight) {
  const odr::RoadNetwork ring = generate_network(builtin(scenario::MapType::kRing, 2, 1));
  const odr::LaneGraph gr(ring);
  RoutePlan on_ring(ring, gr, {}, LaneStart{0, -1, 10.0, false}, 1);
  EXPECT_EQ(drive(on_ring, gr, 50).size(), 50u);
  RoutePlan against(ring, gr, {}, LaneStart{0, 1, 10.0, true}, 1);
  EXPECT_EQ(drive(against, gr, 0).size(), 0u);
  const auto back = against.next();
  ASSERT_TRUE(back);
  EXPECT_EQ(back->node, against.start_node());  // the ring's one section, driven backwards

  const odr::RoadNetwork straight = generate_network(builtin(scenario::MapType::kStraight, 2, 1));
  const odr::LaneGraph gs(straight);
  RoutePlan on_straight(straight, gs, {}, LaneStart{0, -1, 10.0, false}, 1);
  EXPECT_FALSE(on_straight.next());
}

TEST(RoutePlan, OwnLaneTakesTheStraightestWayThroughAJunction) {
  const odr::RoadNetwork net = four_way();
  const odr::LaneGraph g(net);
  RoutePlan plan(net, g, {}, start_at(net, "0", -1, 50.0), 1);
  const auto steps = drive(plan, g, 10);
  ASSERT_EQ(steps.size(), 2u);
  const odr::Road& through = net.roads[static_cast<std::size_t>(g.node(steps[0].node).road)];
  EXPECT_NEAR(through.reference(0).hdg, through.reference(through.length).hdg, 1e-6);
}

TEST(RoutePlan, ListOfRoadsIsDrivenInOrderWithOrWithoutTheConnectingRoads) {
  const odr::RoadNetwork net = four_way();
  const odr::LaneGraph g(net);
  for (const auto& roads : {std::vector<std::string>{"0", "2"}, std::vector<std::string>{"2"}}) {
    RoutePlan plan(net, g, route_of(Kind::kRoads, roads), start_at(net, "0", -1, 50.0), 1);
    const auto steps = drive(plan, g, 10);
    ASSERT_EQ(steps.size(), 2u);
    EXPECT_EQ(net.roads[static_cast<std::size_t>(g.node(steps[1].node).road)].id, "2");
  }
  // Naming the connecting road too.
  RoutePlan plan(net, g, route_of(Kind::kRandom), start_at(net, "0", -1, 50.0), 1);
  const std::size_t connecting = plan.next()->node;
  const std::string c = net.roads[static_cast<std::size_t>(g.node(connecting).road)].id;
  const std::string exit_road =
      net.roads[static_cast<std::size_t>(g.node(g.successors(connecting).front()).road)].id;
  RoutePlan named(net, g, route_of(Kind::kRoads, {"0", c, exit_road}), start_at(net, "0", -1, 50.0),
                  1);
  const auto steps = drive(named, g, 10);
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps[0].node, connecting);
}

TEST(RoutePlan, GoalIsReachedWithTheLaneChangesItNeeds) {
  const odr::RoadNetwork net = generate_network(builtin(scenario::MapType::kStraight, 3, 1));
  const odr::LaneGraph g(net);
  scenario::DriveRoute to;
  to.kind = Kind::kTo;
  to.to = {"0", -1, 400.0};
  // Built-in lanes 0, 1 run along s as OpenDRIVE lanes -2, -1.
  RoutePlan plan(net, g, to, LaneStart{0, -2, 20.0, false}, 1);
  const auto steps = drive(plan, g, 10);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_TRUE(steps[0].lane_change);
  EXPECT_EQ(g.node(steps[0].node).lane, -1);
  EXPECT_EQ(plan.goal_s(), 400.0);
}

// One road: two lanes along s, the outer one ending after 100 m.
constexpr const char* kLaneEnds = R"(<?xml version="1.0"?>
<OpenDRIVE><header revMajor="1" revMinor="6"/>
<road id="m" junction="-1" length="200"><planView>
<geometry s="0" x="0" y="0" hdg="0" length="200"><line/></geometry></planView>
<lanes>
<laneSection s="0"><center><lane id="0" type="none"/></center><right>
<lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane>
<lane id="-2" type="entry"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane>
</right></laneSection>
<laneSection s="100"><center><lane id="0" type="none"/></center><right>
<lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane>
</right></laneSection>
</lanes></road></OpenDRIVE>)";

TEST(RoutePlan, AnEndingLaneMergesIntoItsNeighbour) {
  const odr::RoadNetwork net = odr::parse_opendrive(kLaneEnds, "lane-ends");
  const odr::LaneGraph g(net);
  for (Kind kind : {Kind::kLane, Kind::kRandom}) {
    RoutePlan plan(net, g, route_of(kind), LaneStart{0, -2, 20.0, false}, 3);
    const auto steps = drive(plan, g, 10);
    ASSERT_EQ(steps.size(), 2u);
    EXPECT_TRUE(steps[0].lane_change);
    EXPECT_EQ(g.node(steps[0].node).lane, -1);
    EXPECT_EQ(g.node(steps[1].node).section, 1u);
  }
}

TEST(RoutePlan, NamedErrorsForRoutesTheMapCannotGive) {
  const odr::RoadNetwork crossing = generate_network(builtin(scenario::MapType::kCrossing, 2, 1));
  const odr::LaneGraph gc(crossing);
  const LaneStart on_0{0, -1, 10.0, false};
  EXPECT_EQ(field_of([&] {
              RoutePlan(crossing, gc, route_of(Kind::kRoads, {"0", "7"}), on_0, 1);
            }).substr(0, 36),
            "route/1: road \"7\" does not exist in ");
  // The built-in crossing's roads cross at grade: no lane leads from one to the other.
  const std::string disconnected =
      field_of([&] { RoutePlan(crossing, gc, route_of(Kind::kRoads, {"1"}), on_0, 1); });
  EXPECT_EQ(disconnected.substr(0, 55),
            "route/0: no lane leads from the spawn road \"0\" to road ");

  const odr::RoadNetwork straight = generate_network(builtin(scenario::MapType::kStraight, 2, 1));
  const odr::LaneGraph gs(straight);
  auto to = [&](std::string road, int lane, double s) {
    scenario::DriveRoute r;
    r.kind = Kind::kTo;
    r.to = {std::move(road), lane, s};
    return field_of([&] { RoutePlan(straight, gs, r, on_0, 1); });
  };
  EXPECT_EQ(to("9", -1, 10).substr(0, 30), "to/road: road \"9\" does not exi");
  EXPECT_EQ(to("0", -1, 900).substr(0, 22), "to/s: s 900 is outside");
  EXPECT_EQ(to("0", -3, 100).substr(0, 32), "to/lane: road \"0\" has no lane -3");
  // The oncoming lane runs the other way: no lane change leads into it.
  EXPECT_EQ(to("0", 1, 300).substr(0, 40), "to: road \"0\" lane 1 at s 300 cannot be r");
  // Behind the start on its own lane, on an open road.
  EXPECT_EQ(to("0", -1, 5).substr(0, 4), "to: ");
  EXPECT_EQ(to("0", -1, 300), "no error");
  // A route for a car that drives against its lane.
  EXPECT_EQ(field_of([&] {
              RoutePlan(straight, gs, route_of(Kind::kRandom), LaneStart{0, -1, 10.0, true}, 1);
            }).substr(0, 6),
            "route:");
}

}  // namespace
}  // namespace tb::map
