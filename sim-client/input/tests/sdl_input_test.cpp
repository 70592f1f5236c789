// Key and device events go through SDL's own event queue (SDL_PushEvent, virtual joysticks),
// as they would from a real keyboard or wheel, with SDL's dummy video driver.
#include <gtest/gtest.h>

#include <cstdlib>

#include "sim-client/input/sdl_input.hpp"

namespace tb::client {
namespace {

using std::chrono::milliseconds;

class SdlInputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    setenv("SDL_VIDEODRIVER", "dummy", 1);
    setenv("SDL_JOYSTICK_DISABLE_UDEV", "1", 1);
    ASSERT_EQ(SDL_Init(SDL_INIT_EVENTS | SDL_INIT_JOYSTICK | SDL_INIT_GAMECONTROLLER), 0)
        << SDL_GetError();
  }
  void TearDown() override { SDL_Quit(); }

  static void push_key(SDL_Scancode code, bool down) {
    SDL_Event e{};
    e.type = down ? SDL_KEYDOWN : SDL_KEYUP;
    e.key.state = down ? SDL_PRESSED : SDL_RELEASED;
    e.key.keysym.scancode = code;
    ASSERT_EQ(SDL_PushEvent(&e), 1) << SDL_GetError();
  }
  static void pump(SdlInput& in) {
    SDL_Event e;
    while (SDL_PollEvent(&e) != 0)
      in.handle(e);
  }
};

TEST_F(SdlInputTest, KeyEventsChangeTheControls) {
  SdlInput in(std::nullopt);
  push_key(SDL_SCANCODE_W, true);
  push_key(SDL_SCANCODE_LEFT, true);
  push_key(SDL_SCANCODE_Q, true);
  pump(in);
  const DriverCommand c = in.update(milliseconds(100));
  EXPECT_FLOAT_EQ(c.controls.throttle, 0.6f);
  EXPECT_NEAR(c.controls.steer, -0.05, 1e-6);
  EXPECT_TRUE(c.controls.reverse);
  EXPECT_EQ(in.status(), "keyboard");

  // Auto-repeat must not toggle reverse back.
  SDL_Event rep{};
  rep.type = SDL_KEYDOWN;
  rep.key.repeat = 1;
  rep.key.keysym.scancode = SDL_SCANCODE_Q;
  SDL_PushEvent(&rep);
  push_key(SDL_SCANCODE_W, false);
  push_key(SDL_SCANCODE_S, true);
  push_key(SDL_SCANCODE_H, true);
  pump(in);
  const DriverCommand d = in.update(milliseconds(50));
  EXPECT_TRUE(d.controls.reverse);
  EXPECT_FLOAT_EQ(d.controls.throttle, 0.0f);
  EXPECT_FLOAT_EQ(d.controls.brake, 0.6f);
  EXPECT_TRUE(in.help_shown());
  EXPECT_FALSE(in.quit_requested());
  push_key(SDL_SCANCODE_ESCAPE, true);
  pump(in);
  EXPECT_TRUE(in.quit_requested());
}

TEST_F(SdlInputTest, HotPluggedWheelDrivesAndUnplugBrakes) {
  ControllerMapping m = parse_mapping(R"({
    "api": "joystick", "device": "test wheel",
    "steer": {"axis": 0},
    "throttle": {"axis": 1, "released": 1.0, "pressed": -1.0},
    "brake": {"axis": 2, "released": 1.0, "pressed": -1.0},
    "buttons": {"reverse": 0}
  })",
                                      "wheel.json");
  SdlInput in(m);
  in.scan();
  EXPECT_EQ(in.status(), "controller unplugged: braking");
  EXPECT_FLOAT_EQ(in.update(milliseconds(10)).controls.brake, 1.0f);

  SDL_VirtualJoystickDesc desc{};
  desc.version = SDL_VIRTUAL_JOYSTICK_DESC_VERSION;
  desc.type = SDL_JOYSTICK_TYPE_WHEEL;
  desc.naxes = 3;
  desc.nbuttons = 2;
  desc.name = "Test Wheel";
  const int index = SDL_JoystickAttachVirtualEx(&desc);
  ASSERT_GE(index, 0) << SDL_GetError();
  pump(in);
  ASSERT_EQ(in.status(), "controller Test Wheel");
  SDL_Joystick* js = SDL_JoystickFromInstanceID(SDL_JoystickGetDeviceInstanceID(index));
  ASSERT_NE(js, nullptr);
  ASSERT_EQ(SDL_JoystickSetVirtualAxis(js, 1, -32768), 0);  // throttle floored
  ASSERT_EQ(SDL_JoystickSetVirtualAxis(js, 2, 32767), 0);   // brake released
  ASSERT_EQ(SDL_JoystickSetVirtualAxis(js, 0, 16384), 0);
  ASSERT_EQ(SDL_JoystickSetVirtualButton(js, 0, SDL_PRESSED), 0);
  SDL_JoystickUpdate();
  pump(in);
  DriverCommand c = in.update(milliseconds(10));
  EXPECT_FLOAT_EQ(c.controls.throttle, 1.0f);
  EXPECT_FLOAT_EQ(c.controls.brake, 0.0f);
  EXPECT_NEAR(c.controls.steer, 0.5, 1e-3);
  EXPECT_TRUE(c.controls.reverse);

  // Keys other than help and quit do not drive while a controller does.
  push_key(SDL_SCANCODE_S, true);
  pump(in);
  EXPECT_FLOAT_EQ(in.update(milliseconds(100)).controls.brake, 0.0f);

  ASSERT_EQ(SDL_JoystickDetachVirtual(index), 0);
  pump(in);
  c = in.update(milliseconds(10));
  EXPECT_EQ(in.status(), "controller unplugged: braking");
  EXPECT_FLOAT_EQ(c.controls.throttle, 0.0f);
  EXPECT_FLOAT_EQ(c.controls.brake, 1.0f);
}

TEST_F(SdlInputTest, GamepadThroughTheGameControllerApi) {
  const std::string root = std::getenv("TESTBED_ROOT") ? std::getenv("TESTBED_ROOT") : ".";
  SdlInput in(load_mapping(root + "/sim-client/mappings/xbox.json"));
  in.scan();
  SDL_VirtualJoystickDesc desc{};
  desc.version = SDL_VIRTUAL_JOYSTICK_DESC_VERSION;
  desc.type = SDL_JOYSTICK_TYPE_GAMECONTROLLER;
  desc.naxes = SDL_CONTROLLER_AXIS_MAX;
  desc.nbuttons = SDL_CONTROLLER_BUTTON_MAX;
  desc.name = "Virtual Pad";
  const int index = SDL_JoystickAttachVirtualEx(&desc);
  ASSERT_GE(index, 0) << SDL_GetError();
  ASSERT_TRUE(SDL_IsGameController(index)) << "no automatic mapping for virtual pads";
  pump(in);
  ASSERT_EQ(in.status().rfind("controller ", 0), 0u) << in.status();
  SDL_Joystick* js = SDL_JoystickFromInstanceID(SDL_JoystickGetDeviceInstanceID(index));
  ASSERT_NE(js, nullptr);
  ASSERT_EQ(SDL_JoystickSetVirtualAxis(js, SDL_CONTROLLER_AXIS_TRIGGERRIGHT, 32767), 0);
  ASSERT_EQ(SDL_JoystickSetVirtualAxis(js, SDL_CONTROLLER_AXIS_LEFTX, -32768), 0);
  ASSERT_EQ(SDL_JoystickSetVirtualButton(js, SDL_CONTROLLER_BUTTON_A, SDL_PRESSED), 0);
  SDL_JoystickUpdate();
  SDL_GameControllerUpdate();
  pump(in);
  const DriverCommand c = in.update(milliseconds(10));
  EXPECT_FLOAT_EQ(c.controls.throttle, 1.0f);
  EXPECT_FLOAT_EQ(c.controls.steer, -1.0f);
  EXPECT_TRUE(c.controls.handbrake);
  ASSERT_EQ(SDL_JoystickDetachVirtual(index), 0);
  pump(in);
  EXPECT_FLOAT_EQ(in.update(milliseconds(10)).controls.brake, 1.0f);
}

}  // namespace
}  // namespace tb::client
