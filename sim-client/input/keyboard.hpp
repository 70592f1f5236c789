#pragma once
/// @file Keyboard driving, as CARLA's manual control does it (W/S, A/D, Q, Space), as pure
/// logic: the SDL layer turns key events into Key presses and calls update() once a frame.

#include <array>
#include <string_view>
#include <vector>

#include "common/clock/clock.hpp"
#include "sim-client/input/command.hpp"

namespace tb::client {

enum class Key {
  kThrottle,
  kBrake,
  kSteerLeft,
  kSteerRight,
  kReverse,
  kHandbrake,
  kIndicatorLeft,
  kIndicatorRight,
  kHazard,
  kLowBeam,
  kHighBeam,
  kFog,
  kLightBar,
  kSiren,
  kHelp,
  kQuit,
};
inline constexpr std::size_t kKeyCount = static_cast<std::size_t>(Key::kQuit) + 1;

struct KeyHelp {
  std::string_view keys;
  std::string_view action;
};
/// The key map shown with H (and printed by --help-keys).
const std::vector<KeyHelp>& key_map_help();

class KeyboardDriver {
 public:
  /// CARLA's manual control steps the steering by 5e-4 per millisecond and clamps it to ±0.7.
  static constexpr double kSteerRatePerSecond = 0.5;
  static constexpr double kSteerLimit = 0.7;
  /// CARLA raises throttle by 0.1 and brake by 0.2 per frame; at 60 fps that is 6/s and 12/s.
  static constexpr double kThrottleRatePerSecond = 6.0;
  static constexpr double kBrakeRatePerSecond = 12.0;

  /// Edge actions (reverse toggle, lights, help, quit) happen on press; held keys act in
  /// update(). Repeated presses from key auto-repeat must be filtered by the caller.
  void press(Key k);
  void release(Key k);
  /// Moves the ramps on by @p dt and returns the command in effect.
  const DriverCommand& update(clock::Duration dt);
  const DriverCommand& command() const { return command_; }
  bool help_shown() const { return help_; }
  bool quit_requested() const { return quit_; }
  bool held(Key k) const { return held_[static_cast<std::size_t>(k)]; }

 private:
  std::array<bool, kKeyCount> held_{};
  DriverCommand command_;
  bool help_ = false;
  bool quit_ = false;
};

}  // namespace tb::client
