// RLVW decisions for worked cases. Every expectation is computed here by hand from the physics
// of issue 34's rule: stopping distance D = v·t_r + v²/(2a) with t_r = 1 s, a = 3 m/s²,
// arrival t = d / v at constant speed, and the light's phases from the SPAT times.
#include "its-station/apps/signal/rlvw.hpp"

#include <gtest/gtest.h>

#include <chrono>

#include "common/clock/clock.hpp"

namespace tb::its::apps::signal {
namespace {

using namespace std::chrono_literals;
using S = MovementPhaseState;

constexpr double kKmh = 1.0 / 3.6;

class RlvwTest : public ::testing::Test {
 protected:
  clock::ManualClock clk;
  RlvwConfig cfg;

  clock::WallTime at(double s) const {
    return clk.wall_now() +
           std::chrono::duration_cast<clock::Duration>(std::chrono::duration<double>(s));
  }
  /// A group showing @p state now that ends (likelyTime) @p end_s from now, if given.
  SignalPhase phase(S state, std::optional<double> end_s) const {
    SignalPhase p;
    p.signal_group = 4;
    p.current.state = state;
    if (end_s) {
      p.current.likely_time = at(*end_s);
    }
    p.received_at = clk.wall_now();
    return p;
  }
  RlvwAssessment decide(double d, double v, const SignalPhase& p) const {
    return assess_rlvw(d, v, predict_phases(p, clk.wall_now()), cfg);
  }
};

TEST_F(RlvwTest, StoppingDistance) {
  // 60 km/h: 16.667 m in the reaction second + 16.667² / 6 = 46.296 m braking.
  EXPECT_NEAR(stopping_distance_m(60 * kKmh, cfg), 62.963, 0.001);
  // 30 km/h: 8.333 + 11.574.
  EXPECT_NEAR(stopping_distance_m(30 * kKmh, cfg), 19.907, 0.001);
  EXPECT_NEAR(stopping_distance_m(15.0, cfg), 52.5, 1e-9);  // 15 + 225 / 6
  EXPECT_EQ(stopping_distance_m(0.0, cfg), 0.0);
}

TEST_F(RlvwTest, SixtyAtFortyMetresRedInOneSecondWarns) {
  // Amber now, red in 1 s; arrival 40 / 16.667 = 2.4 s: red. D 62.96 m > 40 m.
  const auto a = decide(40.0, 60 * kKmh, phase(S::kProtectedClearance, 1.0));
  EXPECT_FALSE(a.can_stop);
  ASSERT_TRUE(a.arrival_s);
  EXPECT_NEAR(*a.arrival_s, 2.4, 1e-9);
  EXPECT_EQ(a.state_on_arrival, S::kStopAndRemain);
  ASSERT_TRUE(a.time_to_red_s);
  EXPECT_NEAR(*a.time_to_red_s, 1.0, 1e-3);
  EXPECT_TRUE(a.warn);
}

TEST_F(RlvwTest, ThirtyAtFortyMetresCanStop) {
  // D 19.9 m < 40 m: the driver can still stop comfortably, though red comes first.
  const auto a = decide(40.0, 30 * kKmh, phase(S::kProtectedClearance, 1.0));
  EXPECT_TRUE(a.can_stop);
  EXPECT_TRUE(a.red_on_arrival);
  EXPECT_FALSE(a.warn);
}

TEST_F(RlvwTest, GreenLongEnoughToPass) {
  // Green for 5 s more; arrival at 2.4 s.
  const auto a = decide(40.0, 60 * kKmh, phase(S::kProtectedMovementAllowed, 5.0));
  EXPECT_EQ(a.state_on_arrival, S::kProtectedMovementAllowed);
  EXPECT_FALSE(a.warn);
}

TEST_F(RlvwTest, AmberWithStoppingPossibleIsNoWarning) {
  const auto a = decide(40.0, 30 * kKmh, phase(S::kProtectedClearance, 3.0));
  EXPECT_TRUE(a.can_stop);
  EXPECT_FALSE(a.warn);
}

TEST_F(RlvwTest, DistanceBoundaryEitherSide) {
  // 15 m/s: D = 52.5 m. Red for 30 s more.
  const SignalPhase red = phase(S::kStopAndRemain, 30.0);
  EXPECT_TRUE(decide(52.4, 15.0, red).warn);
  EXPECT_FALSE(decide(52.5, 15.0, red).warn) << "stopping exactly at the line is a stop";
  EXPECT_FALSE(decide(52.6, 15.0, red).warn);
}

TEST_F(RlvwTest, TimeBoundaryEitherSide) {
  // 15 m/s at 45 m: arrival 3.0 s, D 52.5 m > 45 m. Amber now (onset not known: now).
  EXPECT_TRUE(decide(45.0, 15.0, phase(S::kProtectedClearance, 2.9)).warn)
      << "red 0.1 s before the arrival";
  const auto on_amber = decide(45.0, 15.0, phase(S::kProtectedClearance, 3.1));
  EXPECT_EQ(on_amber.state_on_arrival, S::kProtectedClearance);
  EXPECT_FALSE(on_amber.warn) << "arrives 0.1 s before red, on an amber it could not stop for";
  // Red turning green: green from 2.9 s is on time for the arrival at 3.0 s, from 3.1 s not.
  EXPECT_FALSE(decide(45.0, 15.0, phase(S::kStopAndRemain, 2.9)).warn);
  EXPECT_TRUE(decide(45.0, 15.0, phase(S::kStopAndRemain, 3.1)).warn);
}

TEST_F(RlvwTest, AmberCountsAsRedWhenStoppingWasPossibleAtItsOnset) {
  // Amber came on 2 s ago; at 15 m/s the car was 45 + 30 = 75 m away then, D 52.5 m: it could
  // have stopped, so arriving on this amber (red at 3.1 s, arrival 3.0 s) is running a red.
  SignalPhase p = phase(S::kProtectedClearance, 3.1);
  p.current.start_time = at(-2.0);
  EXPECT_TRUE(decide(45.0, 15.0, p).red_on_arrival);
  EXPECT_TRUE(decide(45.0, 15.0, p).warn);
  // Amber 0.4 s ago: 45 + 6 = 51 m < 52.5 m then: the dilemma zone, passing on amber is right.
  p.current.start_time = at(-0.4);
  EXPECT_FALSE(decide(45.0, 15.0, p).warn);
  // An amber still to come (green ends in 1 s) that the car cannot stop for then either.
  EXPECT_FALSE(decide(45.0, 15.0, phase(S::kProtectedMovementAllowed, 1.0)).warn);
}

TEST_F(RlvwTest, WhichTimeRedEndsAt) {
  // 15 m/s at 45 m, arrival 3 s, cannot stop. Red with minEndTime 1 s, likelyTime 4 s: the
  // likely time decides, red on arrival.
  SignalPhase p = phase(S::kStopAndRemain, 4.0);
  p.current.min_end_time = at(1.0);
  EXPECT_TRUE(decide(45.0, 15.0, p).warn);
  // No likelyTime: a red is taken to last until its maxEndTime (the safe side) ...
  p.current.likely_time.reset();
  p.current.max_end_time = at(4.0);
  EXPECT_TRUE(decide(45.0, 15.0, p).warn);
  p.current.max_end_time = at(2.0);
  EXPECT_FALSE(decide(45.0, 15.0, p).warn) << "green by 2 s at the latest";
  // ... and with only minEndTime it may last: red persists.
  p.current.max_end_time.reset();
  EXPECT_TRUE(decide(45.0, 15.0, p).warn);
}

TEST_F(RlvwTest, WhichTimeGreenEndsAt) {
  // Green with only minEndTime 1 s: it may end then (the safe side) — amber on arrival, which
  // the car could not stop for at its onset (45 − 15 = 30 m < 52.5 m): no warning, but the
  // arrival state says amber.
  SignalPhase p = phase(S::kProtectedMovementAllowed, std::nullopt);
  p.current.min_end_time = at(1.0);
  const auto a = decide(45.0, 15.0, p);
  EXPECT_EQ(a.state_on_arrival, S::kProtectedClearance);
  EXPECT_FALSE(a.warn);
  // Green, amber and red listed by the SPAT (state-time-speed): green until 0.5 s, amber until
  // 2.5 s, red until 30 s. Arrival at 3 s: red.
  SignalPhase listed = phase(S::kProtectedMovementAllowed, 0.5);
  listed.upcoming = {{S::kProtectedClearance, std::nullopt, std::nullopt, std::nullopt, at(2.5)},
                     {S::kStopAndRemain, std::nullopt, std::nullopt, std::nullopt, at(30.0)}};
  const auto b = decide(45.0, 15.0, listed);
  EXPECT_EQ(b.state_on_arrival, S::kStopAndRemain);
  EXPECT_TRUE(b.warn);
  ASSERT_TRUE(b.time_to_red_s);
  EXPECT_NEAR(*b.time_to_red_s, 2.5, 1e-3);
}

TEST_F(RlvwTest, UnknownTiming) {
  // Red with no times: it lasts, so a car that cannot stop is warned.
  EXPECT_TRUE(decide(45.0, 15.0, phase(S::kStopAndRemain, std::nullopt)).warn);
  EXPECT_TRUE(decide(45.0, 15.0, phase(S::kStopThenProceed, std::nullopt)).warn)
      << "flashing red: stop first";
  // Green with no times: nothing says it will end.
  EXPECT_FALSE(decide(45.0, 15.0, phase(S::kProtectedMovementAllowed, std::nullopt)).warn);
  // Dark, unavailable, flashing amber: no stop obligation known.
  EXPECT_FALSE(decide(45.0, 15.0, phase(S::kDark, std::nullopt)).warn);
  EXPECT_FALSE(decide(45.0, 15.0, phase(S::kUnavailable, std::nullopt)).warn);
  EXPECT_FALSE(decide(45.0, 15.0, phase(S::kCautionConflictingTraffic, std::nullopt)).warn);
}

TEST_F(RlvwTest, StandingOrPastTheLineIsNoWarning) {
  const SignalPhase red = phase(S::kStopAndRemain, 30.0);
  EXPECT_FALSE(decide(0.5, 0.0, red).warn);
  EXPECT_FALSE(decide(-1.0, 15.0, red).warn);
  EXPECT_TRUE(decide(0.5, 1.0, red).warn) << "rolling over the line at red: 1 m/s needs 1.17 m";
}

TEST_F(RlvwTest, ADriverAlreadyBrakingHasReacted) {
  // 15 m/s at 45 m, red: D = 52.5 m > 45 m warns a driver who has not reacted yet ...
  const SignalPhase red = phase(S::kStopAndRemain, 30.0);
  const auto pending = [&](std::optional<double> accel) {
    return assess_rlvw(45.0, 15.0, predict_phases(red, clk.wall_now()), cfg, accel);
  };
  EXPECT_TRUE(pending(std::nullopt).warn);
  // ... not one braking at 3 m/s², who stands after 225 / 6 = 37.5 m ...
  EXPECT_TRUE(pending(-3.0).stopping);
  EXPECT_FALSE(pending(-3.0).warn);
  // ... nor at 2.5 m/s² (45 m exactly) ...
  EXPECT_FALSE(pending(-2.5).warn);
  // ... but at 2 m/s² the car needs 56.25 m: it will be over the line.
  EXPECT_TRUE(pending(-2.0).warn);
  // Below 0.3 m/s² it is rolling, not braking; speeding up is not braking either.
  EXPECT_FALSE(pending(-0.2).stopping);
  EXPECT_TRUE(pending(-0.2).warn);
  EXPECT_TRUE(pending(1.0).warn);
}

// --- the state machine ---------------------------------------------------------------------

class RlvwMachineTest : public RlvwTest {
 protected:
  RlvwSituation situation(double d, double v, const SignalPhase& p) const {
    RlvwSituation s;
    s.intersection_id = 7;
    s.lane_id = 1;
    s.signal_group = p.signal_group;
    s.distance_to_stop_line_m = d;
    s.speed_mps = v;
    s.signal_fresh = true;
    s.timeline = predict_phases(p, clk.wall_now());
    return s;
  }
  Rlvw rlvw{clk, cfg};
};

TEST_F(RlvwMachineTest, RaisedUpdatedThenClearedWhenPassing) {
  const SignalPhase red = phase(S::kStopAndRemain, 30.0);
  auto s = situation(40.0, 15.0, red);
  const auto raised = rlvw.evaluate(1001, &s);
  ASSERT_TRUE(raised);
  EXPECT_EQ(raised->event, RlvwEvent::kRaised);
  EXPECT_EQ(raised->station_id, 1001u);
  EXPECT_EQ(raised->intersection_id, 7);
  EXPECT_EQ(raised->lane_id, 1);
  EXPECT_EQ(raised->signal_group, 4);
  EXPECT_EQ(raised->clear_reason, RlvwClearReason::kNone);
  EXPECT_NEAR(raised->stopping_distance_m, 52.5, 1e-9);
  EXPECT_EQ(raised->time_to_red_s, 0.0);
  EXPECT_EQ(raised->raised_at, clk.wall_now());

  clk.advance(100ms);
  s = situation(38.5, 15.0, red);
  const auto updated = rlvw.evaluate(1001, &s);
  ASSERT_TRUE(updated);
  EXPECT_EQ(updated->event, RlvwEvent::kUpdated);
  EXPECT_EQ(updated->raised_at, raised->raised_at);
  EXPECT_EQ(updated->updated_at, clk.wall_now());
  EXPECT_DOUBLE_EQ(updated->distance_to_stop_line_m, 38.5);

  clk.advance(2600ms);
  s = situation(-0.5, 15.0, red);
  const auto cleared = rlvw.evaluate(1001, &s);
  ASSERT_TRUE(cleared);
  EXPECT_EQ(cleared->event, RlvwEvent::kCleared);
  EXPECT_EQ(cleared->clear_reason, RlvwClearReason::kPassed);
  EXPECT_FALSE(rlvw.active());
  EXPECT_FALSE(rlvw.evaluate(1001, &s)) << "nothing more once cleared";
}

TEST_F(RlvwMachineTest, BrakingKeepsTheWarningUntilStopped) {
  const SignalPhase red = phase(S::kStopAndRemain, 30.0);
  auto s = situation(40.0, 15.0, red);
  ASSERT_TRUE(rlvw.evaluate(1001, &s));
  // Braking hard: 5 m/s at 10 m can stop (D 5 + 4.17), still red on arrival: stays up.
  s = situation(10.0, 5.0, red);
  const auto still = rlvw.evaluate(1001, &s);
  ASSERT_TRUE(still);
  EXPECT_EQ(still->event, RlvwEvent::kUpdated);
  s = situation(2.0, 0.2, red);
  const auto stopped = rlvw.evaluate(1001, &s);
  ASSERT_TRUE(stopped);
  EXPECT_EQ(stopped->clear_reason, RlvwClearReason::kStopped);
}

TEST_F(RlvwMachineTest, ClearedWhenTheLightWillBeGreen) {
  auto s = situation(40.0, 15.0, phase(S::kStopAndRemain, 30.0));
  ASSERT_TRUE(rlvw.evaluate(1001, &s));
  // The controller shortens the red: green in 1 s, the arrival at 2.6 s is on green.
  s = situation(39.0, 15.0, phase(S::kStopAndRemain, 1.0));
  const auto c = rlvw.evaluate(1001, &s);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->clear_reason, RlvwClearReason::kGreen);
}

TEST_F(RlvwMachineTest, ClearedWhenLeavingTheLaneOrWhenStale) {
  const SignalPhase red = phase(S::kStopAndRemain, 30.0);
  auto s = situation(40.0, 15.0, red);
  ASSERT_TRUE(rlvw.evaluate(1001, &s));
  const auto left = rlvw.evaluate(1001, nullptr);
  ASSERT_TRUE(left);
  EXPECT_EQ(left->clear_reason, RlvwClearReason::kLeftLane);
  EXPECT_DOUBLE_EQ(left->distance_to_stop_line_m, 40.0) << "the last known on its lane";

  ASSERT_TRUE(rlvw.evaluate(1001, &s));
  auto other = s;
  other.lane_id = 2;
  EXPECT_EQ(rlvw.evaluate(1001, &other)->clear_reason, RlvwClearReason::kLeftLane);

  ASSERT_TRUE(rlvw.evaluate(1001, &s));
  s.signal_fresh = false;
  EXPECT_EQ(rlvw.evaluate(1001, &s)->clear_reason, RlvwClearReason::kStale);
  EXPECT_FALSE(rlvw.evaluate(1001, &s)) << "no warning on stale signal data";
}

}  // namespace
}  // namespace tb::its::apps::signal
