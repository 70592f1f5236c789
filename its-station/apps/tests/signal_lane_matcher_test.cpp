// Lane matching against hand-built intersection geometry: straight and curved ingress lanes,
// adjacent lanes, wrong headings, the stop line, GNSS noise at the tolerance. Expected values
// come from the geometry (positions on the lanes), not from the matcher.
#include "its-station/apps/signal/lane_matcher.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace tb::its::apps::signal {
namespace {

constexpr double kPi = 3.14159265358979323846;

GenericLane straight_lane(std::uint8_t id, double x, bool ingress) {
  GenericLane l;
  l.lane_id = id;
  l.ingress = ingress;
  l.egress = !ingress;
  l.lane_width_m = 3.5;
  // South arm: the stop line 10 m south of the reference point, the lane 100 m long.
  l.nodes = {{x, -10.0}, {x, -60.0}, {x, -110.0}};
  return l;
}

// Two northbound ingress lanes (1 at x 1.75, 2 at x 5.25) and the southbound egress lane 3.
IntersectionTopology south_arm() {
  IntersectionTopology t;
  t.intersection_id = 7;
  t.lanes = {straight_lane(1, 1.75, true), straight_lane(2, 5.25, true),
             straight_lane(3, -1.75, false)};
  return t;
}

LocalPose pose(double x, double y, double heading, double speed = 10.0) {
  return LocalPose{x, y, heading, speed};
}

TEST(ProjectOntoLane, StraightLaneDistanceAndSide) {
  const GenericLane l = straight_lane(1, 1.75, true);
  const LaneProjection p = project_onto_lane(l, 2.25, -50.0);
  EXPECT_NEAR(p.distance_to_stop_line_m, 40.0, 1e-9);  // from y -50 to the line at y -10
  EXPECT_NEAR(p.lateral_offset_m, 0.5, 1e-9) << "east of a northbound lane is its right";
  EXPECT_NEAR(p.lane_heading_deg, 0.0, 1e-9) << "towards the stop line: north";
  EXPECT_FALSE(p.beyond_far_end);
  EXPECT_NEAR(project_onto_lane(l, 1.25, -50.0).lateral_offset_m, -0.5, 1e-9);
  EXPECT_NEAR(project_onto_lane(l, 1.75, -7.0).distance_to_stop_line_m, -3.0, 1e-9)
      << "3 m past the stop line";
  EXPECT_TRUE(project_onto_lane(l, 1.75, -115.0).beyond_far_end);
}

TEST(IngressLaneMatcher, StraightLane) {
  IngressLaneMatcher m;
  const auto match = m.update(south_arm(), pose(1.75, -50.0, 0.0));
  ASSERT_TRUE(match);
  EXPECT_EQ(match->lane_id, 1);
  EXPECT_NEAR(match->projection.distance_to_stop_line_m, 40.0, 1e-9);
  EXPECT_NEAR(match->heading_error_deg, 0.0, 1e-9);
}

TEST(IngressLaneMatcher, AdjacentLanesEachTheirOwn) {
  IngressLaneMatcher a, b;
  EXPECT_EQ(a.update(south_arm(), pose(1.75, -50.0, 2.0))->lane_id, 1);
  EXPECT_EQ(b.update(south_arm(), pose(5.25, -50.0, 358.0))->lane_id, 2);
}

TEST(IngressLaneMatcher, WrongHeadingIsNoMatch) {
  IngressLaneMatcher m;
  EXPECT_FALSE(m.update(south_arm(), pose(1.75, -50.0, 180.0))) << "driving away";
  EXPECT_FALSE(m.update(south_arm(), pose(1.75, -50.0, 90.0))) << "across the lane";
  EXPECT_FALSE(m.update(south_arm(), pose(1.75, -50.0, 46.0))) << "beyond the 45° tolerance";
  EXPECT_EQ(m.update(south_arm(), pose(1.75, -50.0, 44.0))->lane_id, 1);
  IngressLaneMatcher egress;
  EXPECT_FALSE(egress.update(south_arm(), pose(-1.75, -50.0, 180.0)))
      << "southbound on the egress lane: not an ingress lane, and 3.5 m from lane 1";
  EXPECT_FALSE(egress.update(south_arm(), pose(-1.75, -50.0, 0.0)))
      << "northbound in the egress lane (wrong way): 3.5 m off lane 1, outside 1.75 + 1.0";
}

TEST(IngressLaneMatcher, GnssNoiseAtTheTolerance) {
  // Lane 1 alone: the gate is half the width (1.75 m) plus the GNSS tolerance (1.0 m).
  IntersectionTopology t = south_arm();
  t.lanes = {straight_lane(1, 1.75, true)};
  IngressLaneMatcher inside, outside, left_inside;
  EXPECT_TRUE(inside.update(t, pose(1.75 + 2.74, -50.0, 0.0)));
  EXPECT_FALSE(outside.update(t, pose(1.75 + 2.76, -50.0, 0.0)));
  EXPECT_TRUE(left_inside.update(t, pose(1.75 - 2.74, -50.0, 0.0)));
}

TEST(IngressLaneMatcher, HysteresisBetweenAdjacentLanes) {
  IngressLaneMatcher m;
  ASSERT_EQ(m.update(south_arm(), pose(1.75, -60.0, 0.0))->lane_id, 1);
  // 0.1 m over the lane boundary (x 3.5): lane 2 closer by 0.2 m, within the 0.5 m margin.
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(m.update(south_arm(), pose(3.6, -59.0 + i, 0.0))->lane_id, 1);
  }
  // A single noisy fix deep in lane 2, then back: no switch.
  EXPECT_EQ(m.update(south_arm(), pose(5.0, -54.0, 0.0))->lane_id, 1);
  EXPECT_EQ(m.update(south_arm(), pose(2.0, -53.0, 0.0))->lane_id, 1);
  // A real lane change: lane 2 closer by 1 m on three fixes in a row.
  EXPECT_EQ(m.update(south_arm(), pose(4.0, -52.0, 5.0))->lane_id, 1);
  EXPECT_EQ(m.update(south_arm(), pose(4.0, -51.0, 5.0))->lane_id, 1);
  EXPECT_EQ(m.update(south_arm(), pose(4.0, -50.0, 5.0))->lane_id, 2);
  EXPECT_EQ(m.update(south_arm(), pose(3.4, -49.0, 0.0))->lane_id, 2) << "held now, too";
}

TEST(IngressLaneMatcher, OneFixOutsideDoesNotDropTheLane) {
  IntersectionTopology t = south_arm();
  t.lanes = {straight_lane(1, 1.75, true)};
  IngressLaneMatcher m;
  ASSERT_TRUE(m.update(t, pose(1.75, -60.0, 0.0)));
  EXPECT_TRUE(m.update(t, pose(1.75 + 3.0, -59.0, 0.0))) << "3 m noise: grace";
  EXPECT_TRUE(m.update(t, pose(1.75, -58.0, 0.0)));
  EXPECT_TRUE(m.update(t, pose(1.75 + 3.0, -57.0, 0.0)));
  EXPECT_TRUE(m.update(t, pose(1.75 + 3.0, -56.0, 0.0)));
  EXPECT_FALSE(m.update(t, pose(1.75 + 3.0, -55.0, 0.0))) << "three fixes outside: lost";
}

TEST(IngressLaneMatcher, PastTheStopLine) {
  IngressLaneMatcher fresh;
  EXPECT_FALSE(fresh.update(south_arm(), pose(1.75, -8.0, 0.0)))
      << "a vehicle already in the junction is on no ingress lane";
  IngressLaneMatcher m;
  ASSERT_NEAR(m.update(south_arm(), pose(1.75, -12.0, 0.0))->projection.distance_to_stop_line_m,
              2.0, 1e-9);
  const auto past = m.update(south_arm(), pose(1.75, -8.0, 0.0));
  ASSERT_TRUE(past) << "the lane held is followed past its line";
  EXPECT_NEAR(past->projection.distance_to_stop_line_m, -2.0, 1e-9);
  EXPECT_TRUE(m.update(south_arm(), pose(1.75, -1.0, 0.0)));  // 9 m past
  for (int i = 0; i < 2; ++i) {
    EXPECT_TRUE(m.update(south_arm(), pose(1.75, 2.0 + i, 0.0))) << "grace";
  }
  EXPECT_FALSE(m.update(south_arm(), pose(1.75, 5.0, 0.0)));
}

TEST(IngressLaneMatcher, StandingKeepsTheLaneButDoesNotMatchANewOne) {
  IngressLaneMatcher fresh;
  EXPECT_FALSE(fresh.update(south_arm(), pose(1.75, -11.0, 0.0, 0.0)));
  IngressLaneMatcher m;
  ASSERT_TRUE(m.update(south_arm(), pose(1.75, -20.0, 0.0, 5.0)));
  const auto stopped = m.update(south_arm(), pose(1.9, -11.0, 137.0, 0.0));
  ASSERT_TRUE(stopped) << "a standing car's course is noise";
  EXPECT_NEAR(stopped->projection.distance_to_stop_line_m, 1.0, 1e-9);
}

// A left-curving ingress lane: quarter circle of radius 30 m about (-30, 0), from heading east
// at (-30, -30) to heading north at its stop line (0, 0); nodes every 3°. The outer lane 2
// (radius 33.5 m) runs beside it.
GenericLane arc_lane(std::uint8_t id, double radius) {
  GenericLane l;
  l.lane_id = id;
  l.ingress = true;
  for (int deg = 0; deg <= 90; deg += 3) {
    const double th = deg * kPi / 180.0;
    l.nodes.push_back({-30.0 + radius * std::cos(th), -radius * std::sin(th)});
  }
  return l;
}

IntersectionTopology curve() {
  IntersectionTopology t;
  t.intersection_id = 9;
  t.lanes = {arc_lane(1, 30.0), arc_lane(2, 33.5)};
  return t;
}

LocalPose on_arc(double radius, double theta_deg, double heading_offset = 0.0) {
  const double th = theta_deg * kPi / 180.0;
  // The direction of travel at θ is (sin θ, cos θ): ETSI heading θ.
  return pose(-30.0 + radius * std::cos(th), -radius * std::sin(th), theta_deg + heading_offset);
}

TEST(IngressLaneMatcher, CurvedLane) {
  for (const double theta : {10.0, 44.0, 45.0, 80.0}) {
    IngressLaneMatcher m;
    const auto match = m.update(curve(), on_arc(30.0, theta));
    ASSERT_TRUE(match) << theta;
    EXPECT_EQ(match->lane_id, 1);
    // The arc length R·θ; the 3° chords are shorter by under 0.01 %.
    EXPECT_NEAR(match->projection.distance_to_stop_line_m, 30.0 * theta * kPi / 180.0, 0.01)
        << theta;
    // Off the chords by at most their sagitta R(1 − cos 1.5°) ≈ 1 cm.
    EXPECT_NEAR(std::abs(match->projection.lateral_offset_m), 0.0, 0.011) << theta;
    EXPECT_NEAR(match->heading_error_deg, 0.0, 1.51) << "a chord turns at most 1.5° off";
  }
}

TEST(IngressLaneMatcher, CurvedAdjacentLanesAndSides) {
  IngressLaneMatcher outer;
  const auto m2 = outer.update(curve(), on_arc(33.5, 45.0));
  ASSERT_TRUE(m2);
  EXPECT_EQ(m2->lane_id, 2);
  EXPECT_NEAR(m2->projection.distance_to_stop_line_m, 33.5 * kPi / 4.0, 0.01);

  IngressLaneMatcher inner;
  const auto m1 = inner.update(curve(), on_arc(31.2, 45.0));
  ASSERT_TRUE(m1);
  EXPECT_EQ(m1->lane_id, 1);
  EXPECT_NEAR(m1->projection.lateral_offset_m, 1.2, 0.01)
      << "the outside of a left bend is the right";

  IngressLaneMatcher wrong;
  EXPECT_FALSE(wrong.update(curve(), on_arc(30.0, 45.0, 180.0))) << "against the lane";
  IngressLaneMatcher off;
  EXPECT_FALSE(off.update(curve(), on_arc(30.0 - 2.8, 45.0))) << "inside, beyond 1.75 + 1.0";
}

TEST(IngressLaneMatcher, CurvedLaneFollowedToItsStopLine) {
  IngressLaneMatcher m;
  double previous = 1e9;
  for (double theta = 85.0; theta >= 1.0; theta -= 2.0) {
    const auto match = m.update(curve(), on_arc(30.0, theta));
    ASSERT_TRUE(match) << theta;
    EXPECT_EQ(match->lane_id, 1);
    EXPECT_LT(match->projection.distance_to_stop_line_m, previous);
    previous = match->projection.distance_to_stop_line_m;
  }
  EXPECT_NEAR(previous, 30.0 * kPi / 180.0, 0.01);
}

TEST(Topology, ValidateNamesLaneAndField) {
  IntersectionTopology t = south_arm();
  EXPECT_FALSE(validate(t));
  t.lanes[1].lane_id = 1;
  ASSERT_TRUE(validate(t));
  EXPECT_NE(validate(t)->message.find("laneID 1 appears twice"), std::string::npos);
  t = south_arm();
  t.lanes[0].nodes.resize(1);
  ASSERT_TRUE(validate(t));
  EXPECT_NE(validate(t)->message.find("lane 1"), std::string::npos);
  t = south_arm();
  t.lanes[0].lane_width_m = 0.0;
  ASSERT_TRUE(validate(t));
  EXPECT_NE(validate(t)->message.find("laneWidth"), std::string::npos);
  t = south_arm();
  t.lanes[0].connects_to = {{3, 255}};
  ASSERT_TRUE(validate(t));
  EXPECT_NE(validate(t)->message.find("signalGroup 255"), std::string::npos);
}

}  // namespace
}  // namespace tb::its::apps::signal
