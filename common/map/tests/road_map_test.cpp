#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/map/road_map.hpp"

namespace tb::map {
namespace {

constexpr double kPi = std::numbers::pi;

scenario::MapSpec straight(int lanes, int oncoming) {
  scenario::MapSpec s;
  s.type = scenario::MapType::kStraight;
  s.lanes = lanes;
  s.oncoming_lanes = oncoming;
  s.lane_width = 3.5;
  s.length = 500.0;
  return s;
}

TEST(RoadMap, StraightTwoWayRoadHasLanesOnBothSides) {
  const RoadMap m(straight(2, 1));
  const Pose p0 = m.lane_pose(0, 0, 100.0);  // rightmost lane runs east
  EXPECT_NEAR(p0.p.x, 100.0, 1e-9);
  EXPECT_NEAR(p0.p.y, -1.75, 1e-9);
  EXPECT_NEAR(p0.yaw, 0.0, 1e-9);
  const Pose p1 = m.lane_pose(0, 1, 100.0);  // oncoming lane runs west from x = 500
  EXPECT_NEAR(p1.p.x, 400.0, 1e-9);
  EXPECT_NEAR(p1.p.y, 1.75, 1e-9);
  EXPECT_NEAR(std::abs(p1.yaw), kPi, 1e-9);
}

TEST(RoadMap, OnRoadAndOffRoad) {
  const RoadMap m(straight(2, 1));
  EXPECT_TRUE(m.on_road({10.0, 3.4}));
  EXPECT_FALSE(m.on_road({10.0, 3.6}));
  EXPECT_FALSE(m.on_road({-1.0, 0.0}));
  EXPECT_FALSE(m.on_road({501.0, 0.0}));
}

TEST(RoadMap, FindLanePrefersTheDirectionOfTravel) {
  const RoadMap m(straight(3, 1));
  const auto east = m.find_lane({50.0, -1.0}, 0.0);
  ASSERT_TRUE(east);
  EXPECT_EQ(east->lane, 1);
  EXPECT_NEAR(east->where.lateral, -1.0, 1e-9);
  EXPECT_FALSE(m.find_lane({50.0, 20.0}, 0.0));
}

TEST(RoadMap, RingLanesAreConcentricCircles) {
  scenario::MapSpec spec;
  spec.type = scenario::MapType::kRing;
  spec.lanes = 2;
  spec.oncoming_lanes = 0;
  spec.lane_width = 3.0;
  spec.radius = 100.0;
  const RoadMap m(spec);
  // Counter-clockwise traffic: the right-hand lane 0 is the outer one.
  const Pose start = m.lane_pose(0, 0, 0.0);
  EXPECT_NEAR(start.p.x, 101.5, 1e-9);
  EXPECT_NEAR(start.p.y, 0.0, 1e-9);
  EXPECT_NEAR(start.yaw, kPi / 2, 1e-9);
  const double circumference = 2 * kPi * 98.5;
  const Pose quarter = m.lane_pose(0, 1, circumference / 4);
  EXPECT_NEAR(quarter.p.x, 0.0, 1e-9);
  EXPECT_NEAR(quarter.p.y, 98.5, 1e-9);
  EXPECT_NEAR(std::abs(quarter.yaw), kPi, 1e-9);
  // s wraps around a closed lane
  const Pose wrapped = m.lane_pose(0, 1, circumference + 1.0);
  const Pose one = m.lane_pose(0, 1, 1.0);
  EXPECT_NEAR(wrapped.p.x, one.p.x, 1e-9);
  EXPECT_NEAR(wrapped.p.y, one.p.y, 1e-9);
  EXPECT_TRUE(m.on_road({0.0, -102.9}));
  EXPECT_FALSE(m.on_road({0.0, -103.1}));
  EXPECT_FALSE(m.on_road({0.0, 0.0}));
}

TEST(RoadMap, ProjectionInvertsPose) {
  scenario::MapSpec spec;
  spec.type = scenario::MapType::kRing;
  spec.oncoming_lanes = 1;
  const RoadMap m(spec);
  for (const Road& road : m.roads()) {
    for (const Lane& lane : road.lanes) {
      for (double s = 0.0; s < length(lane.centre); s += 37.0) {
        const Pose pose = pose_at(lane.centre, s);
        const Projection pr = project(lane.centre, pose.p);
        EXPECT_NEAR(pr.s, s, 1e-6);
        EXPECT_NEAR(pr.lateral, 0.0, 1e-9);
      }
    }
  }
}

TEST(RoadMap, CrossingHasTwoRoadsThroughTheCentre) {
  scenario::MapSpec spec;
  spec.type = scenario::MapType::kCrossing;
  spec.arm_length = 200.0;
  const RoadMap m(spec);
  ASSERT_EQ(m.roads().size(), 2u);
  const Pose north = m.lane_pose(1, 0, 0.0);
  EXPECT_NEAR(north.p.x, 1.75, 1e-9);
  EXPECT_NEAR(north.p.y, -200.0, 1e-9);
  EXPECT_NEAR(north.yaw, kPi / 2, 1e-9);
  EXPECT_TRUE(m.on_road({0.0, 150.0}));
  EXPECT_TRUE(m.on_road({150.0, 0.0}));
  EXPECT_FALSE(m.on_road({150.0, 150.0}));
  // In the middle both roads overlap: a car heading north belongs to the north-south road.
  const auto match = m.find_lane({1.0, 1.0}, kPi / 2);
  ASSERT_TRUE(match);
  EXPECT_EQ(match->road, 1);
}

TEST(RoadMap, MarkingsSeparateDirectionsWithASolidLine) {
  const RoadMap m(straight(4, 2));
  const auto marks = m.markings();
  ASSERT_EQ(marks.size(), 5u);
  EXPECT_EQ(marks[0].style, Marking::Style::kEdge);
  EXPECT_EQ(marks[1].style, Marking::Style::kDashed);
  EXPECT_EQ(marks[2].style, Marking::Style::kSolid);
  EXPECT_EQ(marks[4].style, Marking::Style::kEdge);
}

TEST(RoadMap, RejectsImpossibleLayouts) {
  auto spec = straight(2, 3);
  EXPECT_THROW(RoadMap{spec}, std::invalid_argument);
  EXPECT_THROW(RoadMap(straight(2, 1)).lane(0, 2), std::out_of_range);
}

}  // namespace
}  // namespace tb::map
