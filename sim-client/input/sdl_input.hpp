#pragma once
/// @file The SDL2 side of input: key events to KeyboardDriver, game controller and joystick
/// events (with hot-plugging) to ControllerDriver. Owns no window; the caller pumps events.

#include <optional>
#include <string>

#include <SDL.h>

#include "common/clock/clock.hpp"
#include "sim-client/input/controller.hpp"
#include "sim-client/input/keyboard.hpp"

namespace tb::client {

/// The driving key for a physical key (scancodes, so WASD stays put on other layouts).
std::optional<Key> key_for(SDL_Scancode code);

class SdlInput {
 public:
  /// Without a mapping the keyboard drives; with one the mapped device drives and the keyboard
  /// keeps only H and Esc. SDL's event subsystem (and joystick/game controller subsystems
  /// when a mapping is given) must be initialised.
  explicit SdlInput(std::optional<ControllerMapping> mapping);
  ~SdlInput();
  SdlInput(const SdlInput&) = delete;
  SdlInput& operator=(const SdlInput&) = delete;

  /// Opens a matching device already plugged in (later ones arrive as events).
  void scan();
  void handle(const SDL_Event& e);
  /// Advances the keyboard ramps by @p dt; returns the command of whichever input drives.
  DriverCommand update(clock::Duration dt);

  bool quit_requested() const { return quit_ || keyboard_.quit_requested(); }
  bool help_shown() const { return keyboard_.help_shown(); }
  /// "keyboard", "controller NAME" or "controller unplugged: braking", for the view and logs.
  std::string status() const;
  const KeyboardDriver& keyboard() const { return keyboard_; }

 private:
  bool matches(int device_index) const;
  void open(int device_index);
  void close();

  KeyboardDriver keyboard_;
  std::optional<ControllerDriver> controller_;
  SDL_GameController* pad_ = nullptr;
  SDL_Joystick* stick_ = nullptr;
  SDL_JoystickID instance_ = -1;
  bool quit_ = false;
};

}  // namespace tb::client
