// Draws the view off-screen with SDL's software renderer and checks the pixels.
#include <gtest/gtest.h>

#include <cstdio>

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
  const map::RoadMap road(straight_road());
  ViewScene scene;
  scene.road_map = &road;
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
  const map::RoadMap road(spec);
  ViewScene scene;
  scene.road_map = &road;
  scene.connection = "connecting";
  SceneRenderer r(canvas->renderer(), 320, 240);
  r.pixels_per_metre = 2.0;
  r.draw(scene);
  testing::Image im{320, 240, canvas->read_rgba()};
  // Asphalt of the ring is visible around the origin-centred camera.
  EXPECT_GT(testing::count_near(im, 160, 144, 120, 64, 64, 68, 2), 500);
}

}  // namespace
}  // namespace tb::client
