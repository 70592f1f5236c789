// The HUD's layout of the signal panel and the red-light banner (issue 34), from the scene
// graph alone (no GL): which panel shows for which station, where the icon's lamps are, and
// that nothing overlaps the other warning or leaves the window.
#include "sim-client/view3d/hud.hpp"

#include <gtest/gtest.h>

#include <memory>

#include <nlohmann/json.hpp>

namespace tb::client::view3d {
namespace {

using nlohmann::json;

clock::SteadyTime at(double s) {
  return clock::SteadyTime{
      std::chrono::duration_cast<clock::Duration>(std::chrono::duration<double>(100.0 + s))};
}

std::string signal_msg(const std::string& state, const std::string& event_state) {
  return json{{"type", "signal"},
              {"message",
               {{"intersection_id", 1},
                {"signal_group", 3},
                {"lane_id", 2},
                {"state", state},
                {"event_state", event_state},
                {"time_to_change_s", 4.2},
                {"likely_time_to_change_s", nullptr},
                {"distance_to_stop_line_m", 37.0},
                {"advice", {{"min_speed_kmh", 20.0}, {"max_speed_kmh", 35.0}}},
                {"rlvw", false}}}}
      .dump();
}

std::string rlvw_msg() {
  return json{{"type", "rlvw_warning"},
              {"message",
               {{"intersection_id", 1},
                {"signal_group", 3},
                {"lane_id", 2},
                {"event", "raised"},
                {"severity", "warning"},
                {"distance_to_stop_line_m", 30.0},
                {"speed_mps", 16.0},
                {"time_to_red_s", 0.8},
                {"stopping_distance_m", 58.7}}}}
      .dump();
}

std::string lcrw_msg() {
  return json{{"type", "lcrw_warning"},
              {"message",
               {{"other_station_id", 1002},
                {"event", "raised"},
                {"collision_case", "frontal"},
                {"severity", "warning"},
                {"ttc_s", 3.0},
                {"distance_m", 40.0}}}}
      .dump();
}

FrameInput frame(const v2x::V2xMonitor& m, double t, int own = 0) {
  auto w = std::make_shared<World>();
  for (std::uint32_t station : {1001u, 1002u}) {
    VehicleLook l;
    l.id = std::to_string(station);
    l.station_id = station;
    w->vehicles.push_back(l);
  }
  FrameInput in;
  in.world = w;
  in.vehicles.resize(2);
  in.own = own;
  in.v2x_enabled = true;
  in.v2x = m.picture(at(t));
  return in;
}

bool inside(const Rect& outer, float x, float y) {
  return x >= outer.x && x <= outer.x + outer.w && y >= outer.y && y <= outer.y + outer.h;
}

bool overlap(const Rect& a, const Rect& b) {
  return a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h;
}

TEST(HudSignal, PanelForTheOwnStationWithItsLampsInsideIt) {
  Hud hud;
  v2x::V2xMonitor m;
  ASSERT_TRUE(
      m.on_message("its/1001/app/signal", signal_msg("amber", "protected-clearance"), at(0)));
  hud.update(frame(m, 0.1), 0, 1280, 720, nullptr);
  ASSERT_TRUE(hud.signal().has_value());
  EXPECT_EQ(hud.signal()->countdown, "5 s");
  EXPECT_TRUE(hud.signal()->amber);
  const Rect r = hud.signal_rect();
  EXPECT_GE(r.x, 0);
  EXPECT_LE(r.x + r.w, 1280);
  EXPECT_GE(r.y, 0);
  EXPECT_LE(r.y + r.h, 720);
  const auto& lamps = hud.signal_lamps();
  for (const auto& l : lamps) {
    EXPECT_TRUE(inside(r, l.x - l.r, l.y - l.r)) << l.x << "," << l.y;
    EXPECT_TRUE(inside(r, l.x + l.r, l.y + l.r)) << l.x << "," << l.y;
  }
  // Red on top, green at the bottom, one column, lamps not touching.
  EXPECT_GT(lamps[0].y, lamps[1].y + 2 * lamps[0].r);
  EXPECT_GT(lamps[1].y, lamps[2].y + 2 * lamps[1].r);
  EXPECT_FLOAT_EQ(lamps[0].x, lamps[2].x);
  // Another station's lane is not the driver's.
  hud.update(frame(m, 0.1, 1), 1, 1280, 720, nullptr);
  EXPECT_FALSE(hud.signal().has_value());
  // Stale after a second.
  hud.update(frame(m, 1.2), 0, 1280, 720, nullptr);
  EXPECT_FALSE(hud.signal().has_value());
}

TEST(HudSignal, NothingWithoutMqtt) {
  Hud hud;
  v2x::V2xMonitor m;
  m.on_message("its/1001/app/signal", signal_msg("red", "stop-And-Remain"), at(0));
  m.on_message("its/1001/app/rlvw", rlvw_msg(), at(0));
  FrameInput in = frame(m, 0.1);
  in.v2x_enabled = false;
  hud.update(in, 0, 1280, 720, nullptr);
  EXPECT_FALSE(hud.signal().has_value());
  EXPECT_TRUE(hud.rlvw_banner().empty());
}

TEST(HudSignal, RedLightBannerUnderTheCollisionBannerAndClearOfThePanel) {
  Hud hud;
  v2x::V2xMonitor m;
  m.on_message("its/1001/app/signal", signal_msg("amber", "protected-clearance"), at(0));
  m.on_message("its/1001/app/rlvw", rlvw_msg(), at(0));
  // As DriverView puts it at 1280 x 720: 30 % of the width, 3.2:1, 14 px under the top.
  const Rect mirror{448, 586, 384, 120};
  hud.update(frame(m, 0.1), 0, 1280, 720, &mirror);
  // 0.8 s to red when sent, 0.1 s ago.
  EXPECT_EQ(hud.rlvw_banner(), "RED LIGHT WARNING · red in 0.7 s · stop line 30 m");
  const Rect alone = hud.rlvw_banner_rect();
  EXPECT_LE(alone.y + alone.h, mirror.y);  // under the mirror
  EXPECT_FALSE(overlap(alone, hud.signal_rect()));
  m.on_message("its/1001/app/lcrw", lcrw_msg(), at(0));
  hud.update(frame(m, 0.1), 0, 1280, 720, &mirror);
  ASSERT_FALSE(hud.banner().empty());
  const Rect both = hud.rlvw_banner_rect();
  EXPECT_LT(both.y + both.h, hud.banner_rect().y + 1);  // below the collision banner
  EXPECT_FALSE(overlap(both, hud.banner_rect()));
  EXPECT_FALSE(overlap(both, hud.signal_rect()));
  EXPECT_FALSE(overlap(hud.banner_rect(), hud.signal_rect()));
  // Watching: the followed car's, with its station named.
  hud.update(frame(m, 0.1, -1), 0, 1280, 720, nullptr);
  EXPECT_EQ(hud.rlvw_banner().rfind("1001: RED LIGHT WARNING", 0), 0u);
  EXPECT_TRUE(hud.signal().has_value());
}

}  // namespace
}  // namespace tb::client::view3d
