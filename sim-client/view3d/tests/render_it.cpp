// The 3D view rendered for real: Mesa's llvmpipe into an Xvfb this test starts, checked
// structurally (colours at positions worked out from the camera pose), not against golden
// images. Every frame checked is also written to the test log folder
// (build/…/Testing/Temporary/view3d/) for a person to look at.
#include <gtest/gtest.h>

#include <SDL.h>

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
#include "sim-client/view3d/tests/xvfb.hpp"

namespace tb::client::view3d {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr int kW = 1280, kH = 720;

fs::path log_dir() {
  const char* bin = std::getenv("TESTBED_BIN");
  fs::path d =
      fs::path(bin != nullptr ? bin : "build/bin") / ".." / "Testing" / "Temporary" / "view3d";
  fs::create_directories(d);
  return d;
}

struct Rgb {
  int r, g, b;
};

Rgb pixel(const Image& im, int x, int y) {
  const auto* p = &im.rgba[(static_cast<std::size_t>(y) * im.width + x) * 4];
  return {p[0], p[1], p[2]};
}

/// A world point to window pixels (origin top left) under a camera pose.
osg::Vec2d project(const CameraPose& pose, const osg::Vec3d& w, int width, int height) {
  const osg::Vec3d n = w * pose.view * pose.projection;
  return {(n.x() + 1.0) / 2.0 * width, (1.0 - n.y()) / 2.0 * height};
}

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

class View3dRender : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    xvfb_ = std::make_unique<testing::Xvfb>();
    if (!xvfb_->running())
      return;
    if (SDL_Init(SDL_INIT_VIDEO | SDL_INIT_EVENTS) != 0)
      return;
    SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
    SDL_GL_SetAttribute(SDL_GL_DEPTH_SIZE, 24);
    window_ = SDL_CreateWindow("view3d test", 0, 0, kW, kH, SDL_WINDOW_OPENGL | SDL_WINDOW_HIDDEN);
    if (window_ != nullptr)
      context_ = SDL_GL_CreateContext(window_);
  }
  static void TearDownTestSuite() {
    if (context_ != nullptr)
      SDL_GL_DeleteContext(context_);
    if (window_ != nullptr)
      SDL_DestroyWindow(window_);
    SDL_Quit();
    xvfb_.reset();
  }
  void SetUp() override {
    if (!xvfb_ || !xvfb_->running())
      GTEST_SKIP() << "Xvfb did not start (scripts/install-deps installs xvfb)";
    ASSERT_NE(context_, nullptr) << SDL_GetError();
    ASSERT_EQ(SDL_GL_MakeCurrent(window_, context_), 0) << SDL_GetError();
    view_ = std::make_unique<DriverView>(kW, kH);
  }
  void TearDown() override { view_.reset(); }

  /// Renders @p in (twice: the second frame is the one read back) and saves it as @p name.
  Image shoot(const FrameInput& in, const std::string& name) {
    view_->render(in, 0.0);
    view_->capture_next_frame();
    view_->render(in, 1.0 / 60);
    auto im = view_->take_capture();
    EXPECT_TRUE(im.has_value());
    if (!im)
      return {};
    EXPECT_EQ(write_png((log_dir() / (name + ".png")).string(), im->width, im->height, im->rgba),
              "");
    return *im;
  }

  static inline std::unique_ptr<testing::Xvfb> xvfb_;
  static inline SDL_Window* window_ = nullptr;
  static inline SDL_GLContext context_ = nullptr;
  std::unique_ptr<DriverView> view_;
};

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
bool bluish(Rgb c) {
  return c.b > c.r + 70 && c.b > c.g + 50;
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
  // The car's box as the camera sees it: mostly the car's blue (the rest is glass, lamps,
  // bumper and wheels).
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
  EXPECT_GT(blue, want.width() * want.height() * 4 / 10)
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
  mqtt::ClientConfig sc;
  sc.port = broker.port();
  sc.client_id = sc.username = "station-1001";
  sc.password = broker.password(1001);
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
  in.v2x.denms = {{1002, 1, ev.latitude_deg, ev.longitude_deg, 97, 1}};
  const Image im = shoot(in, "overlay_orbit");
  EXPECT_EQ(view_->overlay().links(), 2u);  // the link to a station not in the world is left out
  EXPECT_EQ(view_->overlay().markers(), 1u);
  EXPECT_EQ(view_->overlay().denms(), 1u);
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

}  // namespace
}  // namespace tb::client::view3d
