#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "sim-client/input/controller.hpp"

namespace tb::client {
namespace {

constexpr const char* kWheel = R"({
  "name": "wheel", "api": "joystick",
  "steer": {"axis": 0, "curve": "tan", "gain": 0.55},
  "throttle": {"axis": 2, "released": 1.0, "pressed": -1.0, "dead_zone": 0.05},
  "brake": {"axis": 3, "released": 1.0, "pressed": -1.0},
  "buttons": {"reverse": 5, "handbrake": 4, "indicator_left": 6}
})";

// The error for @p json, which must fail.
std::string error_of(const std::string& json) {
  try {
    parse_mapping(json, "m.json");
  } catch (const MappingError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Mapping, ErrorsNameFileAndField) {
  EXPECT_EQ(error_of("{").rfind("m.json: /: not valid JSON", 0), 0u) << error_of("{");
  EXPECT_EQ(error_of(R"({"api": "joystick"})"),
            "m.json: /steer: missing (every mapping needs steer, throttle and brake)");
  EXPECT_EQ(error_of(R"({"api": "wheel"})"),
            "m.json: /api: \"wheel\" is neither \"gamecontroller\" nor \"joystick\"");
  EXPECT_EQ(error_of(R"({"api": "joystick", "steer": {"axis": "leftx"}})"),
            "m.json: /steer/axis: must be an axis index (the mapping's api is \"joystick\")");
  EXPECT_NE(error_of(R"({"api": "gamecontroller", "steer": {"axis": "wheel"}})")
                .find("m.json: /steer/axis: unknown axis \"wheel\" (one of leftx"),
            std::string::npos);
  EXPECT_EQ(error_of(R"({"api": "joystick", "steer": {"axis": 0, "dead_zone": 0.9}})"),
            "m.json: /steer/dead_zone: value 0.9 is outside [0, 0.5]");
  EXPECT_EQ(error_of(R"({"api": "joystick", "steer": {"axis": 0},
                         "throttle": {"axis": 1, "released": 0.5, "pressed": 0.55}})"),
            "m.json: /throttle/pressed: must differ from \"released\" by at least 0.1 (the "
            "pedal's travel)");
  EXPECT_EQ(error_of(R"({"api": "joystick", "steer": {"axis": 0}, "throttle": {"axis": 1},
                         "brake": {"axis": 99}})"),
            "m.json: /brake/axis: index 99 is outside [0, 63]");
  EXPECT_EQ(error_of(R"({"api": "joystick", "steer": {"axis": 0}, "throttle": {"axis": 1},
                         "brake": {"axis": 2}, "buttons": {"horn": 1}})")
                .substr(0, 40),
            "m.json: /buttons/horn: unknown action (o");
  EXPECT_EQ(error_of(R"({"api": "joystick", "steer": {"axis": 0, "inverted": true}})"),
            "m.json: /steer/inverted: unknown field");
}

TEST(Mapping, MissingFileIsAClearError) {
  try {
    load_mapping("/nonexistent/wheel.json");
    FAIL();
  } catch (const MappingError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/wheel.json: /: cannot open the mapping file");
  }
}

TEST(Mapping, ShippedExamplesLoad) {
  const std::string root = std::getenv("TESTBED_ROOT") ? std::getenv("TESTBED_ROOT") : ".";
  const ControllerMapping pad = load_mapping(root + "/sim-client/mappings/xbox.json");
  EXPECT_EQ(pad.api, ControllerApi::kGameController);
  EXPECT_EQ(pad.throttle.axis, 5);  // triggerright
  const ControllerMapping wheel = load_mapping(root + "/sim-client/mappings/logitech-wheel.json");
  EXPECT_EQ(wheel.api, ControllerApi::kJoystick);
  EXPECT_EQ(wheel.steer.curve, SteerAxis::Curve::kTan);
}

TEST(ControllerDriver, WheelPedalsAndSteering) {
  ControllerDriver d(parse_mapping(kWheel, "wheel.json"));
  EXPECT_FLOAT_EQ(d.command().controls.brake, ControllerDriver::kUnpluggedBrake);
  d.connect("G29");
  // Unmoved pedals read as released even though the device reports 0 (= half travel).
  EXPECT_FLOAT_EQ(d.command().controls.throttle, 0.0f);
  EXPECT_FLOAT_EQ(d.command().controls.brake, 0.0f);
  d.axis(2, 0.0);  // half way down
  EXPECT_NEAR(d.command().controls.throttle, (0.5 - 0.05) / 0.95, 1e-6);
  d.axis(2, 0.95);  // inside the dead zone
  EXPECT_FLOAT_EQ(d.command().controls.throttle, 0.0f);
  d.axis(3, -1.0);
  EXPECT_FLOAT_EQ(d.command().controls.brake, 1.0f);
  d.axis(0, 0.3);
  EXPECT_NEAR(d.command().controls.steer, 0.55 * std::tan(1.1 * 0.3), 1e-6);
  d.axis(0, -1.0);
  EXPECT_FLOAT_EQ(d.command().controls.steer, -1.0f);

  d.button(5, true);
  d.button(5, true);  // held, not a second press
  d.button(4, true);
  d.button(6, true);
  EXPECT_TRUE(d.command().controls.reverse);
  EXPECT_TRUE(d.command().controls.handbrake);
  EXPECT_EQ(d.command().lights, wire::kIndicatorLeft);
  d.button(4, false);
  EXPECT_FALSE(d.command().controls.handbrake);

  d.axis(2, -1.0);
  d.axis(3, 1.0);
  EXPECT_FLOAT_EQ(d.command().controls.throttle, 1.0f);
  d.disconnect();  // unplugged at full throttle
  EXPECT_FLOAT_EQ(d.command().controls.throttle, 0.0f);
  EXPECT_FLOAT_EQ(d.command().controls.brake, 1.0f);
  EXPECT_FLOAT_EQ(d.command().controls.steer, 0.0f);
}

TEST(ControllerDriver, InvertedLinearSteerWithDeadZone) {
  ControllerMapping m = parse_mapping(kWheel, "wheel.json");
  m.steer.curve = SteerAxis::Curve::kLinear;
  m.steer.gain = 1.0;
  m.steer.invert = true;
  m.steer.dead_zone = 0.1;
  ControllerDriver d(m);
  d.connect("pad");
  d.axis(0, 0.05);
  EXPECT_FLOAT_EQ(d.command().controls.steer, 0.0f);
  d.axis(0, 0.55);
  EXPECT_NEAR(d.command().controls.steer, -0.5, 1e-6);
}

}  // namespace
}  // namespace tb::client
