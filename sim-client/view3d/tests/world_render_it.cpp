// The world's marks and objects rendered for real (llvmpipe in an Xvfb this test starts), and
// checked where the camera's matrices project the file's positions: a stop line in front of
// a car waiting at the shipped four-way junction, and a building where a hand-made file puts
// it; and (issue 34) the HUD's signal panel and red-light banner over a car approaching that
// junction, fed the MQTT contract's messages. Frames are left in Testing/Temporary/view3d/ for
// a person to look at.
#include <gtest/gtest.h>

#include <SDL.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>

#include <fmt/format.h>

#include "common/map/opendrive/queries.hpp"
#include "common/map/opendrive/reader.hpp"
#include "common/map/opendrive/signal_layout.hpp"
#include "sim-client/v2x/monitor.hpp"
#include "sim-client/view/scene.hpp"
#include "sim-client/view3d/driver_view.hpp"
#include "sim-client/view3d/road_objects_node.hpp"
#include "sim-client/view3d/tests/render_fixture.hpp"

namespace tb::client::view3d {
namespace {

namespace fs = std::filesystem;
namespace odr = map::odr;

bool white_near(const Image& im, const osg::Vec2d& p) {
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy) {
      const Rgb c = pixel(im, static_cast<int>(p.x()) + dx, static_cast<int>(p.y()) + dy);
      if (c.r > 200 && c.g > 200 && c.b > 200)
        return true;
    }
  return false;
}

VehicleLook look(const std::string& id, const std::string& colour) {
  VehicleLook l;
  l.id = id;
  l.station_id = 1001;
  const SDL_Color c = *parse_colour(colour);
  l.colour = {c.r / 255.0f, c.g / 255.0f, c.b / 255.0f};
  return l;
}

class WorldRender : public RenderTest {};

FrameInput frame(std::shared_ptr<World> w, const wire::VehicleState& s, CameraMode camera) {
  FrameInput in;
  in.world = std::move(w);
  in.vehicles = {s};
  in.sim_time_ns = 5'000'000'000;
  in.own = 0;
  in.choice.camera = camera;
  in.status.connection = "connected to test";
  return in;
}

std::shared_ptr<World> world_of(odr::RoadNetwork net, const std::string& colour, int version) {
  auto w = std::make_shared<World>();
  w->network = std::make_shared<const odr::RoadNetwork>(std::move(net));
  w->vehicles = {look("me", colour)};
  w->version = version;
  return w;
}

TEST_F(WorldRender, AStopLineIsVisibleInFrontOfACarWaitingAtTheJunction) {
  // Red waits on the east arm (road 1) in lane 1, towards the junction (west), its front 10 m
  // behind the stop line (s 4.5: x 16.5, lane 1 is y 0 to 3.5), the chase camera behind it
  // (nearer, the car hides the line from a camera above and behind it).
  const fs::path file = maps_dir() / "four_way_junction.xodr";
  odr::RoadNetwork with = odr::load_opendrive(file.string());
  odr::RoadNetwork without = odr::load_opendrive(file.string());
  for (odr::Road& r : without.roads) {
    r.signals.clear();
    r.objects.clear();
  }
  const odr::Road& arm = with.roads[static_cast<std::size_t>(with.road_index("1"))];
  const odr::SurfacePose car = arm.surface(16.75, 1.75);
  wire::VehicleState s;
  s.position = {car.x, car.y, car.z};
  s.yaw = static_cast<float>(std::numbers::pi);
  s.sim_time_ns = 5'000'000'000;
  const double line_z = arm.surface(4.5, 1.75).z + 0.02;

  const Image marked =
      shoot(frame(world_of(std::move(with), "#d02020", 1), s, CameraMode::kChase), "stop_line");
  const CameraPose pose = view_->pose();
  const Image plain =
      shoot(frame(world_of(std::move(without), "#d02020", 2), s, CameraMode::kChase),
            "stop_line_without_marks");
  int points = 0, white = 0, white_without = 0;
  for (double y = 0.3; y <= 3.21; y += 0.2) {
    const osg::Vec2d p = project(pose, {16.5, y, line_z});
    ASSERT_GT(p.x(), 2);
    ASSERT_LT(p.x(), kW - 2);
    ASSERT_GT(p.y(), 150);  // below the mirror
    ASSERT_LT(p.y(), kH - 2);
    // In front of the car: above it on the screen, near the middle.
    EXPECT_LT(p.y(), project(pose, {car.x - 2.25, car.y, car.z}).y());
    ++points;
    white += white_near(marked, p);
    white_without += white_near(plain, p);
  }
  EXPECT_GE(white, points * 8 / 10) << "of " << points << " points on the stop line";
  EXPECT_LE(white_without, points / 10) << "the same frame without the marks";
}

TEST_F(WorldRender, ABuildingIsDrawnWhereTheFileStandsIt) {
  // One 200 m road east along y = 0; a house at s 100, t -20 (so x 94 to 106, y -24 to -16),
  // 9 m tall; seen from the top camera over a car at (100, 0).
  const std::string xml =
      R"(<?xml version="1.0"?><OpenDRIVE><header revMajor="1" revMinor="7"/>)"
      R"(<road id="1" length="200" junction="-1"><planView><geometry s="0" x="0" y="0" hdg="0" length="200"><line/></geometry></planView>)"
      R"(<lanes><laneSection s="0"><left><lane id="1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></left><center><lane id="0" type="none"/></center><right><lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></right></laneSection></lanes>)"
      R"(<objects><object id="house" type="building" s="100" t="-20" zOffset="0" hdg="0" length="12" width="8" height="9"/></objects></road></OpenDRIVE>)";
  wire::VehicleState s;
  s.position = {100.0, -1.75, 0.0};
  s.sim_time_ns = 5'000'000'000;
  odr::RoadNetwork bare = odr::parse_opendrive(xml, "house.xodr");
  bare.roads[0].objects.clear();
  FrameInput in =
      frame(world_of(odr::parse_opendrive(xml, "house.xodr"), "#2050d0", 1), s, CameraMode::kTop);
  in.own = -1;
  in.choice.target = 0;
  const Image im = shoot(in, "building_top");
  const CameraPose pose = view_->pose();
  in.world = world_of(std::move(bare), "#2050d0", 2);
  const Image without = shoot(in, "building_top_without");
  const auto roof = roof_colour("house", 0);
  const double roof_sum = roof[0] + roof[1] + roof[2];
  auto at = [&](const Image& image, double x, double y) {
    const osg::Vec2d p = project(pose, {x, y, 9.0});
    EXPECT_GT(p.x(), 0);
    EXPECT_LT(p.x(), kW);
    EXPECT_GT(p.y(), 0);
    EXPECT_LT(p.y(), kH);
    return pixel(image, static_cast<int>(p.x()), static_cast<int>(p.y()));
  };
  // The roof's hue (the sun scales all three channels alike), and not the ground's.
  auto is_roof = [&](double x, double y) {
    const Rgb c = at(im, x, y), g = at(without, x, y);
    const double sum = c.r + c.g + c.b;
    const bool hue = sum > 60 && std::fabs(c.r / sum - roof[0] / roof_sum) < 0.04 &&
                     std::fabs(c.g / sum - roof[1] / roof_sum) < 0.04;
    const bool changed = std::abs(c.r - g.r) + std::abs(c.g - g.g) + std::abs(c.b - g.b) > 30;
    return hue && changed;
  };
  // The roof over the footprint, just inside each corner and in the middle.
  for (const auto& [x, y] :
       {std::pair{100.0, -20.0}, {94.7, -23.3}, {105.3, -23.3}, {94.7, -16.7}, {105.3, -16.7}})
    EXPECT_TRUE(is_roof(x, y)) << "no roof at (" << x << ", " << y << ")";
  // Nothing of it beyond: 1.5 m outside each side the picture is the one without the house.
  for (const auto& [x, y] :
       {std::pair{92.5, -20.0}, {107.5, -20.0}, {100.0, -25.5}, {100.0, -14.5}}) {
    const Rgb c = at(im, x, y), g = at(without, x, y);
    EXPECT_LT(std::abs(c.r - g.r) + std::abs(c.g - g.g) + std::abs(c.b - g.b), 10)
        << "something drawn outside the house at (" << x << ", " << y << ")";
  }
}

// The `its/<id>/app/signal` message of the contract (issue 34), as a station publishes it.
std::string signal_payload(const char* state, const char* event_state, double distance,
                           const char* advice = "null", bool rlvw = false) {
  return fmt::format(
      R"({{"type":"signal","origin":"on_board_application","message":{{"intersection_id":1,)"
      R"("signal_group":2,"lane_id":1,"state":"{}","event_state":"{}","time_to_change_s":3.6,)"
      R"("likely_time_to_change_s":4.2,"distance_to_stop_line_m":{},"advice":{},"rlvw":{}}}}})",
      state, event_state, distance, advice, rlvw);
}

std::string rlvw_payload(const char* event, double distance) {
  return fmt::format(R"({{"type":"rlvw_warning","message":{{"station_id":1001,"intersection_id":1,)"
                     R"("signal_group":2,"lane_id":1,"event":"{}","severity":"warning",)"
                     R"("distance_to_stop_line_m":{},"speed_mps":16.7,"time_to_red_s":1.2,)"
                     R"("stopping_distance_m":63.1,"clear_reason":"{}","raised_at":1795000000000,)"
                     R"("updated_at":1795000000000}}}})",
                     event, distance, event == std::string("cleared") ? "passed" : "none");
}

clock::SteadyTime at_s(double s) {
  return clock::SteadyTime{
      std::chrono::duration_cast<clock::Duration>(std::chrono::duration<double>(100.0 + s))};
}

bool lamp_red(Rgb c) {
  return c.r > 220 && c.g < 80 && c.b < 80;
}
bool lamp_amber(Rgb c) {
  return c.r > 220 && c.g > 150 && c.g < 215 && c.b < 60;
}
bool lamp_green(Rgb c) {
  return c.g > 210 && c.r < 80 && c.b < 130;
}
bool lamp_unlit(Rgb c) {
  return c.r < 70 && c.g < 70 && c.b < 70;
}
bool lamp_grey(Rgb c) {
  return c.r > 90 && c.r < 130 && std::abs(c.r - c.g) < 10 && std::abs(c.b - c.g) < 12;
}

TEST_F(WorldRender, SignalPanelLitByStateAndTheRedLightBanner) {
  // Red drives on the east arm (road 1, lane 1) towards the junction at 60 km/h, 36 m before
  // the stop line (s 4.5), chase camera: the picture a driver gets with the warning.
  const fs::path file = maps_dir() / "four_way_junction.xodr";
  odr::RoadNetwork net = odr::load_opendrive(file.string());
  const odr::Road& arm = net.roads[static_cast<std::size_t>(net.road_index("1"))];
  const odr::SurfacePose car = arm.surface(42.75, 1.75);
  wire::VehicleState s;
  s.position = {car.x, car.y, car.z};
  s.yaw = static_cast<float>(std::numbers::pi);
  s.speed = 16.7f;
  s.gear = 3;
  s.controls.throttle = 0.3f;
  s.sim_time_ns = 5'000'000'000;
  auto world = world_of(std::move(net), "#d02020", 1);
  v2x::V2xMonitor monitor;
  FrameInput in = frame(world, s, CameraMode::kChase);
  in.v2x_enabled = true;
  in.status.mqtt = "MQTT 127.0.0.1:1883";

  // Window pixels (origin bottom left) to the image's (origin top left).
  const auto lamp_pixel = [&](const Image& im, int i) {
    const Hud::Lamp& l = view_->hud().signal_lamps()[static_cast<std::size_t>(i)];
    return pixel(im, static_cast<int>(l.x), kH - 1 - static_cast<int>(l.y));
  };
  const auto red_share = [&](const Image& im, const Rect& r) {
    int red = 0, all = 0;
    for (int y = kH - r.y - r.h + 5; y < kH - r.y - 5; y += 2)
      for (int x = r.x + 5; x < r.x + r.w - 5; x += 2) {
        const Rgb c = pixel(im, x, y);
        red += c.r > 150 && c.g < 60 && c.b < 60;
        ++all;
      }
    return static_cast<double>(red) / all;
  };

  const Image before = shoot(in, "signal_none");
  EXPECT_FALSE(view_->hud().signal().has_value());

  // Amber, and the car cannot stop before the red: the amber lamp lit (red and green dark) and
  // the red-light banner.
  double t = 0.0;
  ASSERT_TRUE(monitor.on_message("its/1001/app/signal",
                                 signal_payload("amber", "protected-clearance", 36.0, "null", true),
                                 at_s(t)))
      << monitor.last_error();
  ASSERT_TRUE(monitor.on_message("its/1001/app/rlvw", rlvw_payload("raised", 36.0), at_s(t)))
      << monitor.last_error();
  in.v2x = monitor.picture(at_s(t + 0.1));
  const Image warned = shoot(in, "signal_amber_rlvw");
  ASSERT_TRUE(view_->hud().signal().has_value());
  EXPECT_EQ(view_->hud().signal()->countdown, "5 s");
  EXPECT_TRUE(lamp_unlit(lamp_pixel(warned, 0)));
  EXPECT_TRUE(lamp_amber(lamp_pixel(warned, 1)));
  EXPECT_TRUE(lamp_unlit(lamp_pixel(warned, 2)));
  ASSERT_FALSE(view_->hud().rlvw_banner().empty());
  // 1.2 s to red when sent, 0.1 s ago.
  EXPECT_NE(view_->hud().rlvw_banner().find("red in 1.1 s"), std::string::npos)
      << view_->hud().rlvw_banner();
  EXPECT_GT(red_share(warned, view_->hud().rlvw_banner_rect()), 0.6);

  // Every state lights its own lamps (dark and unavailable: all three grey).
  struct Case {
    const char* state;
    const char* event_state;
    bool (*top)(Rgb);
    bool (*middle)(Rgb);
    bool (*bottom)(Rgb);
  };
  const Case cases[] = {
      {"red", "stop-And-Remain", lamp_red, lamp_unlit, lamp_unlit},
      {"red_amber", "pre-Movement", lamp_red, lamp_amber, lamp_unlit},
      {"green", "protected-Movement-Allowed", lamp_unlit, lamp_unlit, lamp_green},
      {"dark", "dark", lamp_grey, lamp_grey, lamp_grey},
      {"unavailable", "unavailable", lamp_grey, lamp_grey, lamp_grey},
  };
  for (const Case& c : cases) {
    t += 0.1;
    ASSERT_TRUE(monitor.on_message("its/1001/app/signal",
                                   signal_payload(c.state, c.event_state, 36.0,
                                                  R"({"min_speed_kmh":38.5,"max_speed_kmh":50.0})"),
                                   at_s(t)))
        << monitor.last_error();
    in.v2x = monitor.picture(at_s(t));
    const Image im = shoot(in, fmt::format("signal_{}", c.state));
    ASSERT_TRUE(view_->hud().signal().has_value()) << c.state;
    EXPECT_EQ(view_->hud().signal()->advice, "39–50 km/h");
    const Rgb top = lamp_pixel(im, 0), middle = lamp_pixel(im, 1), bottom = lamp_pixel(im, 2);
    EXPECT_TRUE(c.top(top)) << c.state << " top " << top.r << "," << top.g << "," << top.b;
    EXPECT_TRUE(c.middle(middle)) << c.state << " middle " << middle.r << "," << middle.g << ","
                                  << middle.b;
    EXPECT_TRUE(c.bottom(bottom)) << c.state << " bottom " << bottom.r << "," << bottom.g << ","
                                  << bottom.b;
  }
  // The warning cleared and the lane left: neither banner nor panel; where the lamps were,
  // the picture is the one drawn before any message.
  const Rect banner = view_->hud().rlvw_banner_rect();
  t += 0.1;
  ASSERT_TRUE(monitor.on_message("its/1001/app/rlvw", rlvw_payload("cleared", 30.0), at_s(t)));
  ASSERT_TRUE(monitor.on_message("its/1001/app/signal",
                                 R"({"type":"signal","message":{"lane":null}})", at_s(t)));
  in.v2x = monitor.picture(at_s(t));
  const std::array<Hud::Lamp, 3> lamps = view_->hud().signal_lamps();
  const Image gone = shoot(in, "signal_gone");
  EXPECT_FALSE(view_->hud().signal().has_value());
  EXPECT_TRUE(view_->hud().rlvw_banner().empty());
  EXPECT_LT(red_share(gone, banner), 0.02);
  for (const Hud::Lamp& l : lamps) {
    const int x = static_cast<int>(l.x), y = kH - 1 - static_cast<int>(l.y);
    const Rgb a = pixel(gone, x, y), b = pixel(before, x, y);
    EXPECT_LE(std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b), 6)
        << a.r << "," << a.g << "," << a.b << " against " << b.r << "," << b.g << "," << b.b;
  }
}

TEST_F(WorldRender, TrafficLightsAreLitByTheirSignalGroups) {
  // Two heads of the shipped four-way junction on neighbouring arms (different signal groups),
  // seen by the orbit camera from where both lamp faces look: one group red, the other green,
  // then red + amber and a group the message lacks (dark). Checked at the pixels the lamps'
  // centres project to.
  const fs::path file = maps_dir() / "four_way_junction.xodr";
  odr::RoadNetwork net = odr::load_opendrive(file.string());
  const odr::SignalLayout layout(net);
  ASSERT_GE(layout.heads().size(), 2u);
  // The face of a head looks against its traffic's heading.
  const auto face = [](const odr::SignalHead& h) {
    return osg::Vec3d(-std::cos(h.pose.heading), -std::sin(h.pose.heading), 0.0);
  };
  const auto at = [](const odr::SignalHead& h) { return osg::Vec3d(h.pose.x, h.pose.y, h.pose.z); };
  // Two heads of different groups on neighbouring arms (their faces turned 90° apart), and the
  // camera on their faces' bisector, far enough that it looks at both faces within 60° of
  // straight on, its field of view narrowed to the two (a long lens).
  std::size_t a = 0, b = 0;
  bool found = false;
  osg::Vec3d mid, dir;
  double distance = 0.0;
  for (std::size_t i = 0; i < layout.heads().size() && !found; ++i)
    for (std::size_t j = i + 1; j < layout.heads().size() && !found; ++j) {
      const auto& hi = layout.heads()[i];
      const auto& hj = layout.heads()[j];
      if (hi.signal_group == hj.signal_group || hi.signal_group == 0 || hj.signal_group == 0 ||
          std::abs(face(hi) * face(hj)) > 0.1)
        continue;
      osg::Vec3d d = face(hi) + face(hj);
      d.normalize();
      const osg::Vec3d m = (at(hi) + at(hj)) * 0.5;
      for (double dist = 20.0; dist <= 120.0 && !found; dist += 5.0) {
        const osg::Vec3d eye = m + d * dist;
        osg::Vec3d ei = eye - at(hi), ej = eye - at(hj);
        ei.normalize();
        ej.normalize();
        if (std::min(ei * face(hi), ej * face(hj)) > 0.5) {
          a = i;
          b = j;
          mid = m;
          dir = d;
          distance = dist;
          found = true;
        }
      }
    }
  ASSERT_TRUE(found) << "no two heads of different groups face one camera";
  constexpr double kElevationDeg = 5.0;
  const odr::SignalHead& ha = layout.heads()[a];
  const odr::SignalHead& hb = layout.heads()[b];
  const std::uint16_t junction = layout.junctions().front().intersection_id;
  const auto group = [&](const odr::SignalHead& h) {
    return static_cast<std::uint8_t>(h.signal_group);
  };

  // The watched car stands on the road between the two heads; the camera orbits it.
  wire::VehicleState s;
  s.position = {mid.x(), mid.y(), mid.z() - 2.5};
  s.sim_time_ns = 5'000'000'000;
  FrameInput in = frame(world_of(std::move(net), "#e8e8e8", 1), s, CameraMode::kOrbit);
  in.own = -1;
  in.choice.target = 0;
  in.choice.orbit_azimuth_deg = std::atan2(dir.y(), dir.x()) * 180.0 / std::numbers::pi;
  in.choice.orbit_elevation_deg = kElevationDeg;
  in.choice.orbit_distance_m = distance;
  {
    // Both heads within the picture, with 5° to spare on either side.
    const osg::Vec3d eye = mid + dir * distance;
    osg::Vec3d ea = at(ha) - eye, eb = at(hb) - eye;
    ea.normalize();
    eb.normalize();
    in.choice.hfov_deg = std::acos(ea * eb) * 180.0 / std::numbers::pi + 10.0;
  }
  using P = wire::sim::MovementPhaseState;
  in.signals = {{junction, group(ha), P::kStopAndRemain, 0, 0},
                {junction, group(hb), P::kProtectedMovementAllowed, 0, 0}};
  if (group(hb) < group(ha))
    std::swap(in.signals[0], in.signals[1]);
  const Image im = shoot(in, "signal_heads_red_green");
  const CameraPose pose = view_->pose();
  const SignalHeadsNode* heads = view_->signal_heads();
  ASSERT_NE(heads, nullptr);
  ASSERT_EQ(heads->heads(), layout.heads().size());
  // Every pixel of a 3 x 3 square around a lamp's centre shows it.
  const auto lamp = [&](const Image& image, std::size_t head, SignalHeadsNode::LampIndex l,
                        bool (*is)(Rgb)) {
    const osg::Vec2d p = project(pose, heads->lamp_centre(head, l));
    EXPECT_GT(p.x(), 2);
    EXPECT_LT(p.x(), kW - 2);
    EXPECT_GT(p.y(), 2);
    EXPECT_LT(p.y(), kH - 2);
    int hits = 0;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        hits += is(pixel(image, static_cast<int>(p.x()) + dx, static_cast<int>(p.y()) + dy));
    return hits == 9;
  };
  using L = SignalHeadsNode;
  EXPECT_TRUE(lamp(im, a, L::kRed, lamp_red)) << "head " << a << " red lamp";
  EXPECT_TRUE(lamp(im, a, L::kAmber, lamp_unlit));
  EXPECT_TRUE(lamp(im, a, L::kGreen, lamp_unlit));
  EXPECT_TRUE(lamp(im, b, L::kRed, lamp_unlit));
  EXPECT_TRUE(lamp(im, b, L::kAmber, lamp_unlit));
  EXPECT_TRUE(lamp(im, b, L::kGreen, lamp_green)) << "head " << b << " green lamp";
  // The red lamp is above the green one on the screen (red at the top of a head).
  EXPECT_LT(project(pose, heads->lamp_centre(a, L::kRed)).y(),
            project(pose, heads->lamp_centre(a, L::kGreen)).y());

  // The driver's picture of the red: a car 15 m before that head's stop line, chase camera.
  const odr::SignalApproach* lane = nullptr;
  for (const auto& ap : layout.approaches())
    if (ap.head == a)
      lane = &ap;
  ASSERT_NE(lane, nullptr);
  {
    FrameInput chase = in;
    // The centre 15 m + half a car before the line, on the lane's surface (the arm climbs).
    const double back = 15.0 + 2.2;
    const odr::Road& road = in.world->network->roads[static_cast<std::size_t>(lane->road)];
    odr::SurfacePose on = odr::lane_pose(*in.world->network, lane->road, lane->lane,
                                         std::clamp(lane->stop_s + back, 0.0, road.length));
    const odr::SurfacePose other =
        odr::lane_pose(*in.world->network, lane->road, lane->lane,
                       std::clamp(lane->stop_s - back, 0.0, road.length));
    const auto miss = [&](const odr::SurfacePose& p) {
      return std::hypot(p.x - (lane->stop.x - back * std::cos(lane->stop.heading)),
                        p.y - (lane->stop.y - back * std::sin(lane->stop.heading)));
    };
    if (miss(other) < miss(on))
      on = other;
    chase.vehicles[0].position = {on.x, on.y, on.z};
    chase.vehicles[0].yaw = static_cast<float>(lane->stop.heading);
    chase.vehicles[0].speed = 8.0f;
    chase.own = 0;
    chase.choice = ViewChoice{};
    const Image driver = shoot(chase, "signal_heads_chase_red");
    const CameraPose chase_pose = view_->pose();
    const osg::Vec2d p = project(chase_pose, heads->lamp_centre(a, L::kRed));
    ASSERT_GT(p.y(), 150);  // below the mirror
    int red = 0;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        red += lamp_red(pixel(driver, static_cast<int>(p.x()) + dx, static_cast<int>(p.y()) + dy));
    EXPECT_EQ(red, 9) << "the red lamp ahead of the driver";
  }

  // Red + amber for the first group, the second group missing from the message: dark.
  in.signals = {{junction, group(ha), P::kPreMovement, 0, 0}};
  const Image next = shoot(in, "signal_heads_red_amber_dark");
  EXPECT_TRUE(lamp(next, a, L::kRed, lamp_red));
  EXPECT_TRUE(lamp(next, a, L::kAmber, lamp_amber)) << "head " << a << " amber lamp";
  EXPECT_TRUE(lamp(next, a, L::kGreen, lamp_unlit));
  for (auto l : {L::kRed, L::kAmber, L::kGreen})
    EXPECT_TRUE(lamp(next, b, l, lamp_unlit)) << "head " << b << " lamp " << l;
}

}  // namespace
}  // namespace tb::client::view3d
