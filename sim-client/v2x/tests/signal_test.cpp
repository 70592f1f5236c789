// Issue 34: the own lane's signal (`its/<id>/app/signal`) and the red-light violation warning
// (`its/<id>/app/rlvw`) as the driver's view reads them, and what its panel and banner show.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "sim-client/v2x/monitor.hpp"
#include "sim-client/v2x/signal_panel.hpp"
#include "sim-client/v2x/warning_sound.hpp"

namespace tb::client::v2x {
namespace {

using nlohmann::json;

clock::SteadyTime at(double s) {
  return clock::SteadyTime{
      std::chrono::duration_cast<clock::Duration>(std::chrono::duration<double>(500.0 + s))};
}

/// The MQTT contract's `signal` message (issue 34) in the stations' envelope.
json signal_msg(const std::string& state = "red",
                const std::string& event_state = "stop-And-Remain", json ttc = 6.2,
                json likely = 7.4, double distance = 41.6, json advice = nullptr,
                bool rlvw = false) {
  return json{{"type", "signal"},
              {"origin", "on_board_application"},
              {"version", "1.0.0"},
              {"source_uuid", "its-station-1001"},
              {"timestamp", 1795000000000},
              {"message",
               {{"intersection_id", 1},
                {"signal_group", 3},
                {"lane_id", 2},
                {"state", state},
                {"event_state", event_state},
                {"time_to_change_s", ttc},
                {"likely_time_to_change_s", likely},
                {"distance_to_stop_line_m", distance},
                {"advice", advice},
                {"rlvw", rlvw}}}};
}

json left_lane() {
  return json{{"type", "signal"}, {"message", {{"lane", nullptr}}}};
}

json rlvw_msg(const std::string& event, json time_to_red = 1.0, int group = 3) {
  return json{{"type", "rlvw_warning"},
              {"message",
               {{"station_id", 1001},
                {"intersection_id", 1},
                {"signal_group", group},
                {"lane_id", 2},
                {"event", event},
                {"severity", "warning"},
                {"distance_to_stop_line_m", 40.2},
                {"speed_mps", 16.7},
                {"time_to_red_s", time_to_red},
                {"stopping_distance_m", 63.1},
                {"clear_reason", event == "cleared" ? "passed" : "none"},
                {"raised_at", 1795000000000},
                {"updated_at", 1795000000100}}}};
}

constexpr const char* kSignal = "its/1001/app/signal";
constexpr const char* kRlvw = "its/1001/app/rlvw";

TEST(SignalMonitor, SubscribesToBothTopicsOfEveryStation) {
  const auto subs = V2xMonitor().subscriptions();
  EXPECT_NE(std::find(subs.begin(), subs.end(), "its/+/app/signal"), subs.end());
  EXPECT_NE(std::find(subs.begin(), subs.end(), "its/+/app/rlvw"), subs.end());
}

TEST(SignalMonitor, ReadsEveryFieldOfTheContract) {
  V2xMonitor m;
  ASSERT_TRUE(m.on_message(kSignal,
                           signal_msg("green", "protected-Movement-Allowed", 3.0, 4.5, 85.0,
                                      json{{"min_speed_kmh", 31.4}, {"max_speed_kmh", 48.9}})
                               .dump(),
                           at(0)))
      << m.last_error();
  const auto p = m.picture(at(0.2));
  const LaneSignal* s = p.signal_for(1001);
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(p.signal_for(1002), nullptr);
  EXPECT_EQ(s->intersection_id, 1u);
  EXPECT_EQ(s->signal_group, 3u);
  EXPECT_EQ(s->lane_id, 2u);
  EXPECT_EQ(s->light, SignalLight::kGreen);
  EXPECT_EQ(s->event_state, "protected-Movement-Allowed");
  // Aged by the 0.2 s since the message came.
  EXPECT_NEAR(*s->time_to_change_s, 2.8, 1e-9);
  EXPECT_NEAR(*s->likely_time_to_change_s, 4.3, 1e-9);
  EXPECT_DOUBLE_EQ(s->distance_to_stop_line_m, 85.0);
  ASSERT_TRUE(s->advice.has_value());
  EXPECT_DOUBLE_EQ(s->advice->min_kmh, 31.4);
  EXPECT_DOUBLE_EQ(s->advice->max_kmh, 48.9);
  EXPECT_FALSE(s->rlvw);
  EXPECT_EQ(m.accepted(), 1u);
}

TEST(SignalPanelModel, IconLitByStateGreyWhenDarkOrUnavailable) {
  struct Case {
    const char* state;
    const char* event_state;
    bool red, amber, green;
  };
  const Case cases[] = {{"red", "stop-And-Remain", true, false, false},
                        {"red_amber", "pre-Movement", true, true, false},
                        {"green", "protected-Movement-Allowed", false, false, true},
                        {"amber", "protected-clearance", false, true, false},
                        {"dark", "dark", false, false, false},
                        {"unavailable", "unavailable", false, false, false}};
  for (const Case& c : cases) {
    V2xMonitor m;
    ASSERT_TRUE(m.on_message(kSignal, signal_msg(c.state, c.event_state).dump(), at(0)))
        << c.state << ": " << m.last_error();
    const auto panel = signal_panel(m.picture(at(0.1)), 1001);
    ASSERT_TRUE(panel.has_value()) << c.state;
    EXPECT_EQ(to_string(panel->light), c.state);
    EXPECT_EQ(panel->red, c.red) << c.state;
    EXPECT_EQ(panel->amber, c.amber) << c.state;
    EXPECT_EQ(panel->green, c.green) << c.state;
  }
}

TEST(SignalPanelModel, CountdownInWholeSecondsFromTheLikelyTimeElseTheMinimum) {
  V2xMonitor m;
  // likely 7.4 s: counts up to the whole second, as a countdown display does (never "0" early).
  m.on_message(kSignal, signal_msg("red", "stop-And-Remain", 6.2, 7.4).dump(), at(0));
  auto p = signal_panel(m.picture(at(0)), 1001);
  EXPECT_EQ(p->countdown_s, 8);
  EXPECT_TRUE(p->countdown_is_likely);
  EXPECT_EQ(p->countdown, "8 s");
  // No likely time: the minimum end time.
  m.on_message(kSignal, signal_msg("red", "stop-And-Remain", 6.2, nullptr).dump(), at(0.1));
  p = signal_panel(m.picture(at(0.1)), 1001);
  EXPECT_EQ(p->countdown_s, 7);
  EXPECT_FALSE(p->countdown_is_likely);
  // Exactly 3 s stays 3; a change already due (late message) shows 0, not a negative.
  m.on_message(kSignal, signal_msg("amber", "protected-clearance", 3.0, nullptr).dump(), at(0.2));
  EXPECT_EQ(signal_panel(m.picture(at(0.2)), 1001)->countdown, "3 s");
  m.on_message(kSignal, signal_msg("amber", "protected-clearance", -0.3, nullptr).dump(), at(0.3));
  EXPECT_EQ(signal_panel(m.picture(at(0.3)), 1001)->countdown_s, 0);
  // The countdown runs on between messages: 7.4 s likely when sent is 7.1 s 0.3 s later (8),
  // 6.9 s 0.5 s later (7).
  m.on_message(kSignal, signal_msg("red", "stop-And-Remain", 6.2, 7.4).dump(), at(0.35));
  EXPECT_EQ(signal_panel(m.picture(at(0.35 + 0.3)), 1001)->countdown, "8 s");
  EXPECT_EQ(signal_panel(m.picture(at(0.35 + 0.5)), 1001)->countdown, "7 s");
  // Neither known: no countdown.
  m.on_message(kSignal, signal_msg("green", "protected-Movement-Allowed", nullptr, nullptr).dump(),
               at(0.4));
  p = signal_panel(m.picture(at(0.4)), 1001);
  EXPECT_FALSE(p->countdown_s.has_value());
  EXPECT_EQ(p->countdown, "");
  // The likely time may also be left out altogether.
  json no_likely = signal_msg("red", "stop-And-Remain", 12.01);
  no_likely["message"].erase("likely_time_to_change_s");
  ASSERT_TRUE(m.on_message(kSignal, no_likely.dump(), at(0.5))) << m.last_error();
  EXPECT_EQ(signal_panel(m.picture(at(0.5)), 1001)->countdown, "13 s");
}

TEST(SignalPanelModel, DistanceAndAdviceAsTheDriverReadsThem) {
  V2xMonitor m;
  m.on_message(kSignal, signal_msg("red", "stop-And-Remain", 6.0, 6.0, 41.6).dump(), at(0));
  auto p = signal_panel(m.picture(at(0)), 1001);
  EXPECT_EQ(p->distance, "42 m");
  EXPECT_EQ(p->advice, "");  // advice null: none shown
  EXPECT_EQ(p->caption, "group 3 · lane 2");
  // The whole km/h inside the advised range, so that a driver reading it stays inside.
  m.on_message(kSignal,
               signal_msg("red", "stop-And-Remain", 6.0, 6.0, 80.0,
                          json{{"min_speed_kmh", 31.4}, {"max_speed_kmh", 48.9}})
                   .dump(),
               at(0.1));
  EXPECT_EQ(signal_panel(m.picture(at(0.1)), 1001)->advice, "32–48 km/h");
  // A range narrower than a whole km/h: one speed, its middle.
  m.on_message(kSignal,
               signal_msg("red", "stop-And-Remain", 6.0, 6.0, 80.0,
                          json{{"min_speed_kmh", 40.2}, {"max_speed_kmh", 40.8}})
                   .dump(),
               at(0.2));
  EXPECT_EQ(signal_panel(m.picture(at(0.2)), 1001)->advice, "41 km/h");
}

TEST(SignalPanelModel, ShownWhileFreshHiddenAfterOneSecondOrWhenTheLaneIsLeft) {
  V2xMonitor m;
  m.on_message(kSignal, signal_msg().dump(), at(0));
  EXPECT_TRUE(signal_panel(m.picture(at(1.0)), 1001).has_value());  // ≤ 1 s: fresh
  EXPECT_FALSE(signal_panel(m.picture(at(1.001)), 1001).has_value());
  // A new message brings it back; leaving the lane hides it at once.
  m.on_message(kSignal, signal_msg().dump(), at(2.0));
  EXPECT_TRUE(signal_panel(m.picture(at(2.1)), 1001).has_value());
  EXPECT_TRUE(m.on_message(kSignal, left_lane().dump(), at(2.2)));
  EXPECT_FALSE(signal_panel(m.picture(at(2.2)), 1001).has_value());
  // Another station's lane stays.
  m.on_message("its/1002/app/signal", signal_msg().dump(), at(2.3));
  m.on_message(kSignal, left_lane().dump(), at(2.4));
  EXPECT_TRUE(signal_panel(m.picture(at(2.4)), 1002).has_value());
  // "lane_id": null reads as leaving too.
  json null_lane = signal_msg();
  null_lane["message"]["lane_id"] = nullptr;
  EXPECT_TRUE(m.on_message("its/1002/app/signal", null_lane.dump(), at(2.5)));
  EXPECT_FALSE(signal_panel(m.picture(at(2.5)), 1002).has_value());
}

TEST(SignalMonitor, BadSignalPayloadsAreCountedNamedAndChangeNothing) {
  V2xMonitor m;
  ASSERT_TRUE(
      m.on_message(kSignal, signal_msg("green", "protected-Movement-Allowed").dump(), at(0)));
  struct Bad {
    std::string payload;
    std::string named;
  };
  std::vector<Bad> bad;
  bad.push_back({"{not json", "not JSON"});
  bad.push_back({"[1,2]", "envelope"});
  bad.push_back({R"({"message":"red"})", "envelope"});
  auto with = [](const char* key, json v) {
    json j = signal_msg();
    j["message"][key] = std::move(v);
    return j.dump();
  };
  auto without = [](const char* key) {
    json j = signal_msg();
    j["message"].erase(key);
    return j.dump();
  };
  bad.push_back({with("state", "purple"), "message.state: 'purple'"});
  bad.push_back({with("state", 3), "message.state"});
  bad.push_back({without("state"), "message.state"});
  bad.push_back({with("event_state", "stop-and-remain"), "message.event_state"});
  bad.push_back({with("intersection_id", 70000), "intersection_id"});
  bad.push_back({with("intersection_id", "1"), "intersection_id"});
  bad.push_back({without("intersection_id"), "intersection_id"});
  bad.push_back({with("signal_group", 256), "signal_group"});
  bad.push_back({with("signal_group", -1), "signal_group"});
  bad.push_back({with("lane_id", 1.5), "lane_id"});
  bad.push_back({with("time_to_change_s", "soon"), "time_to_change_s"});
  bad.push_back({without("time_to_change_s"), "time_to_change_s"});
  bad.push_back({with("time_to_change_s", 1e9), "time_to_change_s"});
  bad.push_back({with("likely_time_to_change_s", json::array()), "likely_time_to_change_s"});
  bad.push_back({with("distance_to_stop_line_m", nullptr), "distance_to_stop_line_m"});
  bad.push_back({without("distance_to_stop_line_m"), "distance_to_stop_line_m"});
  bad.push_back({with("advice", json{{"min_speed_kmh", 50}, {"max_speed_kmh", 30}}), "advice"});
  bad.push_back({with("advice", json{{"min_speed_kmh", 30}}), "advice"});
  bad.push_back({with("advice", 42), "advice"});
  bad.push_back({with("advice", json{{"min_speed_kmh", -5}, {"max_speed_kmh", 30}}), "advice"});
  bad.push_back({with("rlvw", "yes"), "rlvw"});
  // A NaN cannot be written in JSON; nlohmann refuses a number beyond a double's range.
  bad.push_back({R"({"message":{"intersection_id":1,"signal_group":3,"lane_id":2,"state":"red",)"
                 R"("event_state":"stop-And-Remain","time_to_change_s":1e999,)"
                 R"("distance_to_stop_line_m":10}})",
                 "not JSON"});
  for (std::size_t i = 0; i < bad.size(); ++i) {
    EXPECT_FALSE(m.on_message(kSignal, bad[i].payload, at(0.1))) << bad[i].payload;
    EXPECT_NE(m.last_error().find(kSignal), std::string::npos) << m.last_error();
    EXPECT_NE(m.last_error().find(bad[i].named), std::string::npos)
        << bad[i].payload << " → " << m.last_error();
  }
  EXPECT_EQ(m.rejected(), bad.size());
  EXPECT_EQ(m.accepted(), 1u);
  // The good message before them still shows, unchanged.
  const auto p = signal_panel(m.picture(at(0.2)), 1001);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->light, SignalLight::kGreen);
}

TEST(RlvwMonitor, RaisedUpdatedClearedWithTheBannerText) {
  V2xMonitor m;
  ASSERT_TRUE(m.on_message(kRlvw, rlvw_msg("raised", 1.04).dump(), at(0))) << m.last_error();
  auto p = m.picture(at(0.1));
  const RlvwAlert* a = p.rlvw_for(1001);
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(a->intersection_id, 1u);
  EXPECT_EQ(a->signal_group, 3u);
  EXPECT_EQ(a->lane_id, 2u);
  EXPECT_DOUBLE_EQ(a->speed_mps, 16.7);
  EXPECT_DOUBLE_EQ(a->stopping_distance_m, 63.1);
  // 1.04 s to red when sent, 0.1 s ago.
  EXPECT_EQ(rlvw_banner(p, 1001), "RED LIGHT WARNING · red in 0.9 s · stop line 40 m");
  EXPECT_EQ(rlvw_banner(p, 1002), "");
  // Red already (time_to_red null).
  ASSERT_TRUE(m.on_message(kRlvw, rlvw_msg("updated", nullptr).dump(), at(0.5)));
  EXPECT_EQ(rlvw_banner(m.picture(at(0.5)), 1001), "RED LIGHT WARNING · red · stop line 40 m");
  // A clear of another signal group (a former lane) leaves it up; its own clear ends it.
  ASSERT_TRUE(m.on_message(kRlvw, rlvw_msg("cleared", nullptr, 4).dump(), at(0.6)));
  EXPECT_NE(m.picture(at(0.6)).rlvw_for(1001), nullptr);
  ASSERT_TRUE(m.on_message(kRlvw, rlvw_msg("cleared", nullptr).dump(), at(0.7)));
  EXPECT_EQ(m.picture(at(0.7)).rlvw_for(1001), nullptr);
  EXPECT_EQ(rlvw_banner(m.picture(at(0.7)), 1001), "");
}

TEST(RlvwMonitor, DroppedAfterTwoSecondsUnlessTheLaneSignalStillSaysRlvw) {
  V2xMonitor m;
  m.on_message(kRlvw, rlvw_msg("raised").dump(), at(0));
  EXPECT_NE(m.picture(at(2.0)).rlvw_for(1001), nullptr);
  EXPECT_EQ(m.picture(at(2.01)).rlvw_for(1001), nullptr);  // a station that died mid-warning
  // The signal message's flag (10 Hz) keeps it up between the warning's own updates.
  m.on_message(kSignal,
               signal_msg("amber", "protected-clearance", 1.0, 1.0, 30.0, nullptr, true).dump(),
               at(2.5));
  EXPECT_NE(m.picture(at(3.0)).rlvw_for(1001), nullptr);
  // ... but not once the lane signal is stale too, nor when it says false.
  EXPECT_EQ(m.picture(at(3.6)).rlvw_for(1001), nullptr);
  m.on_message(kSignal, signal_msg("red").dump(), at(3.7));
  EXPECT_EQ(m.picture(at(3.7)).rlvw_for(1001), nullptr);
}

TEST(RlvwMonitor, BadPayloadsAreRejectedAndLeaveTheWarning) {
  V2xMonitor m;
  ASSERT_TRUE(m.on_message(kRlvw, rlvw_msg("raised").dump(), at(0)));
  auto with = [](const char* key, json v) {
    json j = rlvw_msg("updated");
    j["message"][key] = std::move(v);
    return j.dump();
  };
  const std::pair<std::string, std::string> bad[] = {
      {"{", "not JSON"},
      {"[]", "envelope"},
      {with("event", "exploded"), "'exploded'"},
      {with("intersection_id", nullptr), "intersection_id"},
      {with("signal_group", 300), "signal_group"},
      {with("lane_id", "2"), "lane_id"},
      {with("speed_mps", -1.0), "speed_mps"},
      {with("distance_to_stop_line_m", "far"), "distance_to_stop_line_m"},
      {with("time_to_red_s", "now"), "time_to_red_s"},
      {with("stopping_distance_m", nullptr), "stopping_distance_m"},
  };
  for (const auto& [payload, named] : bad) {
    EXPECT_FALSE(m.on_message(kRlvw, payload, at(0.1))) << payload;
    EXPECT_NE(m.last_error().find(named), std::string::npos) << payload << " → " << m.last_error();
  }
  EXPECT_EQ(m.rejected(), std::size(bad));
  const V2xPicture picture = m.picture(at(0.2));  // rlvw_for points into it
  const RlvwAlert* a = picture.rlvw_for(1001);
  ASSERT_NE(a, nullptr);
  EXPECT_NEAR(*a->time_to_red_s, 1.0 - 0.2, 1e-9);  // as raised, aged by 0.2 s
}

TEST(RlvwAlarm, ItsOwnSoundBetweenTheCollisionWarningsInPriority) {
  V2xMonitor m;
  const auto lcrw = [](const char* severity) {
    return json{{"type", "lcrw_warning"},
                {"message",
                 {{"other_station_id", 1002},
                  {"event", "raised"},
                  {"collision_case", "frontal"},
                  {"severity", severity},
                  {"ttc_s", 2.0},
                  {"distance_m", 30.0}}}}
        .dump();
  };
  EXPECT_EQ(alarm_for(m.picture(at(0)), 1001), Alarm::kOff);
  m.on_message("its/1001/app/lcrw", lcrw("warning"), at(0));
  EXPECT_EQ(alarm_for(m.picture(at(0)), 1001), Alarm::kWarning);
  m.on_message(kRlvw, rlvw_msg("raised").dump(), at(0));
  EXPECT_EQ(alarm_for(m.picture(at(0)), 1001), Alarm::kRedLight);
  EXPECT_EQ(alarm_for(m.picture(at(0)), 1002), Alarm::kOff);
  m.on_message("its/1001/app/lcrw", lcrw("critical"), at(0));
  EXPECT_EQ(alarm_for(m.picture(at(0)), 1001), Alarm::kCritical);
}

}  // namespace
}  // namespace tb::client::v2x
