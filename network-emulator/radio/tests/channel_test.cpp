#include "network-emulator/radio/channel.hpp"

#include <cmath>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace tb::emu::radio {
namespace {

using Kind = scenario::ChannelModel::Kind;

scenario::ChannelModel model(Kind k) {
  scenario::ChannelModel m;
  m.kind = k;
  return m;
}

class ChannelTest : public ::testing::Test {
 protected:
  void place(StationId id, double x, double y = 0.0) {
    positions.set(id, StationPosition{{x, y, 0.0}, 0});
  }
  PositionTable positions;
};

TEST_F(ChannelTest, IdealDeliversEverythingEvenWithoutPositions) {
  auto m = model(Kind::kIdeal);
  m.packet_error_rate = 0.5;  // ignored: ideal is lossless by definition
  Channel ch(m, positions, 1);
  for (int i = 0; i < 1000; ++i) {
    const Decision d = ch.decide(1, 2);
    ASSERT_TRUE(d.deliver);
    EXPECT_EQ(d.delay, clock::Duration{0});
  }
  EXPECT_EQ(ch.links().at({1, 2}).delivered, 1000u);
}

TEST_F(ChannelTest, RangeModelCutsAtRange) {
  auto m = model(Kind::kRange);
  m.range_m = 300.0;
  place(1, 0.0);
  place(2, 299.9);
  place(3, 300.1);
  place(4, 0.0, 300.0);  // exactly at the range, diagonal axis
  Channel ch(m, positions, 1);
  const Decision in = ch.decide(1, 2);
  EXPECT_TRUE(in.deliver);
  ASSERT_TRUE(in.distance_m);
  EXPECT_NEAR(*in.distance_m, 299.9, 1e-9);
  const Decision out = ch.decide(1, 3);
  EXPECT_FALSE(out.deliver);
  EXPECT_EQ(out.reason, DropReason::kOutOfRange);
  EXPECT_TRUE(ch.decide(1, 4).deliver);
  // From 3 to 2 is 0.2 m.
  EXPECT_TRUE(ch.decide(3, 2).deliver);
}

TEST_F(ChannelTest, UnknownPositionDropsUnderDistanceModels) {
  auto m = model(Kind::kRange);
  place(1, 0.0);
  Channel ch(m, positions, 1);
  const Decision d = ch.decide(1, 9);
  EXPECT_FALSE(d.deliver);
  EXPECT_EQ(d.reason, DropReason::kUnknownPosition);
  EXPECT_FALSE(d.distance_m);
}

TEST_F(ChannelTest, LogDistanceThresholdMatchesTheLinkBudget) {
  auto m = model(Kind::kLogDistance);
  m.tx_power_dbm = 23.0;
  m.sensitivity_dbm = -85.0;
  m.reference_loss_db = 47.86;
  m.path_loss_exponent = 2.0;
  // 108 dB of budget: 47.86 + 20 log10(d) = 108  →  d = 10^(60.14 / 20) ≈ 1015.0 m.
  const double edge = std::pow(10.0, (23.0 + 85.0 - 47.86) / 20.0);
  place(1, 0.0);
  place(2, edge - 0.5);
  place(3, edge + 0.5);
  Channel ch(m, positions, 1);
  const Decision in = ch.decide(1, 2);
  EXPECT_TRUE(in.deliver);
  ASSERT_TRUE(in.rx_power_dbm);
  EXPECT_NEAR(*in.rx_power_dbm, -85.0, 0.01);
  EXPECT_GE(*in.rx_power_dbm, -85.0);
  const Decision out = ch.decide(1, 3);
  EXPECT_FALSE(out.deliver);
  EXPECT_EQ(out.reason, DropReason::kBelowSensitivity);
  EXPECT_LT(*out.rx_power_dbm, -85.0);
}

TEST(PathLoss, ReferenceLossIsFreeSpaceAtOneMetre) {
  auto m = model(Kind::kLogDistance);
  EXPECT_NEAR(path_loss_db(m, 1.0), 47.86, 1e-9);
  EXPECT_NEAR(path_loss_db(m, 0.1), 47.86, 1e-9);  // clamped to the reference distance
  EXPECT_NEAR(path_loss_db(m, 100.0), 87.86, 1e-9);
}

TEST(PathLoss, TwoRayIsContinuousAtCrossoverAndFallsWithFourthPowerBeyond) {
  auto m = model(Kind::kTwoRay);
  m.antenna_height_m = 1.5;
  m.frequency_mhz = 5900.0;
  const double lambda = 299'792'458.0 / 5.9e9;
  const double dc = 4.0 * std::numbers::pi * 1.5 * 1.5 / lambda;  // ≈ 556 m
  EXPECT_NEAR(path_loss_db(m, dc * (1 - 1e-9)), path_loss_db(m, dc * (1 + 1e-9)), 1e-6);
  // Free space below crossover: 20 dB per decade; 40 dB per decade above.
  EXPECT_NEAR(path_loss_db(m, 100.0) - path_loss_db(m, 10.0), 20.0, 1e-9);
  EXPECT_NEAR(path_loss_db(m, 10 * dc) - path_loss_db(m, dc), 40.0, 1e-9);
  // And free space at 1 m is the 47.86 dB of the log-distance default.
  EXPECT_NEAR(path_loss_db(m, 1.0), 47.86, 0.01);
}

// The range the operator's view draws (scenario::max_range_m) is where this medium stops
// delivering: every model, just inside and just outside, short of and past the two-ray crossover.
TEST_F(ChannelTest, MaxRangeIsWhereTheMediumStopsDelivering) {
  std::vector<scenario::ChannelModel> models;
  models.push_back(model(Kind::kRange));
  models.back().range_m = 420.0;
  models.push_back(model(Kind::kLogDistance));
  models.push_back(model(Kind::kLogDistance));
  models.back().path_loss_exponent = 2.7;
  models.push_back(model(Kind::kTwoRay));  // beyond the crossover (≈ 556 m)
  models.push_back(model(Kind::kTwoRay));
  models.back().sensitivity_dbm = -60.0;  // short of it
  for (const auto& m : models) {
    const auto r = scenario::max_range_m(m);
    ASSERT_TRUE(r.has_value());
    place(1, 0.0);
    place(2, *r * 0.995);
    place(3, *r * 1.005);
    Channel ch(m, positions, 1);
    EXPECT_TRUE(ch.decide(1, 2).deliver) << to_string(m.kind) << " range " << *r;
    EXPECT_FALSE(ch.decide(1, 3).deliver) << to_string(m.kind) << " range " << *r;
  }
  EXPECT_FALSE(scenario::max_range_m(model(Kind::kIdeal)).has_value());
}

TEST_F(ChannelTest, PacketErrorRateWithinToleranceAndReproducible) {
  auto m = model(Kind::kRange);
  m.range_m = 1000.0;
  m.packet_error_rate = 0.2;
  place(1, 0.0);
  place(2, 10.0);
  Channel a(m, positions, 42);
  Channel b(m, positions, 42);
  constexpr int kFrames = 100'000;
  for (int i = 0; i < kFrames; ++i)
    ASSERT_EQ(a.decide(1, 2).deliver, b.decide(1, 2).deliver) << "frame " << i;
  const LinkStats s = a.links().at({1, 2});
  const double loss =
      static_cast<double>(s.dropped[static_cast<int>(DropReason::kPacketError)]) / kFrames;
  // Binomial sd = sqrt(0.2 * 0.8 / 1e5) ≈ 0.0013; 5 sd of tolerance.
  EXPECT_NEAR(loss, 0.2, 0.0065);
  // Another seed gives another sequence.
  Channel c(m, positions, 43);
  int differ = 0;
  Channel a2(m, positions, 42);
  for (int i = 0; i < 1000; ++i)
    differ += a2.decide(1, 2).deliver != c.decide(1, 2).deliver;
  EXPECT_GT(differ, 0);
}

TEST_F(ChannelTest, DelayAndJitterStayInTheirWindow) {
  auto m = model(Kind::kIdeal);
  m.delay_ms = 2.0;
  m.jitter_ms = 1.0;
  Channel ch(m, positions, 7);
  clock::Duration lo = std::chrono::hours(1), hi{0};
  for (int i = 0; i < 10'000; ++i) {
    const auto d = ch.decide(1, 2).delay;
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  EXPECT_GE(lo, std::chrono::milliseconds(2));
  EXPECT_LT(hi, std::chrono::milliseconds(3));
  // 10,000 uniform draws cover the window to within a few microseconds at both ends.
  EXPECT_LT(lo, std::chrono::microseconds(2010));
  EXPECT_GT(hi, std::chrono::microseconds(2990));
}

TEST_F(ChannelTest, StatsAddUpPerLinkAndInJson) {
  auto m = model(Kind::kLogDistance);
  m.packet_error_rate = 0.1;
  place(1, 0.0);
  place(2, 500.0);
  place(3, 5000.0);  // beyond the ≈ 1 km of the default budget
  Channel ch(m, positions, 3);
  const StationId ids[] = {1, 2, 3, 4};  // 4 has no position
  for (int i = 0; i < 2000; ++i)
    for (StationId from : ids)
      for (StationId to : ids)
        if (from != to)
          ch.decide(from, to);
  std::uint64_t sent = 0;
  for (const auto& [link, s] : ch.links()) {
    EXPECT_EQ(s.sent, 2000u);
    EXPECT_EQ(s.sent, s.delivered + s.dropped_total()) << link.first << "→" << link.second;
    sent += s.sent;
  }
  EXPECT_EQ(ch.links().size(), 12u);
  EXPECT_EQ(ch.totals().sent, sent);
  EXPECT_EQ(ch.links().at({1, 3}).dropped[static_cast<int>(DropReason::kBelowSensitivity)], 2000u);
  EXPECT_EQ(ch.links().at({4, 1}).dropped[static_cast<int>(DropReason::kUnknownPosition)], 2000u);
  EXPECT_GT(ch.links().at({1, 2}).delivered, 0u);
  EXPECT_GT(ch.links().at({1, 2}).dropped[static_cast<int>(DropReason::kPacketError)], 0u);

  const nlohmann::json j = ch.stats_json();
  EXPECT_EQ(j["model"], "log_distance");
  EXPECT_EQ(j["seed"], 3u);
  ASSERT_EQ(j["links"].size(), 12u);
  std::uint64_t json_sum = 0;
  for (const auto& l : j["links"]) {
    std::uint64_t dropped = 0;
    for (const auto& [reason, n] : l["dropped"].items())
      dropped += n.get<std::uint64_t>();
    EXPECT_EQ(l["sent"].get<std::uint64_t>(), l["delivered"].get<std::uint64_t>() + dropped);
    json_sum += l["sent"].get<std::uint64_t>();
  }
  EXPECT_EQ(json_sum, j["totals"]["sent"].get<std::uint64_t>());
  EXPECT_EQ(j["links"][0]["dropped"].size(), kDropReasonCount);
}

TEST_F(ChannelTest, ObserverSeesEveryDecision) {
  auto m = model(Kind::kRange);
  m.range_m = 100;
  m.delay_ms = 1;
  place(1, 0.0);
  place(2, 50.0);
  place(3, 500.0);
  Channel ch(m, positions, 1);
  std::vector<std::tuple<StationId, StationId, bool, DropReason, clock::Duration>> seen;
  ch.set_observer([&](StationId from, StationId to, const Decision& d) {
    seen.emplace_back(from, to, d.deliver, d.reason, d.delay);
  });
  ch.decide(1, 2);
  ch.decide(1, 3);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0], std::make_tuple(1u, 2u, true, DropReason::kOutOfRange,
                                     clock::Duration{std::chrono::milliseconds(1)}));
  EXPECT_EQ(std::get<2>(seen[1]), false);
  EXPECT_EQ(std::get<3>(seen[1]), DropReason::kOutOfRange);
}

TEST(PositionTableTest, IgnoresOlderStates) {
  PositionTable t;
  wire::VehicleState s;
  s.station_id = 5;
  s.sim_time_ns = 200;
  s.position = {1, 2, 3};
  EXPECT_TRUE(t.update(s));
  s.sim_time_ns = 100;
  s.position = {9, 9, 9};
  EXPECT_FALSE(t.update(s));
  EXPECT_EQ(t.position(5)->position[0], 1.0);
  EXPECT_FALSE(t.position(6));
}

TEST(ChannelValidation, RejectsUnusableNumbersNamingTheField) {
  PositionTable t;
  auto m = model(Kind::kRange);
  m.packet_error_rate = 1.5;
  try {
    Channel ch(m, t, 1);
    FAIL() << "accepted packet_error_rate 1.5";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("packet_error_rate"), std::string::npos);
  }
}

}  // namespace
}  // namespace tb::emu::radio
