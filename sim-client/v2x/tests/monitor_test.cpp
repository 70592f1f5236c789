#include "sim-client/v2x/monitor.hpp"

#include <gtest/gtest.h>

#include <set>

#include <nlohmann/json.hpp>

#include "its-station/apps/mqtt/messages.hpp"

namespace tb::client::v2x {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

clock::SteadyTime at(double s) {
  return clock::SteadyTime{
      std::chrono::duration_cast<clock::Duration>(std::chrono::duration<double>(1000.0 + s))};
}

std::string lcrw(std::uint32_t station, std::uint32_t other, const std::string& event,
                 json ttc = 2.4, const std::string& severity = "warning") {
  return json{{"type", "lcrw_warning"},
              {"origin", "on_board_application"},
              {"message",
               {{"station_id", station},
                {"other_station_id", other},
                {"event", event},
                {"collision_case", "frontal"},
                {"severity", severity},
                {"ttc_s", ttc},
                {"distance_m", 72.9}}}}
      .dump();
}

std::string denm(std::uint32_t origin, int seq, bool terminated = false, int validity = 10) {
  json mc = {{"action_id", {{"originating_station_id", origin}, {"sequence_number", seq}}},
             {"event_position", {{"latitude", 411050000}, {"longitude", 290230000}}},
             {"validity_duration", validity}};
  if (terminated)
    mc["termination"] = 0;
  return json{{"type", "denm"},
              {"message",
               {{"management_container", mc},
                {"situation_container", {{"event_type", {{"cause", 97}, {"subcause", 1}}}}}}}}
      .dump();
}

TEST(V2xMonitor, WarningRaisedUpdatedAndCleared) {
  V2xMonitor m;
  EXPECT_TRUE(m.on_message("its/1001/app/lcrw", lcrw(1001, 1002, "raised", 2.9), at(0)));
  auto p = m.picture(at(0.1));
  ASSERT_NE(p.alert_for(1001), nullptr);
  EXPECT_EQ(p.alert_for(1001)->other, 1002u);
  EXPECT_DOUBLE_EQ(*p.alert_for(1001)->ttc_s, 2.9);
  EXPECT_EQ(p.alert_for(1001)->collision_case, "frontal");
  EXPECT_EQ(p.alert_for(1002), nullptr);

  EXPECT_TRUE(
      m.on_message("its/1001/app/lcrw", lcrw(1001, 1002, "updated", 1.2, "critical"), at(0.5)));
  p = m.picture(at(0.6));
  EXPECT_DOUBLE_EQ(*p.alert_for(1001)->ttc_s, 1.2);
  EXPECT_EQ(p.alert_for(1001)->severity, "critical");

  EXPECT_TRUE(m.on_message("its/1001/app/lcrw", lcrw(1001, 1002, "cleared"), at(1.2)));
  EXPECT_EQ(m.picture(at(1.2)).alert_for(1001), nullptr);
  EXPECT_EQ(m.accepted(), 3u);
}

// A warning cleared 30 ms after it was raised (a gap that closes and opens again) still shows
// for the minimum display time, 1 s from its raise; raised again meanwhile, it simply stays.
TEST(V2xMonitor, AnEarlyClearKeepsTheWarningForItsMinimumDisplay) {
  V2xMonitor m;
  ASSERT_TRUE(m.on_message("its/1001/app/lcrw", lcrw(1001, 1002, "raised", 1.6), at(0)));
  ASSERT_TRUE(m.on_message("its/1001/app/lcrw", lcrw(1001, 1002, "cleared"), at(0.03)));
  ASSERT_NE(m.picture(at(0.03)).alert_for(1001), nullptr);
  EXPECT_DOUBLE_EQ(*m.picture(at(0.99)).alert_for(1001)->ttc_s, 1.6);
  EXPECT_EQ(m.picture(at(1.0)).alert_for(1001), nullptr);

  // Cleared early, then raised again 0.5 s after its first raise: the same episode, so the
  // next clear, 1.1 s after that first raise, takes it down at once.
  ASSERT_TRUE(m.on_message("its/1001/app/lcrw", lcrw(1001, 1003, "raised", 2.0), at(2.0)));
  ASSERT_TRUE(m.on_message("its/1001/app/lcrw", lcrw(1001, 1003, "cleared"), at(2.2)));
  ASSERT_TRUE(m.on_message("its/1001/app/lcrw", lcrw(1001, 1003, "raised", 1.4), at(2.5)));
  EXPECT_DOUBLE_EQ(*m.picture(at(2.9)).alert_for(1001)->ttc_s, 1.4);
  EXPECT_NE(m.picture(at(3.05)).alert_for(1001), nullptr);  // raised again: not cleared
  ASSERT_TRUE(m.on_message("its/1001/app/lcrw", lcrw(1001, 1003, "cleared"), at(3.1)));
  EXPECT_EQ(m.picture(at(3.1)).alert_for(1001), nullptr);

  // A clear for a warning never seen changes nothing.
  ASSERT_TRUE(m.on_message("its/1001/app/lcrw", lcrw(1001, 1004, "cleared"), at(4.0)));
  EXPECT_TRUE(m.picture(at(4.0)).alerts.empty());
}

TEST(V2xMonitor, MostUrgentFirstAndInfiniteTtcLast) {
  V2xMonitor m;
  m.on_message("its/1001/app/lcrw", lcrw(1001, 1002, "raised", nullptr), at(0));
  m.on_message("its/1001/app/lcrw", lcrw(1001, 1003, "raised", 1.5), at(0));
  m.on_message("its/1001/app/lcrw", lcrw(1001, 1004, "raised", 2.5), at(0));
  const auto p = m.picture(at(0));
  ASSERT_EQ(p.alerts.size(), 3u);
  EXPECT_EQ(p.alert_for(1001)->other, 1003u);
  EXPECT_FALSE(p.alerts.back().ttc_s.has_value());
}

TEST(V2xMonitor, AWarningNeitherUpdatedNorClearedGoesAfterTheTimeout) {
  V2xMonitor m;
  m.on_message("its/1001/app/lcrw", lcrw(1001, 1002, "raised"), at(0));
  EXPECT_NE(m.picture(at(1.99)).alert_for(1001), nullptr);
  EXPECT_EQ(m.picture(at(2.01)).alert_for(1001), nullptr);
}

TEST(V2xMonitor, LinksAreTheCamsOfTheLastSecond) {
  V2xMonitor m;
  EXPECT_TRUE(m.on_message("its/1001/in/cam/1002", "{}", at(0)));
  EXPECT_TRUE(m.on_message("its/1002/in/cam/1001", "{}", at(0.5)));
  auto p = m.picture(at(0.9));
  ASSERT_EQ(p.links.size(), 2u);
  EXPECT_EQ(p.links[0], (V2xLink{1001, 1002}));
  EXPECT_EQ(p.links[1], (V2xLink{1002, 1001}));
  p = m.picture(at(1.2));
  ASSERT_EQ(p.links.size(), 1u);
  EXPECT_EQ(p.links[0], (V2xLink{1001, 1002}));
  EXPECT_TRUE(m.picture(at(1.6)).links.empty());
}

TEST(V2xMonitor, DenmsUntilTerminatedOrExpired) {
  V2xMonitor m;
  EXPECT_TRUE(m.on_message("its/1002/in/denm/1001", denm(1001, 7), at(0)));
  // The same event heard by another station is one event.
  EXPECT_TRUE(m.on_message("its/1003/in/denm/1001", denm(1001, 7), at(0.1)));
  EXPECT_TRUE(m.on_message("its/1003/in/denm/1001", denm(1001, 8, false, 1), at(0.1)));
  auto p = m.picture(at(0.5));
  ASSERT_EQ(p.denms.size(), 2u);
  EXPECT_EQ(p.denms[0].originator, 1001u);
  EXPECT_EQ(p.denms[0].sequence, 7u);
  EXPECT_NEAR(p.denms[0].latitude_deg, 41.105, 1e-9);
  EXPECT_NEAR(p.denms[0].longitude_deg, 29.023, 1e-9);
  EXPECT_EQ(p.denms[0].cause, 97);
  EXPECT_EQ(p.denms[0].subcause, 1);
  EXPECT_EQ(m.picture(at(1.2)).denms.size(), 1u);  // sequence 8 valid for 1 s
  EXPECT_TRUE(m.on_message("its/1002/in/denm/1001", denm(1001, 7, true), at(2)));
  EXPECT_TRUE(m.picture(at(2)).denms.empty());
}

TEST(V2xMonitor, BadPayloadsAreRejectedWithTheReasonAndChangeNothing) {
  V2xMonitor m;
  m.on_message("its/1001/app/lcrw", lcrw(1001, 1002, "raised"), at(0));
  EXPECT_FALSE(m.on_message("its/1001/app/lcrw", "{not json", at(0)));
  EXPECT_NE(m.last_error().find("its/1001/app/lcrw"), std::string::npos);
  EXPECT_FALSE(m.on_message("its/1001/app/lcrw", lcrw(1001, 1002, "exploded"), at(0)));
  EXPECT_NE(m.last_error().find("exploded"), std::string::npos);
  EXPECT_FALSE(m.on_message("its/1001/app/lcrw", R"({"message":{"event":"cleared"}})", at(0)));
  EXPECT_NE(m.last_error().find("other_station_id"), std::string::npos);
  EXPECT_FALSE(m.on_message("its/x1/app/lcrw", lcrw(1001, 1002, "cleared"), at(0)));
  EXPECT_NE(m.last_error().find("'x1' is not a station id"), std::string::npos);
  EXPECT_FALSE(m.on_message("its/1001/in/cam/-3", "{}", at(0)));
  json far = json::parse(denm(1001, 1));
  far["message"]["management_container"]["event_position"]["latitude"] = 900000002;
  EXPECT_FALSE(m.on_message("its/1002/in/denm/1001", far.dump(), at(0)));
  EXPECT_EQ(m.rejected(), 6u);
  // The raised warning is untouched by the bad clears.
  EXPECT_NE(m.picture(at(0)).alert_for(1001), nullptr);
}

// The payload a station publishes on its/<id>/in/denm/<origin> (its-station's own writer), for
// every RelevanceDistance class: the relevance area's radius is the class's upper bound (CDD,
// TS 102 894-2: lessThan50m … lessThan10km; over10km drawn as 20 km).
TEST(V2xMonitor, DenmRelevanceAreaFromTheStationsPayload) {
  const double want[] = {50, 100, 200, 500, 1000, 5000, 10000, 20000};
  for (int k = 0; k < 8; ++k) {
    its::apps::mqtt::DenmView d;
    d.action_id = {1001, static_cast<std::uint16_t>(k)};
    d.cause_code = 97;
    d.sub_cause_code = 1;
    d.event_latitude_deg = 41.105;
    d.event_longitude_deg = 29.023;
    d.relevance_distance = static_cast<its::apps::RelevanceDistance>(k);
    d.relevance_traffic_direction = static_cast<its::apps::RelevanceTrafficDirection>(k % 4);
    d.validity_duration_s = 60;
    const std::string payload = its::apps::mqtt::envelope("denm", "remote", 1002, clock::WallTime{},
                                                          its::apps::mqtt::denm_message(d))
                                    .dump();
    V2xMonitor m;
    ASSERT_TRUE(m.on_message("its/1002/in/denm/1001", payload, at(0))) << m.last_error();
    const auto p = m.picture(at(1));
    ASSERT_EQ(p.denms.size(), 1u);
    ASSERT_TRUE(p.denms[0].relevance_radius_m.has_value()) << k;
    EXPECT_DOUBLE_EQ(*p.denms[0].relevance_radius_m, want[k]);
    EXPECT_EQ(p.denms[0].relevance_traffic_direction, k % 4);
  }
}

TEST(V2xMonitor, DenmWithoutRelevanceHasNoAreaAndBadOnesAreRejected) {
  V2xMonitor m;
  ASSERT_TRUE(m.on_message("its/1002/in/denm/1001", denm(1001, 1), at(0)));
  auto p = m.picture(at(0));
  ASSERT_EQ(p.denms.size(), 1u);
  EXPECT_FALSE(p.denms[0].relevance_radius_m.has_value());
  EXPECT_FALSE(p.denms[0].relevance_traffic_direction.has_value());
  for (const json& bad : {json(8), json(-1), json("far"), json(1.5)}) {
    json d = json::parse(denm(1001, 2));
    d["message"]["management_container"]["relevance_distance"] = bad;
    EXPECT_FALSE(m.on_message("its/1002/in/denm/1001", d.dump(), at(0))) << bad;
    EXPECT_NE(m.last_error().find("relevance_distance"), std::string::npos) << m.last_error();
  }
  json d = json::parse(denm(1001, 3));
  d["message"]["management_container"]["relevance_traffic_direction"] = 4;
  EXPECT_FALSE(m.on_message("its/1002/in/denm/1001", d.dump(), at(0)));
  EXPECT_NE(m.last_error().find("relevance_traffic_direction"), std::string::npos);
  // Nothing of the rejected ones is in force.
  p = m.picture(at(0));
  ASSERT_EQ(p.denms.size(), 1u);
  EXPECT_EQ(p.denms[0].sequence, 1u);
}

// The operator's lines: one per (warned station, station it is warned about), both named.
TEST(V2xMonitor, EveryWarnedPairIsInThePicture) {
  V2xMonitor m;
  EXPECT_TRUE(m.on_message("its/1001/app/lcrw", lcrw(1001, 1002, "raised", 2.0), at(0)));
  EXPECT_TRUE(m.on_message("its/1001/app/lcrw", lcrw(1001, 1003, "raised", 3.0), at(0)));
  EXPECT_TRUE(m.on_message("its/1003/app/lcrw", lcrw(1003, 1001, "raised", 3.1), at(0)));
  auto p = m.picture(at(0.1));
  ASSERT_EQ(p.alerts.size(), 3u);
  std::set<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (const auto& a : p.alerts)
    pairs.insert({a.station, a.other});
  EXPECT_EQ(pairs, (std::set<std::pair<std::uint32_t, std::uint32_t>>{
                       {1001, 1002}, {1001, 1003}, {1003, 1001}}));
  EXPECT_TRUE(m.on_message("its/1001/app/lcrw", lcrw(1001, 1003, "cleared"), at(0.2)));
  EXPECT_EQ(m.picture(at(0.3)).alerts.size(), 3u);  // its minimum display
  EXPECT_EQ(m.picture(at(1.0)).alerts.size(), 2u);
}

TEST(V2xMonitor, OtherTopicsAndPrefixesAreNotCounted) {
  V2xMonitor m;
  EXPECT_FALSE(m.on_message("its/1001/state", "{}", at(0)));
  EXPECT_FALSE(m.on_message("other/1001/app/lcrw", lcrw(1001, 1002, "raised"), at(0)));
  EXPECT_FALSE(m.on_message("its", "", at(0)));
  EXPECT_EQ(m.rejected(), 0u);
  EXPECT_EQ(m.accepted(), 0u);
  MonitorConfig cfg;
  cfg.prefix = "lab";
  V2xMonitor lab(cfg);
  EXPECT_EQ(lab.subscriptions(),
            (std::vector<std::string>{"lab/+/app/lcrw", "lab/+/in/cam/+", "lab/+/in/denm/+",
                                      "lab/+/app/signal", "lab/+/app/rlvw"}));
  EXPECT_TRUE(lab.on_message("lab/1001/app/lcrw", lcrw(1001, 1002, "raised"), at(0)));
}

}  // namespace
}  // namespace tb::client::v2x
