// GLOSA against worked cases: d / t over the green window with a 1 s margin, clipped to 20 km/h
// and the speed limit; and a check that driving any advised speed arrives inside the green the
// test itself scheduled.
#include "its-station/apps/signal/glosa.hpp"

#include <gtest/gtest.h>

#include <chrono>

#include "common/clock/clock.hpp"

namespace tb::its::apps::signal {
namespace {

using S = MovementPhaseState;
constexpr double kKmh = 1.0 / 3.6;

class GlosaTest : public ::testing::Test {
 protected:
  clock::ManualClock clk;
  GlosaConfig cfg;

  clock::WallTime at(double s) const {
    return clk.wall_now() +
           std::chrono::duration_cast<clock::Duration>(std::chrono::duration<double>(s));
  }
  static MovementEvent event(S state, clock::WallTime likely) {
    MovementEvent e;
    e.state = state;
    e.likely_time = likely;
    return e;
  }
  /// Red until @p green_s, green until @p amber_s (0: no end known), then amber 3 s and red.
  std::vector<PhaseInterval> red_then_green(double green_s, double amber_s) const {
    SignalPhase p;
    p.current = event(S::kStopAndRemain, at(green_s));
    if (amber_s > 0.0) {
      p.upcoming = {event(S::kProtectedMovementAllowed, at(amber_s)),
                    event(S::kProtectedClearance, at(amber_s + 3.0))};
    }
    return predict_phases(p, clk.wall_now());
  }
};

TEST_F(GlosaTest, RedThenAGreenWindow) {
  // Green from 10 s to 30 s, 200 m: arrive within [11 s, 29 s] → v ∈ [200/29, 200/11] =
  // [6.90, 18.18] m/s, capped at 50 km/h = 13.89 m/s.
  const auto a = glosa_advice(200.0, std::nullopt, red_then_green(10.0, 30.0), cfg);
  ASSERT_TRUE(a);
  EXPECT_NEAR(a->min_speed_mps, 200.0 / 29.0, 1e-3);
  EXPECT_NEAR(a->max_speed_mps, 50 * kKmh, 1e-9);
  EXPECT_NEAR(a->window.start_s, 10.0, 1e-3);
  EXPECT_NEAR(a->window.end_s, 30.0, 1e-3);
  // A 70 km/h lane limit lets the top of the range reach 200/11 m/s.
  const auto fast = glosa_advice(200.0, 70 * kKmh, red_then_green(10.0, 30.0), cfg);
  ASSERT_TRUE(fast);
  EXPECT_NEAR(fast->max_speed_mps, 200.0 / 11.0, 1e-3);
}

TEST_F(GlosaTest, GreenOfUnknownLengthAfterRed) {
  // Red for 10 s more, then green with no end known: arrive from 11 s on, any slower speed.
  const auto a = glosa_advice(100.0, std::nullopt, red_then_green(10.0, 0.0), cfg);
  ASSERT_TRUE(a);
  EXPECT_NEAR(a->max_speed_mps, 100.0 / 11.0, 1e-3);
  EXPECT_NEAR(a->min_speed_mps, 20 * kKmh, 1e-9);
}

TEST_F(GlosaTest, GreenNowWithoutEnd) {
  SignalPhase p;
  p.current.state = S::kProtectedMovementAllowed;
  const auto a = glosa_advice(100.0, 60 * kKmh, predict_phases(p, clk.wall_now()), cfg);
  ASSERT_TRUE(a);
  EXPECT_NEAR(a->min_speed_mps, 20 * kKmh, 1e-9);
  EXPECT_NEAR(a->max_speed_mps, 60 * kKmh, 1e-9);
}

TEST_F(GlosaTest, NoRangeWithinTheLimits) {
  // Green for 5 s more, 100 m away: within 4 s would need 25 m/s > 13.9 m/s; what follows is an
  // amber of unknown length. No advice.
  SignalPhase p;
  p.current = event(S::kProtectedMovementAllowed, at(5.0));
  EXPECT_FALSE(glosa_advice(100.0, std::nullopt, predict_phases(p, clk.wall_now()), cfg));
  // The next green is listed, 40 s to 60 s: 100 m in 41..59 s is 1.7..2.4 m/s, below 20 km/h.
  p.upcoming = {event(S::kProtectedClearance, at(8.0)), event(S::kStopAndRemain, at(40.0)),
                event(S::kProtectedMovementAllowed, at(60.0))};
  EXPECT_FALSE(glosa_advice(100.0, std::nullopt, predict_phases(p, clk.wall_now()), cfg));
  // From 400 m the second window is reachable: 400/59 = 6.78 .. 400/41 = 9.76 m/s.
  const auto far = glosa_advice(400.0, std::nullopt, predict_phases(p, clk.wall_now()), cfg);
  ASSERT_TRUE(far);
  EXPECT_NEAR(far->min_speed_mps, 400.0 / 59.0, 1e-3);
  EXPECT_NEAR(far->max_speed_mps, 400.0 / 41.0, 1e-3);
  EXPECT_FALSE(glosa_advice(0.0, std::nullopt, predict_phases(p, clk.wall_now()), cfg));
  EXPECT_FALSE(glosa_advice(-3.0, std::nullopt, predict_phases(p, clk.wall_now()), cfg));
}

TEST_F(GlosaTest, WindowShorterThanTheMarginsIsSkipped) {
  // Green from 10 s to 11.5 s: less than 1 s margin at each end.
  EXPECT_FALSE(glosa_advice(100.0, std::nullopt, red_then_green(10.0, 11.5), cfg));
}

TEST_F(GlosaTest, FollowingTheAdviceArrivesOnGreen) {
  struct Case {
    double distance, green_from, green_until;
  };
  for (const Case c : {Case{200.0, 10.0, 30.0}, Case{150.0, 4.0, 24.0}, Case{80.0, 2.0, 12.0},
                       Case{300.0, 25.0, 45.0}, Case{60.0, 0.5, 20.0}}) {
    const auto a =
        glosa_advice(c.distance, std::nullopt, red_then_green(c.green_from, c.green_until), cfg);
    ASSERT_TRUE(a) << c.distance;
    for (int i = 0; i <= 10; ++i) {
      const double v = a->min_speed_mps + (a->max_speed_mps - a->min_speed_mps) * i / 10.0;
      // A constant-speed arrival: the front reaches the line after d / v.
      const double arrival = c.distance / v;
      EXPECT_GE(arrival, c.green_from + 1.0 - 1e-6) << c.distance << " at " << v;
      EXPECT_LE(arrival, c.green_until - 1.0 + 1e-6) << c.distance << " at " << v;
      EXPECT_GE(v, 20 * kKmh - 1e-9);
      EXPECT_LE(v, 50 * kKmh + 1e-9);
    }
  }
}

}  // namespace
}  // namespace tb::its::apps::signal
