#include <gtest/gtest.h>

#include "sim-client/input/keyboard.hpp"

namespace tb::client {
namespace {

using std::chrono::milliseconds;

TEST(KeyboardDriver, SteeringRampsAtCarlaRateAndClamps) {
  KeyboardDriver k;
  k.press(Key::kSteerLeft);
  k.update(milliseconds(100));
  EXPECT_NEAR(k.command().controls.steer, -0.05, 1e-6);  // 5e-4 per ms
  for (int i = 0; i < 30; ++i)
    k.update(milliseconds(100));
  EXPECT_FLOAT_EQ(k.command().controls.steer, -0.7f);
  // Pressing the other way first snaps to centre, then turns.
  k.press(Key::kSteerRight);
  k.release(Key::kSteerLeft);
  k.update(milliseconds(16));
  EXPECT_FLOAT_EQ(k.command().controls.steer, 0.0f);
  k.update(milliseconds(200));
  EXPECT_NEAR(k.command().controls.steer, 0.1, 1e-6);
  k.release(Key::kSteerRight);
  k.update(milliseconds(16));
  EXPECT_FLOAT_EQ(k.command().controls.steer, 0.0f);
}

TEST(KeyboardDriver, ThrottleAndBrakeRampWhileHeldAndDropOnRelease) {
  KeyboardDriver k;
  k.press(Key::kThrottle);
  k.update(milliseconds(50));
  EXPECT_NEAR(k.command().controls.throttle, 0.3, 1e-6);
  k.update(milliseconds(500));
  EXPECT_FLOAT_EQ(k.command().controls.throttle, 1.0f);
  k.release(Key::kThrottle);
  k.press(Key::kBrake);
  k.update(milliseconds(50));
  EXPECT_FLOAT_EQ(k.command().controls.throttle, 0.0f);
  EXPECT_NEAR(k.command().controls.brake, 0.6, 1e-6);
  k.release(Key::kBrake);
  k.update(milliseconds(1));
  EXPECT_FLOAT_EQ(k.command().controls.brake, 0.0f);
}

TEST(KeyboardDriver, TogglesAndHeldKeys) {
  KeyboardDriver k;
  k.press(Key::kReverse);
  k.release(Key::kReverse);
  k.press(Key::kHandbrake);
  k.update(milliseconds(10));
  EXPECT_TRUE(k.command().controls.reverse);
  EXPECT_TRUE(k.command().controls.handbrake);
  k.release(Key::kHandbrake);
  k.press(Key::kReverse);
  k.update(milliseconds(10));
  EXPECT_FALSE(k.command().controls.reverse);
  EXPECT_FALSE(k.command().controls.handbrake);

  k.press(Key::kIndicatorLeft);
  EXPECT_EQ(k.command().lights, wire::kIndicatorLeft);
  k.press(Key::kIndicatorRight);  // the stalk goes the other way
  EXPECT_EQ(k.command().lights, wire::kIndicatorRight);
  k.press(Key::kLowBeam);
  k.press(Key::kHazard);
  EXPECT_EQ(k.command().lights, wire::kHazard | wire::kLowBeam);
  k.press(Key::kHazard);
  EXPECT_EQ(k.command().lights, wire::kLowBeam);
  // A special vehicle's light bar and siren, each on its own key.
  k.press(Key::kLightBar);
  k.press(Key::kSiren);
  EXPECT_EQ(k.command().lights, wire::kLowBeam | wire::kLightBar | wire::kSiren);
  k.press(Key::kSiren);
  EXPECT_EQ(k.command().lights, wire::kLowBeam | wire::kLightBar);

  EXPECT_FALSE(k.help_shown());
  k.press(Key::kHelp);
  EXPECT_TRUE(k.help_shown());
  EXPECT_FALSE(k.quit_requested());
  k.press(Key::kQuit);
  EXPECT_TRUE(k.quit_requested());
  EXPECT_FALSE(key_map_help().empty());
}

}  // namespace
}  // namespace tb::client
