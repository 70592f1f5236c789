#include "sim-client/input/keyboard.hpp"

#include <algorithm>

namespace tb::client {

void toggle_light(std::uint16_t& lights, wire::Light which) {
  const bool was_on = (lights & which) != 0;
  if (which == wire::kIndicatorLeft || which == wire::kIndicatorRight || which == wire::kHazard) {
    lights &=
        static_cast<std::uint16_t>(~(wire::kIndicatorLeft | wire::kIndicatorRight | wire::kHazard));
  }
  if (was_on) {
    lights &= static_cast<std::uint16_t>(~which);
  } else {
    lights |= which;
  }
}

const std::vector<KeyHelp>& key_map_help() {
  static const std::vector<KeyHelp> help{
      {"W / Up", "throttle"},
      {"S / Down", "brake"},
      {"A D / Left Right", "steer"},
      {"Q", "toggle reverse"},
      {"Space", "handbrake"},
      {"Z / X", "left / right indicator"},
      {"C", "hazard lights"},
      {"L", "low beam"},
      {"K", "high beam"},
      {"F", "fog light"},
      {"B / N", "light bar / siren (special vehicles)"},
      {"Tab", "next camera: chase, cockpit, top, orbit (3D view)"},
      {"[ ]", "previous / next car to follow"},
      {"PgUp PgDn, wheel", "zoom the orbit and top cameras"},
      {"mouse drag", "turn the orbit camera"},
      {"N", "V2X network overlay (with --mqtt)"},
      {"F1", "frame rate"},
      {"H", "show / hide this help"},
      {"Esc", "quit"},
  };
  return help;
}

void KeyboardDriver::press(Key k) {
  held_[static_cast<std::size_t>(k)] = true;
  auto& c = command_.controls;
  switch (k) {
    case Key::kReverse:
      c.reverse = !c.reverse;
      break;
    case Key::kIndicatorLeft:
      toggle_light(command_.lights, wire::kIndicatorLeft);
      break;
    case Key::kIndicatorRight:
      toggle_light(command_.lights, wire::kIndicatorRight);
      break;
    case Key::kHazard:
      toggle_light(command_.lights, wire::kHazard);
      break;
    case Key::kLowBeam:
      toggle_light(command_.lights, wire::kLowBeam);
      break;
    case Key::kHighBeam:
      toggle_light(command_.lights, wire::kHighBeam);
      break;
    case Key::kFog:
      toggle_light(command_.lights, wire::kFogLight);
      break;
    case Key::kLightBar:
      toggle_light(command_.lights, wire::kLightBar);
      break;
    case Key::kSiren:
      toggle_light(command_.lights, wire::kSiren);
      break;
    case Key::kHelp:
      help_ = !help_;
      break;
    case Key::kQuit:
      quit_ = true;
      break;
    default:
      break;
  }
}

void KeyboardDriver::release(Key k) {
  held_[static_cast<std::size_t>(k)] = false;
}

const DriverCommand& KeyboardDriver::update(clock::Duration dt) {
  const double s = std::chrono::duration<double>(dt).count();
  auto& c = command_.controls;
  c.throttle = held(Key::kThrottle)
                   ? static_cast<float>(std::min(c.throttle + kThrottleRatePerSecond * s, 1.0))
                   : 0.0f;
  c.brake = held(Key::kBrake) ? static_cast<float>(std::min(c.brake + kBrakeRatePerSecond * s, 1.0))
                              : 0.0f;
  // As CARLA: a steering key first snaps back a wheel turned the other way; no key centres it.
  const double step = kSteerRatePerSecond * s;
  double steer = c.steer;
  const bool left = held(Key::kSteerLeft), right = held(Key::kSteerRight);
  if (left && !right) {
    steer = steer > 0.0 ? 0.0 : steer - step;
  } else if (right && !left) {
    steer = steer < 0.0 ? 0.0 : steer + step;
  } else {
    steer = 0.0;
  }
  c.steer = static_cast<float>(std::clamp(steer, -kSteerLimit, kSteerLimit));
  c.handbrake = held(Key::kHandbrake);
  return command_;
}

}  // namespace tb::client
