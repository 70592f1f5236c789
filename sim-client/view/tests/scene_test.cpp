// Draws the view off-screen with SDL's software renderer and checks the pixels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "common/map/builtin_network.hpp"
#include "common/map/opendrive/reader.hpp"
#include "common/map/opendrive/signal_layout.hpp"
#include "common/map/opendrive/tests/shared_maps.hpp"
#include "sim-client/view/font.hpp"
#include "sim-client/view/scene.hpp"
#include "sim-client/view/tests/png_reader.hpp"

namespace tb::client {
namespace {

scenario::MapSpec straight_road() {
  scenario::MapSpec m;
  m.type = scenario::MapType::kStraight;
  m.lanes = 2;
  m.oncoming_lanes = 1;
  m.length = 1000.0;
  return m;
}

ViewVehicle car(double x, double y, float yaw, std::uint32_t station, SDL_Color c, bool own) {
  ViewVehicle v;
  v.state.station_id = station;
  v.state.position = {x, y, 0.0};
  v.state.yaw = yaw;
  v.state.speed = 13.9f;
  v.state.gear = 3;
  v.state.controls.throttle = 0.4f;
  v.color = c;
  v.own = own;
  return v;
}

TEST(Font, GlyphsAndUnknownCharacters) {
  const auto a = font::glyph('A');
  EXPECT_EQ(a[0], 0b01110);
  EXPECT_EQ(font::glyph('a'), a);
  EXPECT_EQ(font::glyph('~'),
            (std::array<std::uint8_t, 7>{0x1f, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1f}));
  EXPECT_EQ(font::text_width("1001", 2), 4 * 12 - 2);
}

TEST(ParseColour, HexAndRejects) {
  const auto c = parse_colour("#20a040");
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->r, 0x20);
  EXPECT_EQ(c->g, 0xa0);
  EXPECT_EQ(c->b, 0x40);
  EXPECT_FALSE(parse_colour("20a040").has_value());
  EXPECT_FALSE(parse_colour("#20a04g").has_value());
}

TEST(SceneRenderer, OwnCarAtTheAnchorRoadAndOthersDrawn) {
  SDL_SetHint(SDL_HINT_VIDEODRIVER, "dummy");
  auto canvas = Canvas::offscreen(640, 480);
  const map::odr::RoadNetwork road = map::generate_network(straight_road());
  ViewScene scene;
  scene.network = &road;
  // Heading north-east on purpose: the view turns with the car.
  scene.vehicles.push_back(car(100.0, -1.75, 0.7f, 1001, SDL_Color{32, 160, 64, 255}, true));
  scene.vehicles.push_back(car(120.0, 1.75, 3.14f, 1002, SDL_Color{32, 80, 208, 255}, false));
  scene.connection = "connected to 127.0.0.1:2000";
  scene.input = "keyboard";
  SceneRenderer r(canvas->renderer(), canvas->width(), canvas->height());
  r.draw(scene);
  testing::Image im{640, 480, canvas->read_rgba()};
  ASSERT_EQ(im.rgba.size(), 640u * 480u * 4u);

  const SDL_FPoint a = r.anchor();
  const int own =
      testing::count_near(im, static_cast<int>(a.x), static_cast<int>(a.y), 20, 32, 160, 64);
  EXPECT_GT(own, 200);  // a 4.5 × 1.8 m car at 8 px/m covers ~500 px, less the windscreen
  EXPECT_GT(testing::count_near(im, static_cast<int>(a.x), static_cast<int>(a.y), 30, 255, 220, 0),
            50);  // highlight ring
  // The other car is 20 m ahead along x; it is drawn somewhere, with its label.
  EXPECT_GT(testing::count_near(im, 320, 240, 320, 32, 80, 208), 200);
  EXPECT_GT(testing::distinct_colours(im), 5);
  // The key map (H) appears as an overlay with its amber title.
  EXPECT_EQ(testing::count_near(im, 320, 240, 240, 255, 170, 0), 0);
  scene.help = true;
  r.draw(scene);
  EXPECT_GT(testing::count_near(testing::Image{640, 480, canvas->read_rgba()}, 320, 240, 240, 255,
                                170, 0),
            20);

  const std::string path = ::testing::TempDir() + "/simclient_scene.png";
  std::remove(path.c_str());
  ASSERT_EQ(write_png(path, 640, 480, im.rgba), "");
  testing::Image back;
  ASSERT_TRUE(testing::read_png(path, back));
  EXPECT_EQ(back.width, 640);
  EXPECT_EQ(back.rgba, im.rgba);
  EXPECT_NE(write_png("/nonexistent/dir/x.png", 640, 480, im.rgba).find("/nonexistent/dir/x.png"),
            std::string::npos);
}

TEST(SceneRenderer, RingRoadAndNoCarYet) {
  auto canvas = Canvas::offscreen(320, 240);
  scenario::MapSpec spec;
  spec.type = scenario::MapType::kRing;
  spec.radius = 30.0;
  const map::odr::RoadNetwork road = map::generate_network(spec);
  ViewScene scene;
  scene.network = &road;
  scene.connection = "connecting";
  SceneRenderer r(canvas->renderer(), 320, 240);
  r.pixels_per_metre = 2.0;
  r.draw(scene);
  testing::Image im{320, 240, canvas->read_rgba()};
  // Asphalt of the ring is visible around the origin-centred camera.
  EXPECT_GT(testing::count_near(im, 160, 144, 120, 64, 64, 68, 2), 500);
}

// Where the PNGs of the OpenDRIVE views go, to be looked at.
std::string png_path(const std::string& name) {
  return ::testing::TempDir() + "/" + name;
}

TEST(SceneRenderer, OpenDriveJunctionLanesMarksAndJunctionArea) {
  const map::odr::RoadNetwork net = map::odr::load_opendrive(
      (map::odr::test::shared_maps() / "simple_4way_intersection.xodr").string());
  auto canvas = Canvas::offscreen(640, 480);
  ViewScene scene;
  scene.network = &net;
  // The own car on road 0's inbound lane, 12 m before the junction, heading east.
  scene.vehicles.push_back(car(88.0, -1.5, 0.0f, 1001, SDL_Color{32, 160, 64, 255}, true));
  SceneRenderer r(canvas->renderer(), canvas->width(), canvas->height());
  r.draw(scene);
  testing::Image im{640, 480, canvas->read_rgba()};
  ASSERT_EQ(write_png(png_path("view_4way.png"), 640, 480, im.rgba), "");
  const SDL_Color asphalt = *lane_colour("driving", false);
  const SDL_Color junction = *lane_colour("driving", true);
  const SDL_Color paint = mark_colour("standard");
  // Heading up: the junction (12 m ahead) is above the anchor, the arm's lanes around it.
  const SDL_FPoint a = r.anchor();
  EXPECT_GT(testing::count_near(im, static_cast<int>(a.x), static_cast<int>(a.y) + 60, 30,
                                asphalt.r, asphalt.g, asphalt.b, 2),
            300);
  EXPECT_GT(testing::count_near(im, static_cast<int>(a.x), static_cast<int>(a.y) - 20 * 8, 40,
                                junction.r, junction.g, junction.b, 2),
            500);
  // The arm's marks: solid edges and centre line, 0.2 m wide (1.6 px at 8 px/m).
  EXPECT_GT(testing::count_near(im, 320, 240, 320, paint.r, paint.g, paint.b, 30), 300);
}

TEST(SceneRenderer, BrokenMarksAreDashesOfThreeMetresEveryTwelve) {
  // A built-in straight road of three lanes one way: the two lane lines are broken marks.
  scenario::MapSpec spec = straight_road();
  spec.lanes = 3;
  spec.oncoming_lanes = 0;
  const map::odr::RoadNetwork net = map::generate_network(spec);
  auto canvas = Canvas::offscreen(400, 600);
  ViewScene scene;
  scene.network = &net;
  scene.vehicles.push_back(car(300.0, 0.0, 0.0f, 1001, SDL_Color{32, 160, 64, 255}, true));
  SceneRenderer r(canvas->renderer(), canvas->width(), canvas->height());
  r.draw(scene);
  testing::Image im{400, 600, canvas->read_rgba()};
  ASSERT_EQ(write_png(png_path("view_broken.png"), 400, 600, im.rgba), "");
  // Up the screen along the lane line 1.75 m right of the car (x = anchor + 14 px): painted
  // runs of 3 m (24 px) every 12 m (96 px).
  const SDL_Color paint = mark_colour("standard");
  const int x = static_cast<int>(r.anchor().x + 1.75 * 8);
  std::vector<int> runs;
  int run = 0;
  for (int y = 0; y < 600; ++y) {
    // The line is 0.12 m (1 px) wide: any painted pixel within 2 px of where it should be,
    // below the HUD panel and above the status line.
    bool painted = false;
    for (int dx = -2; dx <= 2 && y > 170 && y < 600 - 30; ++dx) {
      const auto* p = im.at(x + dx, y);
      painted = painted || (std::abs(p[0] - paint.r) < 30 && std::abs(p[1] - paint.g) < 30 &&
                            std::abs(p[2] - paint.b) < 30);
    }
    if (painted) {
      ++run;
    } else if (run > 0) {
      runs.push_back(run);
      run = 0;
    }
  }
  ASSERT_GE(runs.size(), 4u);
  for (std::size_t i = 1; i + 1 < runs.size(); ++i)
    EXPECT_NEAR(runs[i], 24, 2) << "dash " << i;
}

TEST(MapLayer, ColoursByLaneTypeAndSkipsNone) {
  EXPECT_TRUE(lane_colour("driving", false));
  EXPECT_TRUE(lane_colour("sidewalk", false));
  EXPECT_FALSE(lane_colour("none", false));
  EXPECT_NE(lane_colour("shoulder", false)->r, lane_colour("driving", false)->r);
  EXPECT_EQ(mark_colour("yellow").b, 32);
  // Every shared map builds, with surfaces and marks where the file has them.
  for (const auto& e : std::filesystem::directory_iterator(map::odr::test::shared_maps())) {
    if (e.path().extension() != ".xodr")
      continue;
    const MapLayer layer(map::odr::load_opendrive(e.path().string()));
    EXPECT_GT(layer.surfaces().size(), 0u) << e.path();
    EXPECT_GT(layer.marks().size(), 0u) << e.path();
  }
}

TEST(SceneRenderer, ShippedMapsFromAbove) {
  // A watcher's north-up view of each shipped map, scaled to fit: both draw, with junction
  // asphalt, lane types other than driving, and marks.
  const char* root = std::getenv("TESTBED_ROOT");
  const std::filesystem::path dir =
      std::filesystem::path(root != nullptr ? root : ".") / "scenarios" / "maps";
  const struct {
    const char* file;
    double x, y, ppm;
    const char* png;
  } maps[] = {{"four_way_junction.xodr", 0.0, 0.0, 2.6, "four_way.png"},
              {"motorway_merge.xodr", 700.0, 300.0, 0.3, "motorway.png"},
              {"motorway_merge.xodr", 840.0, -15.0, 2.5, "motorway_entry.png"},
              {"motorway_merge.xodr", 360.0, -15.0, 2.5, "motorway_exit.png"},
              {"motorway_merge.xodr", 500.0, 10.0, 12.0, "motorway_shoulder.png"}};
  for (const auto& m : maps) {
    const map::odr::RoadNetwork net = map::odr::load_opendrive((dir / m.file).string());
    auto canvas = Canvas::offscreen(640, 640);
    ViewScene scene;
    scene.network = &net;
    scene.vehicles.push_back(car(m.x, m.y, 0.0f, 1001, SDL_Color{32, 160, 64, 255}, false));
    SceneRenderer r(canvas->renderer(), 640, 640);
    r.pixels_per_metre = m.ppm;
    r.draw(scene);
    testing::Image im{640, 640, canvas->read_rgba()};
    ASSERT_EQ(write_png(png_path(m.png), 640, 640, im.rgba), "");
    const SDL_Color asphalt = *lane_colour("driving", false);
    EXPECT_GT(testing::count_near(im, 320, 320, 320, asphalt.r, asphalt.g, asphalt.b, 2), 2000)
        << m.file;
  }
}

TEST(SceneRenderer, SignalMarkersAtTheStopLinesInTheirGroupsColours) {
  // The shipped four-way junction from the driver's seat on arm 1, 15 m before its light: the
  // marker on arm 1's stop line red, a crossing arm's green; then red + amber (red beyond the
  // line, amber before it) and a group the message lacks (dark).
  const char* root = std::getenv("TESTBED_ROOT");
  const std::filesystem::path dir =
      std::filesystem::path(root != nullptr ? root : ".") / "scenarios" / "maps";
  const map::odr::RoadNetwork net =
      map::odr::load_opendrive((dir / "four_way_junction.xodr").string());
  const auto markers = signal_markers(net);
  const map::odr::SignalLayout layout(net);
  ASSERT_EQ(markers.size(), layout.approaches().size());
  const map::odr::SignalApproach* mine = layout.approach(net.road_index("1"), 1);
  ASSERT_NE(mine, nullptr);
  // The nearest approach of another group: a crossing arm's, on the screen with arm 1's.
  const map::odr::SignalApproach* other = nullptr;
  for (const auto& a : layout.approaches()) {
    const auto d = [&](const map::odr::SignalApproach* x) {
      return std::hypot(x->stop.x - mine->stop.x, x->stop.y - mine->stop.y);
    };
    if (a.signal_group != mine->signal_group && (other == nullptr || d(&a) < d(other)))
      other = &a;
  }
  ASSERT_NE(other, nullptr);
  const double h = mine->stop.heading;
  ViewVehicle own = car(mine->stop.x - 17.0 * std::cos(h), mine->stop.y - 17.0 * std::sin(h),
                        static_cast<float>(h), 1001, SDL_Color{208, 32, 32, 255}, true);
  auto canvas = Canvas::offscreen(640, 480);
  SceneRenderer r(canvas->renderer(), 640, 480);
  ViewScene scene;
  scene.network = &net;
  scene.vehicles.push_back(own);
  using P = wire::sim::MovementPhaseState;
  const auto id = mine->intersection_id;
  const auto g = [](const map::odr::SignalApproach* a) {
    return static_cast<std::uint8_t>(a->signal_group);
  };
  // The pixel a quarter of the marker before (near) or beyond (far) an approach's stop line.
  const auto colour_at = [&](const testing::Image& im, const map::odr::SignalApproach* a,
                             double along) {
    const SDL_FPoint p = r.screen_of(a->stop.x + along * std::cos(a->stop.heading),
                                     a->stop.y + along * std::sin(a->stop.heading));
    EXPECT_GT(p.x, 0);
    EXPECT_LT(p.x, 640);
    EXPECT_GT(p.y, 0);
    EXPECT_LT(p.y, 480);
    const auto* px = im.at(static_cast<int>(p.x), static_cast<int>(p.y));
    return SDL_Color{px[0], px[1], px[2], 255};
  };
  const auto same = [](SDL_Color a, SDL_Color b) {
    return std::abs(a.r - b.r) <= 2 && std::abs(a.g - b.g) <= 2 && std::abs(a.b - b.b) <= 2;
  };
  const double q = SceneRenderer::kMarkerSize / 4;

  scene.signals = {{id, g(mine), P::kStopAndRemain, 0, 0},
                   {id, g(other), P::kProtectedMovementAllowed, 0, 0}};
  std::sort(scene.signals.begin(), scene.signals.end(),
            [](const auto& x, const auto& y) { return x.signal_group < y.signal_group; });
  r.draw(scene);
  testing::Image im{640, 480, canvas->read_rgba()};
  ASSERT_EQ(write_png(png_path("view_signals.png"), 640, 480, im.rgba), "");
  const SDL_Color red = marker_colours(P::kStopAndRemain).first;
  const SDL_Color green = marker_colours(P::kProtectedMovementAllowed).first;
  const SDL_Color amber = marker_colours(P::kProtectedClearance).first;
  const SDL_Color dark = marker_colours(std::nullopt).first;
  EXPECT_NE(red.g, green.g);
  for (double along : {-q, q}) {
    EXPECT_TRUE(same(colour_at(im, mine, along), red)) << along;
    EXPECT_TRUE(same(colour_at(im, other, along), green)) << along;
  }
  // Off the marker (2 m before the line, on the lane): asphalt, not a light's colour.
  const SDL_Color off = colour_at(im, mine, -2.0);
  EXPECT_FALSE(same(off, red) || same(off, green));

  scene.signals = {{id, g(mine), P::kPreMovement, 0, 0}};
  r.draw(scene);
  testing::Image im2{640, 480, canvas->read_rgba()};
  ASSERT_EQ(write_png(png_path("view_signals_red_amber.png"), 640, 480, im2.rgba), "");
  EXPECT_TRUE(same(colour_at(im2, mine, q), red));
  EXPECT_TRUE(same(colour_at(im2, mine, -q), amber));
  EXPECT_TRUE(same(colour_at(im2, other, q), dark));
  EXPECT_TRUE(same(colour_at(im2, other, -q), dark));
}

}  // namespace
}  // namespace tb::client
