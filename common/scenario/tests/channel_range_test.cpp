#include "common/scenario/channel_range.hpp"

#include <numbers>

#include <gtest/gtest.h>

namespace tb::scenario {
namespace {

using Kind = ChannelModel::Kind;

// The ranges worked out by hand from the link budget (tx − sensitivity = 23 − (−85) = 108 dB).
TEST(ChannelRange, FromTheLinkBudgetByHand) {
  ChannelModel m;
  m.kind = Kind::kRange;
  m.range_m = 250.0;
  EXPECT_DOUBLE_EQ(*max_range_m(m), 250.0);

  m.kind = Kind::kLogDistance;  // 47.86 + 20 log10 d = 108 → d = 10^3.007 ≈ 1016.2 m
  EXPECT_NEAR(*max_range_m(m), 1016.2, 0.1);
  m.path_loss_exponent = 3.0;  // 47.86 + 30 log10 d = 108 → d = 10^2.0047 ≈ 101.1 m
  EXPECT_NEAR(*max_range_m(m), 101.1, 0.1);

  // Two-ray, h = 1.5 m: past the crossover (≈ 556 m), 40 log10 d − 20 log10 2.25 = 108
  // → d = 10^(115.04 / 40) ≈ 751.8 m.
  m.kind = Kind::kTwoRay;
  EXPECT_NEAR(*max_range_m(m), 751.8, 0.1);
  // A budget of 80 dB ends in free space: 20 log10(4π d / λ) = 80, λ = c / 5.9 GHz
  // → d = 10^4 · 0.0508 / 4π ≈ 40.4 m.
  m.sensitivity_dbm = -57.0;
  EXPECT_NEAR(*max_range_m(m), 1e4 * (299'792'458.0 / 5.9e9) / (4 * std::numbers::pi), 0.01);

  m.kind = Kind::kIdeal;
  EXPECT_FALSE(max_range_m(m).has_value());
}

}  // namespace
}  // namespace tb::scenario
