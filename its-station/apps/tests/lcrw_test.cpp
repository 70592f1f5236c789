#include "its-station/apps/lcrw/lcrw.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "common/clock/clock.hpp"

namespace tb::its::apps {
namespace {

using namespace std::chrono_literals;
constexpr double kInf = std::numeric_limits<double>::infinity();

VehicleKinematics car(std::uint32_t id, double x, double y, double heading, double speed,
                      clock::WallTime t) {
  VehicleKinematics v;
  v.station_id = id;
  v.x = x;
  v.y = y;
  v.heading_deg = heading;
  v.speed_mps = speed;
  v.length_m = 4.0;
  v.width_m = 1.8;
  v.time = t;
  return v;
}

class LcrwTest : public ::testing::Test {
 protected:
  clock::ManualClock clk;
  clock::WallTime now() const { return clk.wall_now(); }
  LcrwConfig cfg;
};

// --- the TTC solver -----------------------------------------------------------------------

TEST(TimeToClose, ConstantSpeeds) {
  EXPECT_DOUBLE_EQ(time_to_close(30.0, 0.0, 0.0, 10.0, 0.0, 10.0), 3.0);
  EXPECT_DOUBLE_EQ(time_to_close(30.0, 5.0, 0.0, 10.0, 0.0, 10.0), 6.0);
}

TEST(TimeToClose, FollowerAcceleratingFromRest) {
  EXPECT_NEAR(time_to_close(10.0, 0.0, 0.0, 0.0, 2.0, 10.0), std::sqrt(10.0), 1e-9);
}

TEST(TimeToClose, LeadBrakesToAStopAndStays) {
  // Lead stops after 2 s and 10 m; a plain constant-acceleration model would let it roll back
  // and predict contact at 2.83 s instead of 3 s.
  EXPECT_NEAR(time_to_close(20.0, 10.0, -5.0, 10.0, 0.0, 10.0), 3.0, 1e-9);
}

TEST(TimeToClose, FollowerStopsShort) {
  EXPECT_EQ(time_to_close(20.0, 0.0, 0.0, 10.0, -5.0, 10.0), kInf);
  // Stopping exactly 1 m short is still no contact.
  EXPECT_EQ(time_to_close(11.0, 0.0, 0.0, 10.0, -5.0, 10.0), kInf);
}

TEST(TimeToClose, FollowerBrakingButNotEnough) {
  // 10 m/s, -2 m/s²: would need 25 m; hits after 20 m: 20 = 10t - t² → t = 5 - √5.
  EXPECT_NEAR(time_to_close(20.0, 0.0, 0.0, 10.0, -2.0, 10.0), 5.0 - std::sqrt(5.0), 1e-9);
}

TEST(TimeToClose, BeyondHorizonOrOpeningIsInfinite) {
  EXPECT_EQ(time_to_close(1000.0, 0.0, 0.0, 10.0, 0.0, 10.0), kInf);
  EXPECT_EQ(time_to_close(10.0, 20.0, 0.0, 10.0, 0.0, 10.0), kInf);
  EXPECT_EQ(time_to_close(10.0, 0.0, 0.0, 0.0, 0.0, 10.0), kInf);
}

TEST(TimeToClose, OpeningNowButClosingLater) {
  // Lead is faster but brakes hard: the follower catches up after the lead has stopped.
  // Lead 12 m/s, -6 m/s² stops after 2 s / 12 m; follower 10 m/s; gap 10 → 22 = 10t → 2.2 s.
  EXPECT_NEAR(time_to_close(10.0, 12.0, -6.0, 10.0, 0.0, 10.0), 2.2, 1e-9);
}

TEST(TimeToClose, ContactNowIsZero) {
  EXPECT_EQ(time_to_close(0.0, 0.0, 0.0, 1.0, 0.0, 10.0), 0.0);
}

// --- geometry --------------------------------------------------------------------------------

TEST_F(LcrwTest, HeadOnInSameLaneWarnsWithFrontalCase) {
  Lcrw lcrw(clk, cfg);
  const auto own = car(1, 0, 0, 0, 15, now());
  const std::vector<VehicleKinematics> n{car(2, 0, 80, 180, 15, now())};
  const auto ev = lcrw.evaluate(own, n);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].event, WarningEvent::kRaised);
  EXPECT_EQ(ev[0].collision_case, CollisionCase::kFrontal);
  EXPECT_EQ(ev[0].station_id, 1u);
  EXPECT_EQ(ev[0].other_station_id, 2u);
  EXPECT_NEAR(ev[0].distance_m, 76.0, 1e-9);
  EXPECT_NEAR(ev[0].relative_speed_mps, 30.0, 1e-9);
  EXPECT_NEAR(ev[0].ttc_s, 76.0 / 30.0, 1e-9);
  EXPECT_EQ(ev[0].severity, Severity::kWarning);
  EXPECT_EQ(ev[0].raised_at, now());
}

TEST_F(LcrwTest, HeadOnFartherThanThresholdDoesNotWarn) {
  Lcrw lcrw(clk, cfg);
  const std::vector<VehicleKinematics> n{car(2, 0, 95, 180, 15, now())};  // TTC 3.03 s
  EXPECT_TRUE(lcrw.evaluate(car(1, 0, 0, 0, 15, now()), n).empty());
}

TEST_F(LcrwTest, PredictedOnsetRaisesOnTimeBetweenFixes) {
  // Head-on at 15 + 15 m/s, 91 m gap: TTC 3.0333 s, the threshold 33.3 ms away — before the
  // next fix. Evaluated again then (the states as they were, dead-reckoned), it warns at TTC 3.
  Lcrw lcrw(clk, cfg);
  const auto t0 = now();
  const auto own = car(1, 0, 0, 0, 15, t0);
  const std::vector<VehicleKinematics> n{car(2, 0, 95, 180, 15, t0)};
  EXPECT_TRUE(lcrw.evaluate(own, n).empty());
  ASSERT_TRUE(lcrw.time_to_onset_s().has_value());
  EXPECT_NEAR(*lcrw.time_to_onset_s(), 91.0 / 30.0 - 3.0, 1e-9);
  clk.advance(std::chrono::microseconds(std::llround(*lcrw.time_to_onset_s() * 1e6) + 1));
  const auto ev = lcrw.evaluate(own, n);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].event, WarningEvent::kRaised);
  EXPECT_NEAR(ev[0].ttc_s, 3.0, 1e-5);
  // Warned: no onset to wait for; nor for what is not in path, not closing, or far.
  EXPECT_FALSE(lcrw.time_to_onset_s().has_value());
  Lcrw other(clk, cfg);
  const auto me = car(1, 0, 0, 0, 15, now());
  other.evaluate(me, std::vector<VehicleKinematics>{car(2, 3.5, 95, 180, 15, now())});
  EXPECT_FALSE(other.time_to_onset_s().has_value());  // the next lane
  other.evaluate(me, std::vector<VehicleKinematics>{car(2, 0, 95, 0, 20, now())});
  EXPECT_FALSE(other.time_to_onset_s().has_value());  // moving away ahead
  other.evaluate(me, std::vector<VehicleKinematics>{car(2, 0, 200, 180, 15, now())});
  EXPECT_NEAR(*other.time_to_onset_s(), 196.0 / 30.0 - 3.0, 1e-9);  // far: the caller decides
}

TEST_F(LcrwTest, RearEndOnSlowerCarWarnsWithForwardCase) {
  Lcrw lcrw(clk, cfg);
  // Heading east: gap 29 m, closing 10 m/s.
  const std::vector<VehicleKinematics> n{car(2, 33, 0, 90, 10, now())};
  const auto ev = lcrw.evaluate(car(1, 0, 0, 90, 20, now()), n);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].collision_case, CollisionCase::kForward);
  EXPECT_NEAR(ev[0].ttc_s, 2.9, 1e-9);
  EXPECT_NEAR(ev[0].distance_m, 29.0, 1e-9);
}

TEST_F(LcrwTest, StoppedCarAheadWarnsApproachingDriver) {
  Lcrw lcrw(clk, cfg);
  const std::vector<VehicleKinematics> n{car(2, 0, 24, 0, 0, now())};
  const auto ev = lcrw.evaluate(car(1, 0, 0, 0, 10, now()), n);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_NEAR(ev[0].ttc_s, 2.0, 1e-9);
}

TEST_F(LcrwTest, BothStoppedNeverWarn) {
  Lcrw lcrw(clk, cfg);
  const std::vector<VehicleKinematics> n{car(2, 0, 5, 0, 0, now())};
  EXPECT_TRUE(lcrw.evaluate(car(1, 0, 0, 0, 0, now()), n).empty());
}

TEST_F(LcrwTest, StoppedOwnCarFacingOncomingCarWarns) {
  Lcrw lcrw(clk, cfg);
  const std::vector<VehicleKinematics> n{car(2, 0, 44, 180, 20, now())};
  const auto ev = lcrw.evaluate(car(1, 0, 0, 0, 0, now()), n);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_NEAR(ev[0].ttc_s, 2.0, 1e-9);
}

TEST_F(LcrwTest, FasterCarFromBehindWarnsOnlyWhenRearIsIncluded) {
  const auto own = car(1, 0, 0, 0, 10, now());
  const std::vector<VehicleKinematics> n{car(2, 0, -24, 0, 20, now())};
  Lcrw front_only(clk, cfg);
  EXPECT_TRUE(front_only.evaluate(own, n).empty());
  cfg.include_vehicles_behind = true;
  Lcrw both(clk, cfg);
  const auto ev = both.evaluate(own, n);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].collision_case, CollisionCase::kForward);
  EXPECT_NEAR(ev[0].ttc_s, 2.0, 1e-9);
}

TEST_F(LcrwTest, MovingApartNeverWarns) {
  Lcrw lcrw(clk, cfg);
  const auto own = car(1, 0, 0, 0, 10, now());
  // Faster car just ahead, and a car just behind driving away the other way.
  const std::vector<VehicleKinematics> n{car(2, 0, 6, 0, 15, now()), car(3, 0, -6, 180, 15, now())};
  EXPECT_TRUE(lcrw.evaluate(own, n).empty());
}

TEST_F(LcrwTest, OncomingCarInNextLaneNeverWarnsWhilePassing) {
  Lcrw lcrw(clk, cfg);
  for (int step = 0; step < 100; ++step) {
    const double t = step * 0.1;
    // Own northbound at x = 0, the other southbound in the next lane at x = -3.5, with a small
    // heading error that would drift it into the path over a long gap.
    auto own = car(1, 0, 15 * t, 0, 15, now());
    auto other = car(2, -3.5, 150 - 15 * t, 177, 15, now());
    const std::vector<VehicleKinematics> n{other};
    EXPECT_TRUE(lcrw.evaluate(own, n).empty()) << "at t=" << t;
    clk.advance(100ms);
  }
}

TEST_F(LcrwTest, CarsSideBySideNeverWarn) {
  Lcrw lcrw(clk, cfg);
  const auto own = car(1, 0, 0, 0, 20, now());
  // Next lane, overlapping; the same lane but beside it (narrow road); slightly behind.
  const std::vector<VehicleKinematics> n{
      car(2, 3.5, 1, 0, 10, now()), car(3, -2.0, 0.5, 0, 10, now()), car(4, 3.5, -3, 0, 30, now())};
  EXPECT_TRUE(lcrw.evaluate(own, n).empty());
}

TEST_F(LcrwTest, CrossingTrafficIsNotALongitudinalRisk) {
  Lcrw lcrw(clk, cfg);
  const auto own = car(1, 0, 0, 0, 15, now());
  for (const double h : {45.0, 90.0, 135.0, 225.0, 270.0, 315.0}) {
    const std::vector<VehicleKinematics> n{car(2, 0, 30, h, 15, now())};
    EXPECT_TRUE(lcrw.evaluate(own, n).empty()) << "heading " << h;
    const auto a = assess(own, n[0], now(), cfg);
    EXPECT_FALSE(a.collision_case.has_value()) << "heading " << h;
  }
}

TEST_F(LcrwTest, ShallowAngleIsStillOnePath) {
  Lcrw lcrw(clk, cfg);
  const std::vector<VehicleKinematics> n{car(2, 0, 30, 20, 2, now())};
  const auto ev = lcrw.evaluate(car(1, 0, 0, 0, 15, now()), n);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].collision_case, CollisionCase::kForward);
  // The lead's speed along the own path is 2·cos 20°.
  EXPECT_NEAR(ev[0].relative_speed_mps, 15 - 2 * std::cos(20 * M_PI / 180), 1e-9);
}

TEST_F(LcrwTest, HeadingWrapAroundNorth) {
  Lcrw lcrw(clk, cfg);
  const std::vector<VehicleKinematics> n{car(2, 0, 24, 1, 0, now())};
  const auto ev = lcrw.evaluate(car(1, 0, 0, 359, 10, now()), n);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].collision_case, CollisionCase::kForward);
}

TEST_F(LcrwTest, ReversingTowardsAParkedCarBehindWarns) {
  Lcrw lcrw(clk, cfg);
  auto own = car(1, 0, 0, 0, 3, now());
  own.reversing = true;
  const std::vector<VehicleKinematics> n{car(2, 0, -9, 0, 0, now()), car(3, 0, 9, 0, 0, now())};
  const auto ev = lcrw.evaluate(own, n);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].other_station_id, 2u);
  EXPECT_NEAR(ev[0].ttc_s, 5.0 / 3.0, 1e-9);
}

TEST_F(LcrwTest, CarAheadReversingTowardsUsWarns) {
  Lcrw lcrw(clk, cfg);
  auto other = car(2, 0, 10, 0, 3, now());
  other.reversing = true;
  const std::vector<VehicleKinematics> n{other};
  const auto ev = lcrw.evaluate(car(1, 0, 0, 0, 0, now()), n);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_NEAR(ev[0].ttc_s, 2.0, 1e-9);
  EXPECT_NEAR(ev[0].relative_speed_mps, 3.0, 1e-9);
}

TEST_F(LcrwTest, CriticalSeverityBelowCriticalTtc) {
  Lcrw lcrw(clk, cfg);
  const std::vector<VehicleKinematics> n{car(2, 0, 14, 0, 0, now())};
  const auto ev = lcrw.evaluate(car(1, 0, 0, 0, 10, now()), n);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_NEAR(ev[0].ttc_s, 1.0, 1e-9);
  EXPECT_EQ(ev[0].severity, Severity::kCritical);
}

TEST_F(LcrwTest, AccelerationShortensTtcWhenUsed) {
  auto own = car(1, 0, 0, 0, 10, now());
  own.longitudinal_accel_mps2 = 2.0;
  const std::vector<VehicleKinematics> n{car(2, 0, 38, 0, 0, now())};  // gap 34
  // Constant speed: 3.4 s, no warning. With acceleration: 34 = 10t + t² → t ≈ 2.68 s.
  cfg.use_acceleration = false;
  Lcrw plain(clk, cfg);
  EXPECT_TRUE(plain.evaluate(own, n).empty());
  cfg.use_acceleration = true;
  Lcrw accel(clk, cfg);
  const auto ev = accel.evaluate(own, n);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_NEAR(ev[0].ttc_s, -5 + std::sqrt(25 + 34), 1e-9);
}

TEST_F(LcrwTest, AgedNeighbourStateIsDeadReckoned) {
  // The CAM is 0.5 s old: the lead (10 m/s) has moved 5 m since.
  const auto stamp = now();
  clk.advance(500ms);
  Lcrw lcrw(clk, cfg);
  const std::vector<VehicleKinematics> n{car(2, 0, 28, 0, 10, stamp)};
  const auto ev = lcrw.evaluate(car(1, 0, 0, 0, 20, now()), n);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_NEAR(ev[0].distance_m, 29.0, 1e-9);
  EXPECT_NEAR(ev[0].ttc_s, 2.9, 1e-9);
  EXPECT_EQ(ev[0].other_state_time, stamp);
}

TEST(Extrapolate, BrakingEndsAtStandstill) {
  clock::ManualClock clk;
  auto v = car(1, 0, 0, 90, 10, clk.wall_now());
  v.longitudinal_accel_mps2 = -5.0;
  clk.advance(5s);
  const auto e = extrapolate(v, clk.wall_now(), true);
  EXPECT_NEAR(e.x, 10.0, 1e-9);
  EXPECT_NEAR(e.y, 0.0, 1e-9);
  EXPECT_EQ(e.speed_mps, 0.0);
  EXPECT_FALSE(e.reversing);
}

TEST(Geometry, FrontReferenceToCentre) {
  VehicleKinematics v;
  v.heading_deg = 90;
  v.length_m = 4.0;
  v.x = 10;
  const auto c = centre_from_front_reference(v);
  EXPECT_NEAR(c.x, 8.0, 1e-9);
  EXPECT_NEAR(c.y, 0.0, 1e-9);
}

TEST(Geometry, GeodeticPositionThroughLocalFrame) {
  const geodesy::LocalFrame frame(geodesy::Geodetic{48.0, 11.0, 500.0});
  const auto g = frame.to_geodetic(geodesy::Enu{120.0, -40.0, 0.0});
  const auto v =
      with_geodetic_position(VehicleKinematics{}, frame, g.latitude_deg, g.longitude_deg);
  EXPECT_NEAR(v.x, 120.0, 0.01);
  EXPECT_NEAR(v.y, -40.0, 0.01);
}

// --- the state machine ---------------------------------------------------------------------

TEST_F(LcrwTest, HysteresisHoldsTheWarningUntilTtcClearThreshold) {
  Lcrw lcrw(clk, cfg);
  const auto own = car(1, 0, 0, 0, 10, now());
  auto at_ttc = [&](double ttc) {
    return std::vector<VehicleKinematics>{car(2, 0, 4 + 10 * ttc, 0, 0, now())};
  };
  EXPECT_TRUE(lcrw.evaluate(own, at_ttc(3.2)).empty());
  auto ev = lcrw.evaluate(own, at_ttc(2.9));
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].event, WarningEvent::kRaised);
  const auto raised = ev[0].raised_at;
  clk.advance(100ms);
  ev = lcrw.evaluate(car(1, 0, 0, 0, 10, now()), at_ttc(3.3));
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].event, WarningEvent::kUpdated);
  EXPECT_EQ(ev[0].raised_at, raised);
  EXPECT_EQ(lcrw.active().size(), 1u);
  clk.advance(100ms);
  ev = lcrw.evaluate(car(1, 0, 0, 0, 10, now()), at_ttc(3.6));
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].event, WarningEvent::kCleared);
  EXPECT_EQ(ev[0].clear_reason, ClearReason::kRiskEnded);
  EXPECT_TRUE(lcrw.active().empty());
  // Between the thresholds again: not raised anew.
  clk.advance(100ms);
  EXPECT_TRUE(lcrw.evaluate(car(1, 0, 0, 0, 10, now()), at_ttc(3.2)).empty());
}

TEST_F(LcrwTest, LostNeighbourClearsTheWarning) {
  Lcrw lcrw(clk, cfg);
  const std::vector<VehicleKinematics> n{car(2, 0, 24, 0, 0, now())};
  ASSERT_EQ(lcrw.evaluate(car(1, 0, 0, 0, 10, now()), n).size(), 1u);
  const auto ev = lcrw.evaluate(car(1, 0, 0, 0, 10, now()), {});
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].event, WarningEvent::kCleared);
  EXPECT_EQ(ev[0].clear_reason, ClearReason::kNeighbourLost);
}

TEST_F(LcrwTest, StaleNeighbourCountsAsLost) {
  Lcrw lcrw(clk, cfg);
  const std::vector<VehicleKinematics> n{car(2, 0, 44, 180, 10, now())};
  ASSERT_EQ(lcrw.evaluate(car(1, 0, 0, 0, 10, now()), n).size(), 1u);
  clk.advance(2600ms);  // no CAM for longer than max_neighbour_age_s
  const auto ev = lcrw.evaluate(car(1, 0, 0, 0, 0, now()), n);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].clear_reason, ClearReason::kNeighbourLost);
}

TEST_F(LcrwTest, LaneChangeIntoPathRaisesAndOutOfPathClears) {
  Lcrw lcrw(clk, cfg);
  const auto own = car(1, 0, 0, 0, 20, now());
  EXPECT_TRUE(lcrw.evaluate(own, std::vector{car(2, 3.5, 25, 0, 10, now())}).empty());
  auto ev = lcrw.evaluate(own, std::vector{car(2, 1.0, 25, 0, 10, now())});
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].event, WarningEvent::kRaised);
  EXPECT_NEAR(ev[0].lateral_offset_m, 1.0, 1e-9);
  ev = lcrw.evaluate(own, std::vector{car(2, 3.4, 25, 0, 10, now())});
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].clear_reason, ClearReason::kLeftPath);
}

TEST_F(LcrwTest, ActiveWarningClearsWhenVehiclesMoveApart) {
  Lcrw lcrw(clk, cfg);
  const auto own = car(1, 0, 0, 0, 20, now());
  ASSERT_EQ(lcrw.evaluate(own, std::vector{car(2, 0, 30, 0, 10, now())}).size(), 1u);
  const auto ev = lcrw.evaluate(own, std::vector{car(2, 0, 30, 0, 25, now())});
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].clear_reason, ClearReason::kMovingApart);
}

TEST_F(LcrwTest, OwnStationInNeighbourListIsIgnored) {
  Lcrw lcrw(clk, cfg);
  const std::vector<VehicleKinematics> n{car(1, 0, 10, 180, 10, now())};
  EXPECT_TRUE(lcrw.evaluate(car(1, 0, 0, 0, 10, now()), n).empty());
}

TEST_F(LcrwTest, ThresholdsAreConfigurable) {
  cfg.ttc_warning_s = 5.0;
  cfg.ttc_clear_s = 5.5;
  Lcrw lcrw(clk, cfg);
  const std::vector<VehicleKinematics> n{car(2, 0, 49, 0, 0, now())};  // TTC 4.5 s
  EXPECT_EQ(lcrw.evaluate(car(1, 0, 0, 0, 10, now()), n).size(), 1u);
}

/// The thesis's frontal case, closed loop: two cars approach head-on at 15 m/s; once warned,
/// both drivers brake at 6 m/s² (reported in the CAM). The warning must come when the TTC first
/// falls below 3 s, hold while they brake, and clear when the risk ends.
TEST_F(LcrwTest, FrontalApproachWarnsUntilTheDriversHaveBraked) {
  Lcrw lcrw(clk, cfg);
  double y1 = 0, y2 = 160, v = 15;
  bool braking = false;
  int raised = 0, cleared = 0;
  double ttc_at_raise = 0;
  for (int step = 0; step < 300; ++step) {
    auto a = car(1, 0, y1, 0, v, now());
    auto b = car(2, 0, y2, 180, v, now());
    if (braking) {
      a.longitudinal_accel_mps2 = -6.0;
      b.longitudinal_accel_mps2 = -6.0;
    }
    for (const auto& e : lcrw.evaluate(a, std::vector{b})) {
      if (e.event == WarningEvent::kRaised) {
        ++raised;
        ttc_at_raise = e.ttc_s;
        braking = true;
      } else if (e.event == WarningEvent::kCleared) {
        ++cleared;
        EXPECT_EQ(e.clear_reason, ClearReason::kRiskEnded);
      }
    }
    const double dt = 0.05;
    const double acc = braking ? -6.0 : 0.0;
    const double nv = std::max(0.0, v + acc * dt);
    const double s = (v + nv) / 2 * dt;
    y1 += s;
    y2 -= s;
    v = nv;
    clk.advance(50ms);
  }
  EXPECT_EQ(raised, 1);
  EXPECT_EQ(cleared, 1);
  EXPECT_GT(ttc_at_raise, 2.9);
  EXPECT_LT(ttc_at_raise, 3.0);
  EXPECT_GT(y2 - y1, 4.0) << "they stopped apart";
}

}  // namespace
}  // namespace tb::its::apps
