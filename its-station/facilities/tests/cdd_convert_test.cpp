#include <gtest/gtest.h>

#include <cmath>

#include "its-station/facilities/cdd_convert.hpp"
#include "its-station/facilities/its_time.hpp"

namespace tb::its::facilities {
namespace {

namespace m = messages;

TEST(CddConvert, PositionRoundsToTenthMicrodegree) {
  EXPECT_EQ(cdd::latitude(48.12345678), 481234568);
  EXPECT_EQ(cdd::longitude(-11.00000004), -110000000);
  EXPECT_EQ(cdd::latitude(91.0), m::kLatitudeUnavailable);
  EXPECT_EQ(cdd::longitude(std::nan("")), m::kLongitudeUnavailable);
  EXPECT_FALSE(cdd::latitude_deg(m::kLatitudeUnavailable));
  EXPECT_DOUBLE_EQ(*cdd::latitude_deg(481234568), 48.1234568);
}

TEST(CddConvert, ConfidenceEllipseRoundsUpAndSaturates) {
  auto e = cdd::confidence_ellipse(PositionFix::Ellipse{3.001, 0.0001, 179.96});
  EXPECT_EQ(e.semiMajorConfidence, 301);
  EXPECT_EQ(e.semiMinorConfidence, 1);
  EXPECT_EQ(e.semiMajorOrientation, 1800);
  e = cdd::confidence_ellipse(PositionFix::Ellipse{50.0, 45.0, 0.0});
  EXPECT_EQ(e.semiMajorConfidence, m::kSemiAxisLengthOutOfRange);
  e = cdd::confidence_ellipse(std::nullopt);
  EXPECT_EQ(e.semiMajorConfidence, m::kSemiAxisLengthUnavailable);
  EXPECT_EQ(e.semiMajorOrientation, m::kHeadingValueUnavailable);
}

TEST(CddConvert, HeadingWrapsAndConfidenceBands) {
  EXPECT_EQ(cdd::heading_value(359.97), 0);
  EXPECT_EQ(cdd::heading_value(-90.0), 2700);
  EXPECT_EQ(cdd::heading_value(std::nullopt), m::kHeadingValueUnavailable);
  EXPECT_EQ(cdd::heading_confidence(0.01), 1);
  EXPECT_EQ(cdd::heading_confidence(12.5), 125);
  EXPECT_EQ(cdd::heading_confidence(12.51), m::kHeadingConfidenceOutOfRange);
  EXPECT_EQ(cdd::heading_confidence(std::nullopt), m::kHeadingConfidenceUnavailable);
  // No heading: no confidence either.
  EXPECT_EQ(cdd::heading(std::nullopt, 1.0).headingConfidence, m::kHeadingConfidenceUnavailable);
}

TEST(CddConvert, SpeedAndAcceleration) {
  EXPECT_EQ(cdd::speed_value(13.894), 1389);
  EXPECT_EQ(cdd::speed_value(500.0), 16382);
  EXPECT_EQ(cdd::speed_value(std::nullopt), m::kSpeedValueUnavailable);
  EXPECT_EQ(cdd::speed_confidence(1.3), m::kSpeedConfidenceOutOfRange);
  EXPECT_EQ(cdd::speed_confidence(0.098), 10);
  EXPECT_EQ(cdd::acceleration_value(-30.0), -160);
  EXPECT_EQ(cdd::acceleration_value(2.34), 23);
  EXPECT_EQ(cdd::acceleration_value(std::nullopt), m::kAccelerationValueUnavailable);
  // Far beyond any integer: saturates rather than wrapping.
  EXPECT_EQ(cdd::speed_value(1e300), 16382);
  EXPECT_EQ(cdd::acceleration_value(-1e300), -160);
  EXPECT_EQ(cdd::yaw_rate(1e300).yawRateValue, 32766);
  EXPECT_EQ(cdd::steering_wheel_angle(-1e300).steeringWheelAngleValue, -511);
}

TEST(CddConvert, AltitudeConfidenceClasses) {
  EXPECT_EQ(cdd::altitude(500.0, 0.9).altitudeConfidence, m::AltitudeConfidence::alt_001_00);
  EXPECT_EQ(cdd::altitude(500.0, 1.01).altitudeConfidence, m::AltitudeConfidence::alt_002_00);
  EXPECT_EQ(cdd::altitude(500.0, 250.0).altitudeConfidence, m::AltitudeConfidence::outOfRange);
  EXPECT_EQ(cdd::altitude(500.0, std::nullopt).altitudeConfidence,
            m::AltitudeConfidence::unavailable);
  EXPECT_EQ(cdd::altitude(12000.0, std::nullopt).altitudeValue, 800000);
}

TEST(CddConvert, CurvatureNeedsMotion) {
  EXPECT_EQ(cdd::curvature(10.0, 0.5).curvatureValue, m::kCurvatureValueUnavailable);
  // 10 °/s at 10 m/s: κ = 0.01745 1/m → 175.
  EXPECT_EQ(cdd::curvature(10.0, 10.0).curvatureValue, 175);
  EXPECT_EQ(cdd::curvature(-90.0, 1.0).curvatureValue, -1022);
}

TEST(ItsTime, EpochAndDeltaTime) {
  using namespace std::chrono;
  const clock::WallTime epoch2004{milliseconds{kItsEpochUnixMs}};
  EXPECT_EQ(timestamp_its(epoch2004), 0);
  EXPECT_EQ(timestamp_its(epoch2004 + milliseconds{65537}), 65537);
  EXPECT_EQ(generation_delta_time(65537), 1);
  EXPECT_EQ(generation_delta_time(-1), 65535);
  // 2024-01-01T00:00:00Z is 7305 days (20 years, 5 leap days) after 2004-01-01.
  const clock::WallTime y2024{seconds{1'704'067'200}};
  EXPECT_EQ(timestamp_its(y2024), std::int64_t{7305} * 86'400'000);
}

TEST(ItsTime, GenerationTimeFromDeltaTime) {
  using namespace std::chrono;
  const clock::WallTime gen{milliseconds{1'763'770'000'123}};
  const auto gdt = generation_delta_time(timestamp_its(gen));
  EXPECT_EQ(generation_time(gdt, gen + milliseconds{35}), gen);
  EXPECT_EQ(generation_time(gdt, gen + seconds{50}), gen);
  // A sender whose clock runs 1.5 s ahead of ours is still placed right.
  EXPECT_EQ(generation_time(gdt, gen - milliseconds{1500}), gen);
}

TEST(ItsTime, APeerCountingTaiIsDatedFiveSecondsAheadNotAMinuteBack) {
  // CDD V2.x TimestampIts is TAI, 5 s ahead of our UTC since 2017 (docs/time.md).
  using namespace std::chrono;
  const clock::WallTime utc{milliseconds{1'763'770'000'123}};
  const auto tai_gdt = generation_delta_time(timestamp_its(utc + seconds{5}));
  EXPECT_EQ(generation_time(tai_gdt, utc + milliseconds{40}), utc + seconds{5});
  // And a UTC peer's CAM 55 s old is still placed in the past.
  const auto gdt = generation_delta_time(timestamp_its(utc));
  EXPECT_EQ(generation_time(gdt, utc + seconds{55}), utc);
}

}  // namespace
}  // namespace tb::its::facilities
