#include "sim-client/view3d/view_controls.hpp"

#include <gtest/gtest.h>

namespace tb::client::view3d {
namespace {

SDL_Event key(SDL_Scancode code, bool repeat = false) {
  SDL_Event e{};
  e.type = SDL_KEYDOWN;
  e.key.keysym.scancode = code;
  e.key.repeat = repeat ? 1 : 0;
  return e;
}

TEST(ViewControls, TabCyclesTheCamerasAndIgnoresKeyRepeat) {
  ViewControls c;
  EXPECT_EQ(c.choice().camera, CameraMode::kChase);
  const CameraMode order[] = {CameraMode::kCockpit, CameraMode::kTop, CameraMode::kOrbit,
                              CameraMode::kChase};
  for (CameraMode want : order) {
    EXPECT_TRUE(c.handle(key(SDL_SCANCODE_TAB)));
    EXPECT_EQ(c.choice().camera, want);
  }
  c.handle(key(SDL_SCANCODE_TAB, true));
  EXPECT_EQ(c.choice().camera, CameraMode::kChase);
}

TEST(ViewControls, BracketsPickTheCarFromTheOwnOneWrappingRound) {
  ViewControls c;
  c.set_vehicle_count(3);
  c.set_own(1);
  EXPECT_EQ(c.choice().target, -1);  // until a pick, the cameras follow the own car
  c.handle(key(SDL_SCANCODE_RIGHTBRACKET));
  EXPECT_EQ(c.choice().target, 2);
  c.handle(key(SDL_SCANCODE_RIGHTBRACKET));
  EXPECT_EQ(c.choice().target, 0);
  c.handle(key(SDL_SCANCODE_LEFTBRACKET));
  EXPECT_EQ(c.choice().target, 2);
  c.set_own(0);  // a picked car stays picked
  EXPECT_EQ(c.choice().target, 2);
}

TEST(ViewControls, ZoomOverlayFrameRateAndMouseOrbit) {
  ViewControls c;
  const double d = c.choice().orbit_distance_m;
  c.handle(key(SDL_SCANCODE_PAGEUP));
  EXPECT_LT(c.choice().orbit_distance_m, d);
  EXPECT_GT(c.choice().top_zoom, 1.0);
  c.handle(key(SDL_SCANCODE_N));
  EXPECT_TRUE(c.choice().overlay);
  c.handle(key(SDL_SCANCODE_F1));
  EXPECT_TRUE(c.choice().show_fps);
  SDL_Event m{};
  m.type = SDL_MOUSEMOTION;
  m.motion.state = SDL_BUTTON_LMASK;
  m.motion.xrel = 100;
  m.motion.yrel = 1000;
  const double az = c.choice().orbit_azimuth_deg;
  EXPECT_TRUE(c.handle(m));
  EXPECT_NEAR(c.choice().orbit_azimuth_deg, az - 30.0, 1e-9);
  EXPECT_EQ(c.choice().orbit_elevation_deg, 89.0);
  m.motion.state = 0;
  EXPECT_FALSE(c.handle(m));                    // moving without a button does nothing
  EXPECT_FALSE(c.handle(key(SDL_SCANCODE_W)));  // driving keys are not the view's
}

}  // namespace
}  // namespace tb::client::view3d
