#pragma once
/// @file Game controllers, joysticks and steering wheels: a JSON mapping file (axes, inversion,
/// dead zones, pedal ranges, buttons) and the pure logic that turns axis and button readings
/// into a DriverCommand. The SDL layer (sdl_input.hpp) feeds it events.

#include <array>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "sim-client/input/command.hpp"

namespace tb::client {

/// Which SDL API reads the device: GameController (standard layout, axes and buttons by name)
/// or Joystick (raw numbered axes and buttons, what wheels and pedals need).
enum class ControllerApi { kGameController, kJoystick };

struct SteerAxis {
  enum class Curve { kLinear, kTan };
  int axis = 0;
  bool invert = false;
  double dead_zone = 0.0;  ///< |value| below this reads as 0; the rest is rescaled to [0, 1]
  Curve curve = Curve::kLinear;
  /// linear: steer = gain·v; tan: steer = gain·tan(1.1·v), CARLA's wheel example (gain 0.55).
  double gain = 1.0;
};

/// A pedal or trigger: the raw value (SDL's axis scaled to [-1, 1]) at rest and fully pressed;
/// giving them the other way round inverts the axis.
struct PedalAxis {
  int axis = 0;
  double released = -1.0;
  double pressed = 1.0;
  double dead_zone = 0.0;  ///< travel fraction ignored near rest
};

enum class Action {
  kReverse,    ///< toggles
  kHandbrake,  ///< held
  kIndicatorLeft,
  kIndicatorRight,
  kHazard,
  kLowBeam,
  kHighBeam,
  kFog,
};
inline constexpr std::size_t kActionCount = static_cast<std::size_t>(Action::kFog) + 1;
std::string_view to_string(Action a);

struct ControllerMapping {
  std::string source;  ///< file it came from, for messages
  std::string name;
  ControllerApi api = ControllerApi::kJoystick;
  std::string device;  ///< open the first device whose name contains this; empty: any
  SteerAxis steer;
  PedalAxis throttle;
  PedalAxis brake;
  std::array<std::optional<int>, kActionCount> buttons{};
};

/// A mapping that cannot be used; what() reads "FILE: /json/pointer: reason".
class MappingError : public std::runtime_error {
 public:
  MappingError(std::string file, std::string field, std::string reason);
  const std::string& file() const { return file_; }
  const std::string& field() const { return field_; }

 private:
  std::string file_, field_;
};

/// @throws MappingError naming the file and the field.
ControllerMapping load_mapping(const std::filesystem::path& file);
ControllerMapping parse_mapping(std::string_view json_text, const std::string& file_name);

/// SDL GameController axis and button names ("leftx", "triggerright", "a", "leftshoulder", ...)
/// and their SDL enum values; the SDL layer checks at compile time that they agree.
std::optional<int> game_controller_axis(std::string_view name);
std::optional<int> game_controller_button(std::string_view name);

/// Turns readings of one device into a command. Until a device is connected, and after it is
/// unplugged, the command releases the throttle and brakes fully.
class ControllerDriver {
 public:
  static constexpr float kUnpluggedBrake = 1.0f;

  explicit ControllerDriver(ControllerMapping mapping);
  const ControllerMapping& mapping() const { return mapping_; }

  void connect(std::string device_name);
  void disconnect();
  bool connected() const { return connected_; }
  const std::string& device_name() const { return device_; }
  /// @p value is SDL's reading scaled to [-1, 1].
  void axis(int index, double value);
  void button(int index, bool down);
  DriverCommand command() const;

 private:
  struct Reading {
    double value = 0.0;
    bool seen = false;
  };
  double pedal(const PedalAxis& p) const;

  ControllerMapping mapping_;
  bool connected_ = false;
  std::string device_;
  std::vector<Reading> axes_;
  std::vector<bool> buttons_;
  bool reverse_ = false;
  std::uint16_t lights_ = 0;
};

}  // namespace tb::client
