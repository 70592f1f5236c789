// LCRW on curved paths: arcs of known radius against hand-worked values (issue 22).
#include <gtest/gtest.h>

#include <cmath>

#include "common/clock/clock.hpp"
#include "its-station/apps/lcrw/lcrw.hpp"

namespace tb::its::apps {
namespace {

// A left bend of radius 150 m starting at the origin, heading north: its centre is (-150, 0).
// 30 m along it the arc angle is 30 / 150 = 0.2 rad, so the point is
// (-150 + 150 cos 0.2, 150 sin 0.2) = (-2.990, 29.800) and the tangent is turned 0.2 rad
// = 11.459° to the left: heading 348.541°. A straight line along the heading would put that
// point 2.990 m to the left at 29.800 m.
constexpr double kR = 150.0;
constexpr double kArcX = -2.990013, kArcY = 29.800400, kArcHeading = 348.540844;

VehicleKinematics car(std::uint32_t id, double x, double y, double heading, double speed,
                      std::optional<double> yaw_rate_dps, clock::WallTime t) {
  VehicleKinematics v;
  v.station_id = id;
  v.x = x;
  v.y = y;
  v.heading_deg = heading;
  v.speed_mps = speed;
  v.yaw_rate_dps = yaw_rate_dps;
  v.length_m = 4.0;
  v.width_m = 1.8;
  v.time = t;
  return v;
}

TEST(PredictedPath, PointsAndTangentsOnALeftBend) {
  const PredictedPath p(0.0, 0.0, 0.0, 1.0 / kR);
  const auto q = p.at(30.0);
  EXPECT_NEAR(q.x, kArcX, 1e-5);
  EXPECT_NEAR(q.y, kArcY, 1e-5);
  EXPECT_NEAR(p.heading_at_deg(30.0), kArcHeading, 1e-5);
  const auto on = p.project(kArcX, kArcY);
  EXPECT_NEAR(on.s, 30.0, 1e-6);
  EXPECT_NEAR(on.lateral, 0.0, 1e-6);
  // The same arc angle on the outer lane (radius 153.5 m): 3.5 m to the right, still 30 m on.
  const auto outer = p.project(-150.0 + 153.5 * std::cos(0.2), 153.5 * std::sin(0.2));
  EXPECT_NEAR(outer.s, 30.0, 1e-6);
  EXPECT_NEAR(outer.lateral, 3.5, 1e-6);
  // Behind the start: negative s.
  const auto behind = p.project(-(1.0 - std::cos(0.1)) * kR, -kR * std::sin(0.1));
  EXPECT_NEAR(behind.s, -15.0, 1e-6);
  EXPECT_NEAR(behind.lateral, 0.0, 1e-6);
}

TEST(PredictedPath, RightBendMirrorsTheLeftOne) {
  // Heading east, bending right (k < 0): the centre is (0, -150); 30 m on the point is
  // (150 sin 0.2, -150 + 150 cos 0.2) = (29.800, -2.990), the tangent 101.459°.
  const PredictedPath p(0.0, 0.0, 90.0, -1.0 / kR);
  const auto q = p.at(30.0);
  EXPECT_NEAR(q.x, kArcY, 1e-5);
  EXPECT_NEAR(q.y, kArcX, 1e-5);
  EXPECT_NEAR(p.heading_at_deg(30.0), 90.0 + 11.459156, 1e-5);
  const auto on = p.project(kArcY, kArcX);
  EXPECT_NEAR(on.s, 30.0, 1e-6);
  EXPECT_NEAR(on.lateral, 0.0, 1e-6);
  // A point inside a right bend (radius 147 m, same arc angle) is 3 m right of the path.
  const auto inner = p.project(147.0 * std::sin(0.2), -150.0 + 147.0 * std::cos(0.2));
  EXPECT_NEAR(inner.s, 30.0, 1e-6);
  EXPECT_NEAR(inner.lateral, 3.0, 1e-6);
}

TEST(PathCurvature, FromYawRateOverSignedSpeedElseCamCurvature) {
  const LcrwConfig cfg;
  auto v = car(1, 0, 0, 0, 20.0, 7.639437, {});
  EXPECT_NEAR(path_curvature(v, cfg), 1.0 / kR, 1e-8);  // 20 m/s at 0.1333 rad/s
  v.reversing = true;  // the same yaw rate backward bends the other way relative to the nose
  EXPECT_NEAR(path_curvature(v, cfg), -1.0 / kR, 1e-8);
  v.speed_mps = 0.5;  // too slow to divide by: the CAM's curvature, or straight
  EXPECT_EQ(path_curvature(v, cfg), 0.0);
  v.curvature_per_m = 0.01;
  EXPECT_EQ(path_curvature(v, cfg), 0.01);
  v.curvature_per_m = 2.0;  // tighter than any car turns: clamped to 5 m
  EXPECT_EQ(path_curvature(v, cfg), 0.2);
  LcrwConfig straight;
  straight.use_curvature = false;
  EXPECT_EQ(path_curvature(car(1, 0, 0, 0, 20.0, 7.639437, {}), straight), 0.0);
}

class LcrwCurveTest : public ::testing::Test {
 protected:
  clock::ManualClock clk;
  LcrwConfig cfg;
};

TEST_F(LcrwCurveTest, CarAheadOnTheRingIsInPathAndGapIsAlongTheArc) {
  // Own 20 m/s at the start of the 150 m bend (yaw rate 20/150 rad/s = 7.639°/s), the other 30 m
  // ahead along the arc at 10 m/s (3.820°/s). Gap 30 - 4 = 26 m, closing 10 m/s: TTC 2.6 s.
  const auto own = car(1, 0, 0, 0, 20.0, 7.639437, clk.wall_now());
  const auto other = car(2, kArcX, kArcY, kArcHeading, 10.0, 3.819719, clk.wall_now());
  const auto a = assess(own, other, clk.wall_now(), cfg);
  EXPECT_TRUE(a.in_path);
  EXPECT_NEAR(a.longitudinal_offset_m, 30.0, 1e-6);
  EXPECT_NEAR(a.lateral_offset_m, 0.0, 1e-6);
  EXPECT_NEAR(a.gap_m, 26.0, 1e-6);
  EXPECT_NEAR(a.closing_speed_mps, 10.0, 1e-6);
  EXPECT_NEAR(a.ttc_s, 2.6, 1e-6);
  EXPECT_NEAR(a.lateral_at_contact_m, 0.0, 1e-6);  // it stays on the ring
  EXPECT_EQ(a.collision_case, CollisionCase::kForward);
  Lcrw lcrw(clk, cfg);
  const std::vector<VehicleKinematics> n{other};
  const auto e = lcrw.evaluate(own, n);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].event, WarningEvent::kRaised);
  EXPECT_NEAR(e[0].distance_m, 26.0, 1e-6);

  // The straight-line model of the thesis sees it 2.99 m to the left: not in path (the bug).
  LcrwConfig straight = cfg;
  straight.use_curvature = false;
  const auto s = assess(own, other, clk.wall_now(), straight);
  EXPECT_NEAR(s.lateral_offset_m, -2.990013, 1e-5);
  EXPECT_FALSE(s.in_path);
}

TEST_F(LcrwCurveTest, CarInTheOuterLaneOfTheBendIsNotInPath) {
  // Same arc angle on the lane 3.5 m further out (radius 153.5 m, 10 m/s = 3.733°/s).
  const auto own = car(1, 0, 0, 0, 20.0, 7.639437, clk.wall_now());
  const auto other = car(2, 0.440220, 30.495742, kArcHeading, 10.0, 3.732624, clk.wall_now());
  const auto a = assess(own, other, clk.wall_now(), cfg);
  EXPECT_NEAR(a.lateral_offset_m, 3.5, 1e-5);
  EXPECT_NEAR(a.lateral_at_contact_m, 3.5, 1e-3);
  EXPECT_FALSE(a.in_path);
  Lcrw lcrw(clk, cfg);
  const std::vector<VehicleKinematics> n{other};
  EXPECT_TRUE(lcrw.evaluate(own, n).empty());
}

TEST_F(LcrwCurveTest, OncomingCarOnTheBendIsFrontal) {
  // The other comes the opposite way on the same arc (heading 348.54 + 180), 10 m/s, yaw rate
  // clockwise for it: -3.820°/s. Closing 30 m/s over 26 m: TTC 0.8667 s.
  const auto own = car(1, 0, 0, 0, 20.0, 7.639437, clk.wall_now());
  const auto other = car(2, kArcX, kArcY, kArcHeading - 180.0, 10.0, -3.819719, clk.wall_now());
  const auto a = assess(own, other, clk.wall_now(), cfg);
  EXPECT_EQ(a.collision_case, CollisionCase::kFrontal);
  EXPECT_TRUE(a.in_path);
  EXPECT_NEAR(a.ttc_s, 26.0 / 30.0, 1e-6);
}

TEST_F(LcrwCurveTest, ReversingAlongATightArcTowardsAParkedCar) {
  // Reversing at 4 m/s with the nose swinging left at 4/30 rad/s = 7.639°/s: the path bends
  // with k = ω / u = 0.1333 / -4 = -1/30 m⁻¹ relative to the nose. 14 m back along it
  // (k·s = 0.4667 rad) the parked car stands at 30 (1 - cos 0.4667) = 3.208 m right of the
  // start line and 30 sin 0.4667 = 13.497 m behind, turned 26.738° (heading 333.262°).
  // Gap 14 - 4 = 10 m at 4 m/s: TTC 2.5 s.
  auto own = car(1, 0, 0, 0, 4.0, 7.639437, clk.wall_now());
  own.reversing = true;
  const auto parked = car(2, 3.207811, -13.497356, 333.261970, 0.0, 0.0, clk.wall_now());
  const auto a = assess(own, parked, clk.wall_now(), cfg);
  EXPECT_NEAR(a.own_curvature_per_m, -1.0 / 30.0, 1e-8);
  EXPECT_NEAR(a.longitudinal_offset_m, -14.0, 1e-5);
  EXPECT_NEAR(a.lateral_offset_m, 0.0, 1e-5);
  EXPECT_TRUE(a.ahead);
  EXPECT_TRUE(a.in_path);
  EXPECT_NEAR(a.ttc_s, 2.5, 1e-5);
  Lcrw lcrw(clk, cfg);
  const std::vector<VehicleKinematics> n{parked};
  const auto e = lcrw.evaluate(own, n);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].event, WarningEvent::kRaised);
}

TEST_F(LcrwCurveTest, InPathHysteresisHoldsAWarningAtTheEdge) {
  // Straight road, other 25 m ahead standing; own 10 m/s: TTC 2.1 s. In-path limit
  // 1.8 + 0.5 = 2.3 m; with the warning active 2.8 m.
  const auto own = car(1, 0, 0, 0, 10.0, 0.0, clk.wall_now());
  Lcrw lcrw(clk, cfg);
  const auto at = [&](double lateral) {
    const std::vector<VehicleKinematics> n{car(2, lateral, 25.0, 0, 0.0, 0.0, clk.wall_now())};
    return lcrw.evaluate(own, n);
  };
  EXPECT_TRUE(at(2.5).empty());  // outside: no warning
  auto e = at(2.0);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].event, WarningEvent::kRaised);
  e = at(2.6);  // noise at the edge: the warning holds
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].event, WarningEvent::kUpdated);
  e = at(2.9);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].event, WarningEvent::kCleared);
  EXPECT_EQ(e[0].clear_reason, ClearReason::kLeftPath);
}

TEST(ExtrapolateOnArc, MovesAlongTheBendAndTurnsTheHeading) {
  clock::ManualClock clk;
  const auto v = car(1, 0, 0, 0, 15.0, 5.729578, clk.wall_now());  // 15 m/s, R 150 m
  const double k = path_curvature(v, LcrwConfig{});
  clk.advance(std::chrono::seconds(2));  // 30 m along the arc
  const auto e = extrapolate(v, clk.wall_now(), true, k);
  EXPECT_NEAR(e.x, kArcX, 1e-5);
  EXPECT_NEAR(e.y, kArcY, 1e-5);
  EXPECT_NEAR(e.heading_deg, kArcHeading, 1e-5);
}

}  // namespace
}  // namespace tb::its::apps
