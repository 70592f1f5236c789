#include <gtest/gtest.h>

#include "common/geodesy/local_frame.hpp"
#include "its-station/facilities/cam_rules.hpp"

namespace tb::its::facilities {
namespace {

using namespace std::chrono_literals;

const geodesy::LocalFrame kFrame{{48.0, 11.0, 500.0}};

PositionFix at(double east, double north, double heading, double speed) {
  PositionFix f;
  const auto g = kFrame.to_geodetic({east, north, 0.0});
  f.latitude_deg = g.latitude_deg;
  f.longitude_deg = g.longitude_deg;
  f.heading_deg = heading;
  f.speed_mps = speed;
  return f;
}

clock::SteadyTime t(std::int64_t ms) {
  return clock::SteadyTime{std::chrono::milliseconds{ms}};
}

TEST(CamRules, FirstCamIsAlwaysDue) {
  CamRules r({}, {});
  EXPECT_EQ(r.check(t(0), at(0, 0, 0, 0)), CamTrigger::kFirst);
  EXPECT_FALSE(r.next_time_due());
}

TEST(CamRules, ThresholdsAreStrict) {
  CamRules r({}, {});
  r.generated(t(0), at(0, 0, 10, 5), CamTrigger::kFirst);
  EXPECT_EQ(r.check(t(200), at(0, 0, 13.9, 5.4)), CamTrigger::kNone);
  EXPECT_EQ(r.check(t(200), at(0, 0, 14.1, 5)), CamTrigger::kHeading);
  EXPECT_EQ(r.check(t(200), at(0, 3.9, 10, 5)), CamTrigger::kNone);
  EXPECT_EQ(r.check(t(200), at(0, 4.1, 10, 5)), CamTrigger::kPosition);
  EXPECT_EQ(r.check(t(200), at(2.9, 2.9, 10, 5)), CamTrigger::kPosition);  // 4.1 m diagonal
  EXPECT_EQ(r.check(t(200), at(0, 0, 10, 5.6)), CamTrigger::kSpeed);
  EXPECT_EQ(r.check(t(200), at(0, 0, 10, 4.4)), CamTrigger::kSpeed);
}

TEST(CamRules, HeadingWrapsAtNorth) {
  CamRules r({}, {});
  r.generated(t(0), at(0, 0, 358.0, 5), CamTrigger::kFirst);
  EXPECT_EQ(r.check(t(200), at(0, 0, 1.0, 5)), CamTrigger::kNone);  // 3° apart, not 357°
  EXPECT_EQ(r.check(t(200), at(0, 0, 2.5, 5)), CamTrigger::kHeading);
}

TEST(CamRules, NothingBeforeTGenCamDcc) {
  CamRules r({}, {});
  r.generated(t(0), at(0, 0, 0, 0), CamTrigger::kFirst);
  EXPECT_EQ(r.check(t(99), at(50, 0, 90, 30)), CamTrigger::kNone);
  EXPECT_EQ(r.check(t(100), at(50, 0, 90, 30)), CamTrigger::kHeading);
}

TEST(CamRules, TGenCamFollowsDynamicCamsThenReturnsAfterNGenCam) {
  CamRules r({}, {});
  const auto f = at(0, 0, 0, 0);
  r.generated(t(0), f, CamTrigger::kFirst);
  EXPECT_EQ(r.T_GenCam(), 1000ms);
  r.generated(t(250), f, CamTrigger::kSpeed);
  EXPECT_EQ(r.T_GenCam(), 250ms);
  EXPECT_EQ(*r.next_time_due(), t(500));
  EXPECT_EQ(r.check(t(499), f), CamTrigger::kNone);
  EXPECT_EQ(r.check(t(500), f), CamTrigger::kTime);
  r.generated(t(500), f, CamTrigger::kTime);
  r.generated(t(750), f, CamTrigger::kTime);
  EXPECT_EQ(r.T_GenCam(), 250ms);
  r.generated(t(1000), f, CamTrigger::kTime);  // the third in a row
  EXPECT_EQ(r.T_GenCam(), 1000ms);
  // A dynamic CAM after more than T_GenCamMax is clamped to it.
  r.generated(t(3000), f, CamTrigger::kHeading);
  EXPECT_EQ(r.T_GenCam(), 1000ms);
}

TEST(CamRules, DynamicCamRestartsTheNGenCamCount) {
  CamRules r({}, {});
  const auto f = at(0, 0, 0, 0);
  r.generated(t(0), f, CamTrigger::kFirst);
  r.generated(t(300), f, CamTrigger::kPosition);
  r.generated(t(600), f, CamTrigger::kTime);
  r.generated(t(900), f, CamTrigger::kTime);
  r.generated(t(1100), f, CamTrigger::kPosition);  // T_GenCam := 200, count restarts
  r.generated(t(1300), f, CamTrigger::kTime);
  r.generated(t(1500), f, CamTrigger::kTime);
  EXPECT_EQ(r.T_GenCam(), 200ms);
  r.generated(t(1700), f, CamTrigger::kTime);
  EXPECT_EQ(r.T_GenCam(), 1000ms);
}

TEST(CamRules, LowFrequencyEvery500ms) {
  CamRules r({}, {});
  EXPECT_TRUE(r.low_frequency_due(t(0)));
  r.low_frequency_sent(t(0));
  EXPECT_FALSE(r.low_frequency_due(t(499)));
  EXPECT_TRUE(r.low_frequency_due(t(500)));
  r.reset();
  EXPECT_TRUE(r.low_frequency_due(t(501)));
}

TEST(CamRules, FixedPolicyIgnoresDynamics) {
  scenario::CamPolicy p;
  p.kind = scenario::CamPolicy::Kind::kFixed;
  p.period_ms = 250.0;
  CamRules r({}, p);
  r.generated(t(0), at(0, 0, 0, 0), CamTrigger::kFirst);
  EXPECT_EQ(r.check(t(200), at(100, 0, 90, 30)), CamTrigger::kNone);
  EXPECT_EQ(r.check(t(250), at(0, 0, 0, 0)), CamTrigger::kFixed);
  EXPECT_EQ(*r.next_time_due(), t(250));
}

TEST(CamRules, DistanceIsGeodesic) {
  // 0.001° of latitude near 48° N is 111.2 m (WGS84 meridian arc).
  EXPECT_NEAR(distance_m(48.0, 11.0, 48.001, 11.0), 111.2, 0.1);
  EXPECT_NEAR(distance_m(48.0, 11.0, 48.0, 11.0), 0.0, 1e-9);
}

}  // namespace
}  // namespace tb::its::facilities
