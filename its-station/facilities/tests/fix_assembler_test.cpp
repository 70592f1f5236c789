#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "its-station/facilities/gpsd_report.hpp"
#include "its-station/facilities/position.hpp"

namespace tb::its::facilities {
namespace {

using namespace std::chrono_literals;

GpsdReport tpv(double lat, double lon, double speed, double track) {
  GpsdReport r;
  r.mode = GpsdMode::k3D;
  r.time = clock::WallTime{std::chrono::seconds{1'700'000'000}};
  r.latitude_deg = lat;
  r.longitude_deg = lon;
  r.altitude_hae_m = 120.0;
  r.speed_mps = speed;
  r.track_deg = track;
  return r;
}

TEST(FixAssembler, TpvWithFixBecomesFix) {
  FixAssembler a;
  PositionFix f;
  auto r = tpv(48.1, 11.5, 10.0, 90.0);
  r.eph_m = 17.1;
  ASSERT_EQ(a.on_report(r, clock::SteadyTime{5s}, f), FixAssembler::Outcome::kFix);
  EXPECT_DOUBLE_EQ(f.latitude_deg, 48.1);
  EXPECT_DOUBLE_EQ(f.longitude_deg, 11.5);
  EXPECT_EQ(f.time, *r.time);
  EXPECT_EQ(f.received, clock::SteadyTime{5s});
  ASSERT_TRUE(f.altitude_m);
  EXPECT_DOUBLE_EQ(*f.altitude_m, 120.0);
  ASSERT_TRUE(f.position_confidence);
  EXPECT_DOUBLE_EQ(f.position_confidence->semi_major_m, 17.1);
  EXPECT_DOUBLE_EQ(f.position_confidence->semi_minor_m, 17.1);
  // No SKY yet: HDOP recovered from eph (17.1 / 19 = 0.9).
  ASSERT_TRUE(f.speed_confidence_mps);
  EXPECT_NEAR(*f.speed_confidence_mps, 0.9 * 0.05 * 1.959964, 1e-9);
  ASSERT_TRUE(f.heading_confidence_deg);
  EXPECT_NEAR(*f.heading_confidence_deg,
              std::atan2(*f.speed_confidence_mps, 10.0) * 180.0 / 3.141592653589793, 1e-9);
}

TEST(FixAssembler, NoFixModesAreLosses) {
  FixAssembler a;
  PositionFix f;
  GpsdReport r;
  r.mode = GpsdMode::kNoFix;
  EXPECT_EQ(a.on_report(r, {}, f), FixAssembler::Outcome::kLoss);
  r.mode = GpsdMode::kNotSeen;
  EXPECT_EQ(a.on_report(r, {}, f), FixAssembler::Outcome::kLoss);
}

TEST(FixAssembler, ReportsWithoutModeOrPositionAreIgnored) {
  FixAssembler a;
  PositionFix f;
  GpsdReport sky;
  sky.hdop = 1.3;
  EXPECT_EQ(a.on_report(sky, {}, f), FixAssembler::Outcome::kNone);
  auto r = tpv(kNaN, 11.5, 1.0, 0.0);
  EXPECT_EQ(a.on_report(r, {}, f), FixAssembler::Outcome::kNone);
  r = tpv(48.0, 11.5, 1.0, 0.0);
  r.time.reset();
  EXPECT_EQ(a.on_report(r, {}, f), FixAssembler::Outcome::kNone);
  r = tpv(91.0, 11.5, 1.0, 0.0);
  EXPECT_EQ(a.on_report(r, {}, f), FixAssembler::Outcome::kNone);
}

TEST(FixAssembler, TwoDimensionalFixHasNoAltitude) {
  FixAssembler a;
  PositionFix f;
  auto r = tpv(48.0, 11.0, 0.0, 0.0);
  r.mode = GpsdMode::k2D;
  r.epv_m = 3.0;
  ASSERT_EQ(a.on_report(r, {}, f), FixAssembler::Outcome::kFix);
  EXPECT_FALSE(f.altitude_m);
  EXPECT_FALSE(f.altitude_confidence_m);
}

TEST(FixAssembler, PerAxisErrorsGiveAxisAlignedEllipse) {
  FixAssembler a;
  PositionFix f;
  auto r = tpv(48.0, 11.0, 5.0, 10.0);
  r.eph_m = 20.0;
  r.epx_m = 4.0;  // east-west
  r.epy_m = 9.0;  // north-south, the larger: major axis points north
  ASSERT_EQ(a.on_report(r, {}, f), FixAssembler::Outcome::kFix);
  EXPECT_DOUBLE_EQ(f.position_confidence->semi_major_m, 9.0);
  EXPECT_DOUBLE_EQ(f.position_confidence->semi_minor_m, 4.0);
  EXPECT_DOUBLE_EQ(f.position_confidence->orientation_deg, 0.0);
  r.epx_m = 12.0;
  ASSERT_EQ(a.on_report(r, {}, f), FixAssembler::Outcome::kFix);
  EXPECT_DOUBLE_EQ(f.position_confidence->semi_major_m, 12.0);
  EXPECT_DOUBLE_EQ(f.position_confidence->orientation_deg, 90.0);
}

TEST(FixAssembler, FreshGstWinsAndIsScaledTo95Percent) {
  FixAssembler a;
  PositionFix f;
  GpsdReport gst;
  gst.gst = GpsdGst{2.0, 1.0, 200.0, 3.0};
  EXPECT_EQ(a.on_report(gst, clock::SteadyTime{10s}, f), FixAssembler::Outcome::kNone);
  auto r = tpv(48.0, 11.0, 5.0, 10.0);
  r.epx_m = 4.0;
  r.epy_m = 9.0;
  ASSERT_EQ(a.on_report(r, clock::SteadyTime{10s} + 100ms, f), FixAssembler::Outcome::kFix);
  EXPECT_NEAR(f.position_confidence->semi_major_m, 2.0 * 2.447747, 1e-9);
  EXPECT_NEAR(f.position_confidence->semi_minor_m, 1.0 * 2.447747, 1e-9);
  EXPECT_NEAR(f.position_confidence->orientation_deg, 20.0, 1e-9);  // 200° is the same axis
  // Two seconds later the GST describes an old epoch: back to gpsd's per-axis estimate.
  ASSERT_EQ(a.on_report(r, clock::SteadyTime{12s}, f), FixAssembler::Outcome::kFix);
  EXPECT_DOUBLE_EQ(f.position_confidence->semi_major_m, 9.0);
}

TEST(FixAssembler, SkyHdopDrivesSpeedConfidenceNotEps) {
  FixAssembler a;
  PositionFix f;
  GpsdReport sky;
  sky.hdop = 2.0;
  a.on_report(sky, {}, f);
  auto r = tpv(48.0, 11.0, 20.0, 10.0);
  r.eph_m = 5.0;  // would say HDOP 0.26; the SKY's HDOP is what the receiver reported
  ASSERT_EQ(a.on_report(r, {}, f), FixAssembler::Outcome::kFix);
  EXPECT_NEAR(*f.speed_confidence_mps, 2.0 * 0.05 * 1.959964, 1e-12);
}

TEST(FixAssembler, HeadingConfidenceGrowsAtLowSpeed) {
  const double sc = speed_confidence_95(1.0);
  EXPECT_LT(heading_confidence_95(30.0, sc), heading_confidence_95(3.0, sc));
  EXPECT_LT(heading_confidence_95(30.0, sc), 0.5);
  EXPECT_DOUBLE_EQ(heading_confidence_95(0.1, sc), 180.0);
  EXPECT_DOUBLE_EQ(heading_confidence_95(kNaN, sc), 180.0);
}

TEST(FixAssembler, NoErrorEstimatesMeansNoConfidences) {
  FixAssembler a;
  PositionFix f;
  auto r = tpv(48.0, 11.0, 5.0, 370.0);
  ASSERT_EQ(a.on_report(r, {}, f), FixAssembler::Outcome::kFix);
  EXPECT_FALSE(f.position_confidence);
  EXPECT_FALSE(f.speed_confidence_mps);
  EXPECT_FALSE(f.heading_confidence_deg);
  EXPECT_NEAR(*f.heading_deg, 10.0, 1e-9);  // wrapped into [0, 360)
}

TEST(PositionProvider, AnnouncesLossAndRegainOnce) {
  InjectedPositionProvider p;
  std::vector<bool> avail;
  int fixes = 0;
  p.on_availability([&](bool a) { avail.push_back(a); });
  p.on_fix([&](const PositionFix&) { ++fixes; });
  PositionFix f;
  p.inject(f);
  p.inject(f);
  p.lose_fix();
  p.lose_fix();
  EXPECT_FALSE(p.current());
  p.inject(f);
  EXPECT_EQ(fixes, 3);
  EXPECT_EQ(avail, (std::vector<bool>{true, false, true}));
}

}  // namespace
}  // namespace tb::its::facilities
