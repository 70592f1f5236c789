// The 3D view rendered for real: Mesa's llvmpipe into an Xvfb this test starts, checked
// structurally (colours at positions worked out from the camera pose), not against golden
// images. Every frame checked is also written to the test log folder
// (build/…/Testing/Temporary/view3d/) for a person to look at.
#include <gtest/gtest.h>

#include <SDL.h>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>

#include "common/clock/clock.hpp"
#include "common/map/builtin_network.hpp"
#include "common/mqtt/mosquitto_client.hpp"
#include "common/mqtt/tests/test_broker.hpp"
#include "sim-client/v2x/subscriber.hpp"
#include "sim-client/view/scene.hpp"
#include "sim-client/view3d/driver_view.hpp"
#include "sim-client/view3d/tests/render_fixture.hpp"

namespace tb::client::view3d {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

struct Box {
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1, n = 0;
  void add(int x, int y) {
    x0 = std::min(x0, x);
    y0 = std::min(y0, y);
    x1 = std::max(x1, x);
    y1 = std::max(y1, y);
    ++n;
  }
  double cy() const { return (y0 + y1) / 2.0; }
  int height() const { return y1 - y0 + 1; }
  int width() const { return x1 - x0 + 1; }
};

Box find(const Image& im, const std::function<bool(Rgb)>& is) {
  Box b;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x)
      if (is(pixel(im, x, y)))
        b.add(x, y);
  return b;
}

VehicleLook look(const std::string& id, std::uint32_t station, const std::string& colour) {
  VehicleLook l;
  l.id = id;
  l.station_id = station;
  const SDL_Color c = *parse_colour(colour);
  l.colour = {c.r / 255.0f, c.g / 255.0f, c.b / 255.0f};
  l.length_m = 4.5f;
  l.width_m = 1.8f;
  l.height_m = 1.45f;
  l.wheelbase_m = 2.64f;
  l.track_m = 1.54f;
  l.wheel_radius_m = 0.32f;
  return l;
}

wire::VehicleState at(double x, double y, double yaw = 0.0) {
  wire::VehicleState s;
  s.position = {x, y, 0.0};
  s.yaw = static_cast<float>(yaw);
  s.sim_time_ns = 5'000'000'000;
  return s;
}

/// A straight 3-lane road along +x (lane centres at y = 3.5 oncoming, 0 and -3.5 forward;
/// lines at y = 5.25, 1.75 solid, -1.75 broken, -5.25 solid).
std::shared_ptr<World> straight_world(std::vector<VehicleLook> cars) {
  scenario::MapSpec spec;
  spec.type = scenario::MapType::kStraight;
  spec.lanes = 3;
  spec.oncoming_lanes = 1;
  spec.lane_width = 3.5;
  spec.length = 600.0;
  auto w = std::make_shared<World>();
  w->network = std::make_shared<const map::odr::RoadNetwork>(map::generate_network(spec));
  w->vehicles = std::move(cars);
  w->frame.emplace(geodesy::Geodetic{41.105, 29.023, 60.0});
  w->version = 1;
  return w;
}

class View3dRender : public RenderTest {};

FrameInput driving(std::shared_ptr<World> w, std::vector<wire::VehicleState> states) {
  FrameInput in;
  in.world = std::move(w);
  in.vehicles = std::move(states);
  in.sim_time_ns = 5'000'000'000;
  in.own = 0;
  in.choice.camera = CameraMode::kChase;
  in.status.connection = "connected to test";
  in.status.input = "keyboard";
  return in;
}

bool mark_white(Rgb c) {
  return c.r > 200 && c.g > 200 && c.b > 200;
}
bool asphalt(Rgb c) {
  return c.r < 110 && c.g < 110 && c.b < 110 && std::abs(c.r - c.b) < 20;
}
// The test cars' blue (#2040e0, lit), not the sky's (red above 90 even at the zenith).
bool bluish(Rgb c) {
  return c.b > c.r + 70 && c.b > c.g + 50 && c.r < 75;
}
bool greenish(Rgb c) {
  return c.g > c.r + 70 && c.g > c.b + 70;
}
bool magenta(Rgb c) {
  return c.r > c.g + 80 && c.b > c.g + 80;
}

// Outside the HUD's panels (bottom left, bottom right status) and the mirror (top).
bool clear_of_hud(const osg::Vec2d& p) {
  const double k = kH / 720.0;
  if (p.x() < 330 * k && p.y() > kH - 180 * k)
    return false;
  if (p.y() < 150 * k)
    return false;
  return p.x() >= 2 && p.y() >= 2 && p.x() < kW - 2 && p.y() < kH - 2;
}

TEST_F(View3dRender, LaneMarksWhereTheChasePoseProjectsThem) {
  auto w = straight_world({look("me", 1001, "#2040e0")});
  const FrameInput in = driving(w, {at(100.0, 0.0)});
  const Image im = shoot(in, "lane_marks_chase");
  const CameraPose& pose = view_->pose();
  int checked = 0, white = 0;
  // Solid lines, 8 to 45 m ahead of the camera.
  for (double y : {5.25, 1.75, -5.25}) {
    for (double x = 102.0; x <= 140.0; x += 2.0) {
      const osg::Vec2d p = project(pose, {x, y, 0.02}, kW, kH);
      if (!clear_of_hud(p))
        continue;
      ++checked;
      bool hit = false;
      for (int dx = -1; dx <= 1 && !hit; ++dx)
        for (int dy = -1; dy <= 1 && !hit; ++dy)
          hit = mark_white(pixel(im, static_cast<int>(p.x()) + dx, static_cast<int>(p.y()) + dy));
      white += hit;
      EXPECT_TRUE(hit) << "no mark colour at (" << x << ", " << y << ") → pixel " << p.x() << ", "
                       << p.y();
    }
  }
  EXPECT_GE(checked, 30);
  // The broken line: painted at the dashes' middles, asphalt half way between two dashes.
  for (double x0 : {108.0, 120.0, 132.0}) {
    const osg::Vec2d dash = project(pose, {x0 + 1.5, -1.75, 0.02}, kW, kH);
    const osg::Vec2d gap = project(pose, {x0 + 7.5, -1.75, 0.02}, kW, kH);
    EXPECT_TRUE(mark_white(pixel(im, static_cast<int>(dash.x()), static_cast<int>(dash.y()))))
        << "dash at x " << x0 + 1.5;
    EXPECT_TRUE(asphalt(pixel(im, static_cast<int>(gap.x()), static_cast<int>(gap.y()))))
        << "gap at x " << x0 + 7.5;
  }
  // Between the lines, the oncoming lane's middle is asphalt.
  for (double x = 106.0; x <= 140.0; x += 4.0) {
    const osg::Vec2d p = project(pose, {x, 3.5, 0.0}, kW, kH);
    EXPECT_TRUE(asphalt(pixel(im, static_cast<int>(p.x()), static_cast<int>(p.y()))))
        << "lane at x " << x;
  }
}

TEST_F(View3dRender, OwnCarInItsColourWhereTheCameraSeesIt) {
  auto w = straight_world({look("me", 1001, "#2040e0")});
  const Image im = shoot(driving(w, {at(100.0, 0.0)}), "own_car_chase");
  // The car's box as the camera sees it: a third or more the car's blue (the rest is glass,
  // lamps, bumper, wheels, and the road beside the glasshouse, which is narrower than the body
  // and stands on it behind the boot lid).
  Box want;
  for (double x : {97.75, 102.25})
    for (double y : {-0.9, 0.9})
      for (double z : {0.0, 1.45}) {
        const osg::Vec2d p = project(view_->pose(), {100.0 + (x - 100.0), y, z}, kW, kH);
        want.add(static_cast<int>(p.x()), static_cast<int>(p.y()));
      }
  int blue = 0;
  for (int y = want.y0; y <= want.y1; ++y)
    for (int x = want.x0; x <= want.x1; ++x)
      blue += bluish(pixel(im, x, y));
  EXPECT_GT(blue, want.width() * want.height() / 3)
      << "box " << want.x0 << "," << want.y0 << " - " << want.x1 << "," << want.y1;
  // And nowhere else: the blue found is inside that box.
  const Box got = find(im, bluish);
  EXPECT_GE(got.x0, want.x0 - 2);
  EXPECT_LE(got.x1, want.x1 + 2);
  EXPECT_GE(got.y0, want.y0 - 2);
  EXPECT_LE(got.y1, want.y1 + 2);
  // Nowhere near the top of the image (the car sits low, the road ahead above it).
  const Box b = find(im, bluish);
  EXPECT_GT(b.y0, kH / 2);
  EXPECT_NEAR((b.x0 + b.x1) / 2.0, kW / 2.0, 10.0);
}

TEST_F(View3dRender, ACarThirtyMetresAheadIsSmallerAndHigherThanOneTenMetresAhead) {
  auto w = straight_world(
      {look("me", 1001, "#2040e0"), look("near", 1002, "#20c020"), look("far", 1003, "#d020d0")});
  const Image im =
      shoot(driving(w, {at(100.0, 0.0), at(110.0, 3.5), at(130.0, -3.5)}), "near_and_far");
  const Box near = find(im, greenish), far = find(im, magenta);
  ASSERT_GT(near.n, 100);
  ASSERT_GT(far.n, 20);
  EXPECT_LT(far.height(), near.height());
  EXPECT_LT(far.width(), near.width());
  EXPECT_LT(far.cy(), near.cy());  // higher in the image
  // Perspective: about three times as far, about a third the size.
  EXPECT_NEAR(static_cast<double>(near.height()) / far.height(), 2.5, 0.9);
}

TEST_F(View3dRender, FiftyVehiclesRenderEachWhereItIs) {
  std::vector<VehicleLook> looks;
  std::vector<wire::VehicleState> states;
  for (int i = 0; i < 50; ++i) {
    looks.push_back(
        look("car" + std::to_string(i), static_cast<std::uint32_t>(2000 + i), "#d020d0"));
    states.push_back(at(20.0 + 10.0 * (i / 3), 3.5 * (1 - i % 3), i % 3 == 0 ? 3.14159 : 0.0));
  }
  auto w = straight_world(looks);
  FrameInput in = driving(w, states);
  in.own = -1;  // watching from above
  in.choice.camera = CameraMode::kTop;
  in.choice.target = 25;
  in.choice.top_zoom = 0.3;
  const auto t0 = std::chrono::steady_clock::now();
  const Image im = shoot(in, "fifty_vehicles_top");
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(view_->vehicles().size(), 50u);
  int seen = 0, visible = 0;
  for (const auto& s : states) {
    const osg::Vec2d p = project(view_->pose(), {s.position[0], s.position[1], 1.0}, kW, kH);
    if (!clear_of_hud(p))
      continue;
    ++visible;
    seen += magenta(pixel(im, static_cast<int>(p.x()), static_cast<int>(p.y())));
  }
  EXPECT_GE(visible, 40);
  EXPECT_EQ(seen, visible);
  RecordProperty("two_frames_ms", std::to_string(ms));
}

TEST_F(View3dRender, CockpitHasADashboardAndTheMirrorShowsTheCarBehind) {
  auto w = straight_world({look("me", 1001, "#2040e0"), look("behind", 1002, "#20c020")});
  FrameInput in = driving(w, {at(100.0, 0.0), at(88.0, 0.0)});
  in.choice.camera = CameraMode::kCockpit;
  const Image im = shoot(in, "cockpit_mirror");
  // No own car in the driver's eye: no blue anywhere.
  EXPECT_LT(find(im, bluish).n, 20);
  // The dashboard: dark across the bottom.
  int dark = 0;
  for (int x = 0; x < kW; x += 8)
    dark += pixel(im, x, kH - 4).r < 40;
  EXPECT_GT(dark, kW / 8 * 9 / 10);
  // The mirror inset (top centre) shows the green car following.
  const Rect* m = view_->mirror();
  ASSERT_NE(m, nullptr);
  Box green;
  const Box all = find(im, greenish);
  for (int y = kH - m->y - m->h; y < kH - m->y; ++y)
    for (int x = m->x; x < m->x + m->w; ++x)
      if (greenish(pixel(im, x, y)))
        green.add(x, y);
  EXPECT_GT(green.n, 30);
  EXPECT_EQ(green.n, all.n);  // and only there: it is behind us
}

TEST_F(View3dRender, WarningBannerWhileMqttCarriesAWarningAndGoneAfterCleared) {
  mqtt::testing::Broker broker("1001,1002");
  ASSERT_TRUE(broker.configured());
  ASSERT_TRUE(broker.start()) << broker.log();
  clock::SystemClock clk;
  v2x::V2xMonitor monitor;
  v2x::V2xSubscriber reader(clk, monitor,
                            {"127.0.0.1", static_cast<std::uint16_t>(broker.port()), "hmi", "hmi"});
  reader.start();
  mqtt::ClientConfig sc = broker.station_account(1001);
  mqtt::MosquittoClient station(clk, sc);
  station.start();
  ASSERT_TRUE(
      mqtt::testing::wait_until([&] { return reader.connected() && station.connected(); }, 10s));

  auto w = straight_world({look("me", 1001, "#2040e0"), look("other", 1002, "#20c020")});
  FrameInput in = driving(w, {at(100.0, 0.0), at(140.0, 0.0, 3.14159)});
  in.v2x_enabled = true;
  const std::string raised =
      R"({"type":"lcrw_warning","message":{"station_id":1001,"other_station_id":1002,)"
      R"("event":"raised","collision_case":"frontal","severity":"warning","ttc_s":2.4,)"
      R"("distance_m":38.0}})";
  // Published until the reader's subscription is in place (QoS 1, kept while unacknowledged).
  ASSERT_TRUE(mqtt::testing::wait_until(
      [&] {
        station.publish("its/1001/app/lcrw", raised, mqtt::Qos::kAtLeastOnce, false);
        return monitor.picture(clk.steady_now()).alert_for(1001) != nullptr;
      },
      10s));
  in.v2x = monitor.picture(clk.steady_now());
  const Image on = shoot(in, "warning_banner");
  ASSERT_FALSE(view_->hud().banner().empty());
  EXPECT_NE(view_->hud().banner().find("TTC 2.4 s"), std::string::npos);
  const Rect r = view_->hud().banner_rect();
  const auto red_share = [&](const Image& im) {
    int red = 0, all = 0;
    for (int y = kH - r.y - r.h + 4; y < kH - r.y - 4; y += 2)
      for (int x = r.x + 4; x < r.x + r.w - 4; x += 2) {
        const Rgb c = pixel(im, x, y);
        red += c.r > 170 && c.g < 90 && c.b < 80;
        ++all;
      }
    return static_cast<double>(red) / all;
  };
  EXPECT_GT(red_share(on), 0.6);

  station.publish("its/1001/app/lcrw",
                  R"({"type":"lcrw_warning","message":{"station_id":1001,"other_station_id":1002,)"
                  R"("event":"cleared","clear_reason":"risk_ended"}})",
                  mqtt::Qos::kAtLeastOnce, false);
  ASSERT_TRUE(mqtt::testing::wait_until(
      [&] { return monitor.picture(clk.steady_now()).alert_for(1001) == nullptr; }, 10s));
  in.v2x = monitor.picture(clk.steady_now());
  const Image off = shoot(in, "warning_cleared");
  EXPECT_TRUE(view_->hud().banner().empty());
  EXPECT_LT(red_share(off), 0.02);
  reader.stop();
  station.stop();
}

TEST_F(View3dRender, OverlayDrawsLinksWarningMarkersAndDenms) {
  auto w = straight_world({look("a", 1001, "#2040e0"), look("b", 1002, "#20c020")});
  FrameInput in = driving(w, {at(100.0, 0.0), at(130.0, 3.5, 3.14159)});
  in.own = -1;
  in.choice.camera = CameraMode::kOrbit;
  in.choice.overlay = true;
  in.choice.target = 0;
  in.v2x_enabled = true;
  in.v2x.links = {{1001, 1002}, {1002, 1001}, {1002, 9999}};
  in.v2x.alerts = {{1001, 1002, 2.0, "frontal", "warning", 30.0}};
  const geodesy::Geodetic ev = w->frame->to_geodetic({115.0, -3.5, 0.0});
  in.v2x.denms = {{1002, 1, ev.latitude_deg, ev.longitude_deg, 97, 1, std::nullopt, 0}};
  const Image im = shoot(in, "overlay_orbit");
  EXPECT_EQ(view_->overlay().links(), 2u);  // the link to a station not in the world is left out
  EXPECT_EQ(view_->overlay().markers(), 1u);
  EXPECT_EQ(view_->overlay().denms(), 1u);
  EXPECT_EQ(view_->overlay().warning_lines(), 1u);
  EXPECT_EQ(view_->overlay().range_rings(), 0u);  // the ideal channel: no range to draw
  EXPECT_EQ(view_->overlay().denm_areas(), 0u);   // a DENM without relevance distance
  // The warning marker: red above car a.
  const osg::Vec2d m = project(view_->pose(), {100.0, 0.0, 1.45 + 2.2 + 0.6}, kW, kH);
  int red = 0;
  for (int dy = -6; dy <= 6; ++dy)
    for (int dx = -6; dx <= 6; ++dx) {
      const Rgb c = pixel(im, static_cast<int>(m.x()) + dx, static_cast<int>(m.y()) + dy);
      red += c.r > 180 && c.g < 80 && c.b < 80;
    }
  EXPECT_GT(red, 20);
  // The DENM pylon: orange at the event position.
  const osg::Vec2d d = project(view_->pose(), {115.0, -3.5, 1.0}, kW, kH);
  const Rgb c = pixel(im, static_cast<int>(d.x()), static_cast<int>(d.y()));
  EXPECT_GT(c.r, 180);
  EXPECT_GT(c.g, 70);
  EXPECT_LT(c.b, 60);
}

// A car seen from the side at 50 m (from the driver's seat of a car 50 m to its right, eye
// 1.23 m up, 90° wide at 1280×720): the pixels that differ from the same view without it form a
// three-box silhouette, graded from the Welcome's length and height: bonnet and boot well below
// the roof, and raked glass between them (half way up the windscreen and the rear window, the
// outline is between the two: neither a box nor a wedge).
TEST_F(View3dRender, ACarFromTheSideAtFiftyMetresHasBonnetCabinAndBoot) {
  const VehicleLook car = look("car", 1002, "#c03020");
  const double L = car.length_m, H = car.height_m;
  auto w = straight_world({look("me", 1001, "#2040e0"), car});
  // The watcher sits 50 m south of the car's middle, facing north; its own car is not drawn.
  const wire::VehicleState me = at(100.0 + 0.05 * 4.5, -50.0 - 0.2 * 1.8, 3.14159265 / 2);
  FrameInput in = driving(w, {me, at(100.0, 0.0)});
  in.choice.camera = CameraMode::kCockpit;
  const Image with = shoot(in, "car_side_50m");
  // The same through a 12° lens, for a person to look at (not graded).
  in.choice.hfov_deg = 12.0;
  shoot(in, "car_side_50m_zoomed");
  in.choice.hfov_deg = 90.0;
  in.vehicles[1] = at(100.0, 3000.0);  // past the far plane
  const Image without = shoot(in, "car_side_50m_background");
  const CameraPose& pose = view_->pose();
  const auto differs = [&](int x, int y) {
    const Rgb a = pixel(with, x, y), b = pixel(without, x, y);
    return std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b) > 30;
  };
  // Height of the silhouette at body x (metres ahead of the middle), as a share of H.
  const auto height_at = [&](double x) {
    const osg::Vec2d foot = project(pose, {100.0 + x, 0.0, 0.0}, kW, kH);
    const osg::Vec2d roof = project(pose, {100.0 + x, 0.0, H}, kW, kH);
    const int col = static_cast<int>(std::lround(foot.x()));
    int top = -1;
    for (int y = static_cast<int>(roof.y()) - 12; y <= static_cast<int>(foot.y()); ++y)
      if (differs(col, y)) {
        top = y;
        break;
      }
    return top < 0 ? 0.0 : (foot.y() - top) / (foot.y() - roof.y());
  };
  const osg::Vec2d front = project(pose, {100.0 + L / 2, 0.0, 0.0}, kW, kH);
  const osg::Vec2d back = project(pose, {100.0 - L / 2, 0.0, 0.0}, kW, kH);
  ASSERT_GT(front.x(), back.x());                          // the car faces right
  EXPECT_NEAR(front.x() - back.x(), L / 100.0 * kW, 1.0);  // 4.5 m across 100 m of view
  double bonnet = 0, boot = 0, roof = 0;
  for (double f : {0.36, 0.40, 0.44}) {
    bonnet = std::max(bonnet, height_at(f * L));
    boot = std::max(boot, height_at(-f * L));
  }
  for (double f : {-0.12, -0.06, 0.0})
    roof = std::min(roof == 0 ? 9.0 : roof, height_at(f * L));
  RecordProperty("bonnet_boot_roof", fmt::format("{:.2f} {:.2f} {:.2f}", bonnet, boot, roof));
  EXPECT_GT(roof, 0.9) << "roof";
  EXPECT_LT(bonnet, 0.75) << "bonnet";
  EXPECT_LT(boot, 0.75) << "boot";
  EXPECT_GT(bonnet, 0.35) << "bonnet";  // a bonnet, not nothing
  EXPECT_GT(boot, 0.35) << "boot";
  // Raked glass: half way along the windscreen and the rear window, in between.
  for (double x : {0.15 * L, -0.23 * L}) {
    const double h = height_at(x);
    EXPECT_GT(h, bonnet + 0.08) << "at " << x;
    EXPECT_LT(h, roof - 0.08) << "at " << x;
  }
  // And nothing of the car outside its length (columns beyond the bumpers unchanged above the
  // road's shadow).
  for (int y = static_cast<int>(project(pose, {100.0, 0.0, H}, kW, kH).y()) - 10;
       y < static_cast<int>(front.y()) - 3; ++y) {
    EXPECT_FALSE(differs(static_cast<int>(front.x()) + 4, y)) << "row " << y;
    EXPECT_FALSE(differs(static_cast<int>(back.x()) - 4, y)) << "row " << y;
  }
}

// The sky: a gradient that is bluer and darker overhead than just above the horizon (chase
// camera, flat map), and the sun's disc where the light comes from: south-east, 20° up.
TEST_F(View3dRender, SkyDarkensUpwardsAndTheSunStandsSouthEast) {
  auto w = straight_world({look("me", 1001, "#2040e0")});
  const Image im = shoot(driving(w, {at(100.0, 0.0)}), "sky_chase");
  const CameraPose& pose = view_->pose();
  // The horizon: a far point level with the eye, straight ahead (east).
  const int horizon =
      static_cast<int>(project(pose, pose.eye + osg::Vec3d(2000.0, 0.0, 0.0), kW, kH).y());
  ASSERT_GT(horizon, 100);
  // Right of the mirror inset and the HUD's text.
  const auto mean = [&](int y0, int y1) {
    double r = 0, g = 0, b = 0;
    int n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = 900; x < kW - 10; x += 4) {
        const Rgb c = pixel(im, x, y);
        r += c.r;
        g += c.g;
        b += c.b;
        ++n;
      }
    return std::array<double, 3>{r / n, g / n, b / n};
  };
  const auto top = mean(4, 24), low = mean(horizon - 30, horizon - 10);
  RecordProperty("sky_top_rgb", fmt::format("{:.0f} {:.0f} {:.0f}", top[0], top[1], top[2]));
  RecordProperty("sky_low_rgb", fmt::format("{:.0f} {:.0f} {:.0f}", low[0], low[1], low[2]));
  EXPECT_GT(top[2] - top[0], low[2] - low[0] + 20);                    // bluer
  EXPECT_LT(top[0] + top[1] + top[2], low[0] + low[1] + low[2] - 60);  // darker
  EXPECT_GT(low[2], low[0]);                                           // still sky, not haze-grey

  // Watching (no mirror) from behind a car heading south-east, the sun is in view (the chase camera
  // sees about 21° above the horizon straight ahead).
  FrameInput in = driving(w, {at(100.0, 0.0, -50.0 * 3.14159265 / 180)});
  in.own = -1;
  in.choice.target = 0;
  const CameraPose east = pose;
  ASSERT_NE(view_->mirror(), nullptr);
  const Rect east_mirror = *view_->mirror();
  view_ = std::make_unique<DriverView>(kW, kH);  // a chase camera that starts behind this car
  const Image sunny = shoot(in, "sky_sun");
  const double el = 20.0 * 3.14159265 / 180, az = -45.0 * 3.14159265 / 180;
  const osg::Vec3d toward(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  const osg::Vec2d sun = project(view_->pose(), view_->pose().eye + toward * 1000.0, kW, kH);
  ASSERT_TRUE(clear_of_hud(sun) || sun.y() < 150) << sun.x() << "," << sun.y();
  ASSERT_TRUE(sun.x() > 20 && sun.x() < kW - 20 && sun.y() > 10 && sun.y() < kH - 10)
      << sun.x() << "," << sun.y();
  const auto bright = [](Rgb c) { return c.r > 240 && c.g > 235 && c.b > 190; };
  // Above the horizon (below it the lane marks are as white).
  const auto in_sky = [&](const Image& image, const CameraPose& p, double heading,
                          const Rect* mirror) {
    const osg::Vec3d ahead(std::cos(heading), std::sin(heading), 0.0);
    const int h = static_cast<int>(project(p, p.eye + ahead * 2000.0, kW, kH).y()) - 3;
    Box b;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < kW; ++x) {
        // Not the HUD's title, nor the mirror's inset (the road behind).
        const bool hud =
            (x < 420 && y < 60) || (mirror && x >= mirror->x && x < mirror->x + mirror->w &&
                                    y >= kH - mirror->y - mirror->h - 4 && y < kH - mirror->y + 4);
        if (!hud && bright(pixel(image, x, y)))
          b.add(x, y);
      }
    return b;
  };
  EXPECT_TRUE(bright(pixel(sunny, static_cast<int>(sun.x()), static_cast<int>(sun.y()))));
  // The disc is small (1.2° ≈ 17 px at 90°): the brightest pixels are around that point only.
  const Box disc = in_sky(sunny, view_->pose(), -50.0 * 3.14159265 / 180, nullptr);
  EXPECT_NEAR((disc.x0 + disc.x1) / 2.0, sun.x(), 3.0);
  EXPECT_NEAR((disc.y0 + disc.y1) / 2.0, sun.y(), 3.0);
  EXPECT_LT(disc.width(), 30);
  // And none in the first view, facing east with the sun 45° off to the right and higher.
  EXPECT_EQ(in_sky(im, east, 0.0, &east_mirror).n, 0);
}

bool overlay_yellow(Rgb c) {
  return c.r > 200 && c.g > 170 && c.b < 90;
}

/// Distance from @p p to the segment @p a – @p b, in pixels.
double to_segment(const osg::Vec2d& p, const osg::Vec2d& a, const osg::Vec2d& b) {
  const osg::Vec2d ab = b - a;
  const double t = std::clamp(((p - a) * ab) / ab.length2(), 0.0, 1.0);
  return (a + ab * t - p).length();
}

// A warning from car A about car B: a yellow line over the roofs from A to B. Its pixels lie on
// the segment between A's and B's projected positions (worked out from the positions put in and
// the camera's matrices), along most of it, and nowhere else.
TEST_F(View3dRender, OverlayWarningLineRunsFromTheWarnedCarToTheOther) {
  auto w = straight_world({look("a", 1001, "#2040e0"), look("b", 1002, "#20c020")});
  const osg::Vec3d a(100.0, 0.0, 0.0), b(126.0, 3.5, 0.0);
  FrameInput in = driving(w, {at(a.x(), a.y()), at(b.x(), b.y(), 3.14159)});
  in.own = -1;
  in.choice.camera = CameraMode::kOrbit;
  in.choice.orbit_distance_m = 45.0;
  in.choice.orbit_elevation_deg = 40.0;
  in.choice.orbit_azimuth_deg = -120.0;
  in.choice.overlay = true;
  in.choice.target = 0;
  in.v2x_enabled = true;
  in.v2x.alerts = {{1001, 1002, 2.0, "frontal", "warning", 26.0}};
  const Image im = shoot(in, "overlay_warning_line");
  ASSERT_EQ(view_->overlay().warning_lines(), 1u);
  const double lift = 1.45 + V2xOverlay::kWarningOverRoof;
  const osg::Vec2d pa = project(view_->pose(), a + osg::Vec3d(0, 0, lift), kW, kH);
  const osg::Vec2d pb = project(view_->pose(), b + osg::Vec3d(0, 0, lift), kW, kH);
  ASSERT_TRUE(clear_of_hud(pa) && clear_of_hud(pb))
      << pa.x() << "," << pa.y() << " " << pb.x() << "," << pb.y();
  ASSERT_GT((pb - pa).length(), 150.0);  // long enough on screen to grade
  // Along the segment (short of the arrow head at B), yellow within 2 px of every point.
  int on = 0, samples = 0;
  for (double t = 0.08; t <= 0.8; t += 0.02) {
    const osg::Vec2d p = pa + (pb - pa) * t;
    ++samples;
    bool hit = false;
    for (int dy = -2; dy <= 2 && !hit; ++dy)
      for (int dx = -2; dx <= 2 && !hit; ++dx)
        hit = overlay_yellow(pixel(im, static_cast<int>(p.x()) + dx, static_cast<int>(p.y()) + dy));
    on += hit;
  }
  EXPECT_GE(on, samples * 9 / 10) << on << " of " << samples;
  // Every yellow pixel is on that line (the arrow head at B is up to 1.4 m long and wide).
  int yellow = 0, off = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      if (clear_of_hud({double(x), double(y)}) && overlay_yellow(pixel(im, x, y))) {
        ++yellow;
        off += to_segment({double(x), double(y)}, pa, pb) > 25.0;
      }
  EXPECT_GT(yellow, 100);
  EXPECT_EQ(off, 0);
  // Without the warning, no line.
  in.v2x.alerts.clear();
  const Image none = shoot(in, "overlay_no_warning");
  int left = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      left += clear_of_hud({double(x), double(y)}) && overlay_yellow(pixel(none, x, y));
  EXPECT_EQ(left, 0);
}

// Range rings and a DENM relevance area: the ring's pixels at the range from each car (the
// channel's max range), the area's tint around the event and not outside it.
TEST_F(View3dRender, OverlayDrawsRangeRingsAndTheDenmRelevanceArea) {
  auto base = straight_world({look("a", 1001, "#2040e0"), look("b", 1002, "#20c020")});
  auto w = std::make_shared<World>(*base);
  w->radio_range_m = 30.0;
  FrameInput in = driving(w, {at(100.0, 0.0), at(160.0, 3.5, 3.14159)});
  in.own = -1;
  in.choice.camera = CameraMode::kTop;
  in.choice.top_zoom = 0.6;  // 4.8 px/m
  in.choice.overlay = true;
  in.choice.target = 0;
  in.v2x_enabled = true;
  const Image plain = shoot(in, "overlay_ranges_off_denm");
  const geodesy::Geodetic ev = w->frame->to_geodetic({60.0, -60.0, 0.0});
  in.v2x.denms = {{1002, 1, ev.latitude_deg, ev.longitude_deg, 97, 1, 50.0 / 5.0, 0}};
  const Image im = shoot(in, "overlay_ranges");
  EXPECT_EQ(view_->overlay().range_rings(), 2u);
  EXPECT_EQ(view_->overlay().denm_areas(), 1u);
  const auto greenish_ring = [](Rgb c) { return c.g > 200 && c.g > c.r + 60 && c.g > c.b + 60; };
  // Around car a, the ring's colour on the circle of 30 m (within 1.5 px), seen at most angles.
  int ring = 0, probes = 0;
  for (int i = 0; i < 36; ++i) {
    const double ang = 2 * 3.14159265 * i / 36;
    const osg::Vec2d p =
        project(view_->pose(), {100.0 + 30.0 * std::cos(ang), 30.0 * std::sin(ang), 0.25}, kW, kH);
    if (!clear_of_hud(p))
      continue;
    ++probes;
    bool hit = false;
    for (int dy = -2; dy <= 2 && !hit; ++dy)
      for (int dx = -2; dx <= 2 && !hit; ++dx)
        hit = greenish_ring(pixel(im, static_cast<int>(p.x()) + dx, static_cast<int>(p.y()) + dy));
    ring += hit;
  }
  EXPECT_GE(probes, 20);
  EXPECT_GE(ring, probes * 8 / 10);
  // Half way to the ring, no ring colour.
  const osg::Vec2d mid = project(view_->pose(), {115.0, 0.0, 0.0}, kW, kH);
  EXPECT_FALSE(greenish_ring(pixel(im, static_cast<int>(mid.x()), static_cast<int>(mid.y()))));
  // The relevance area (10 m around the event): tinted orange inside against the same frame
  // without it (away from the label over the pylon), untouched 4 m outside.
  const auto tint = [&](double x, double y) {
    const osg::Vec2d p = project(view_->pose(), {x, y, 0.0}, kW, kH);
    const Rgb c = pixel(im, static_cast<int>(p.x()), static_cast<int>(p.y()));
    const Rgb o = pixel(plain, static_cast<int>(p.x()), static_cast<int>(p.y()));
    return std::pair{c.r - o.r, c.b - o.b};
  };
  for (const auto& [dx, dy] : {std::pair{-6.0, 0.0}, {0.0, 6.0}, {0.0, -6.0}, {-4.0, -4.0}}) {
    const auto [dr, db] = tint(60.0 + dx, -60.0 + dy);
    EXPECT_GT(dr, 15) << dx << "," << dy;
    EXPECT_LT(db, 0) << dx << "," << dy;
  }
  for (const auto& [dx, dy] : {std::pair{0.0, 14.0}, {14.0, 0.0}, {-10.0, -10.0}}) {
    const auto [dr, db] = tint(60.0 + dx, -60.0 + dy);
    EXPECT_EQ(dr, 0) << dx << "," << dy;
  }
}

}  // namespace
}  // namespace tb::client::view3d
