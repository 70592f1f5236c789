#include "sim-client/input/sdl_input.hpp"

#include <algorithm>
#include <cctype>

#include <spdlog/spdlog.h>

namespace tb::client {
namespace {

// controller.cpp names GameController axes and buttons by SDL's enum values.
static_assert(SDL_CONTROLLER_AXIS_LEFTX == 0 && SDL_CONTROLLER_AXIS_TRIGGERRIGHT == 5);
static_assert(SDL_CONTROLLER_BUTTON_A == 0 && SDL_CONTROLLER_BUTTON_LEFTSHOULDER == 9 &&
              SDL_CONTROLLER_BUTTON_DPAD_RIGHT == 14);

double scale_axis(Sint16 v) {
  return std::clamp(static_cast<double>(v) / 32767.0, -1.0, 1.0);
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

}  // namespace

std::optional<Key> key_for(SDL_Scancode code) {
  switch (code) {
    case SDL_SCANCODE_W:
    case SDL_SCANCODE_UP:
      return Key::kThrottle;
    case SDL_SCANCODE_S:
    case SDL_SCANCODE_DOWN:
      return Key::kBrake;
    case SDL_SCANCODE_A:
    case SDL_SCANCODE_LEFT:
      return Key::kSteerLeft;
    case SDL_SCANCODE_D:
    case SDL_SCANCODE_RIGHT:
      return Key::kSteerRight;
    case SDL_SCANCODE_Q:
      return Key::kReverse;
    case SDL_SCANCODE_SPACE:
      return Key::kHandbrake;
    case SDL_SCANCODE_Z:
      return Key::kIndicatorLeft;
    case SDL_SCANCODE_X:
      return Key::kIndicatorRight;
    case SDL_SCANCODE_C:
      return Key::kHazard;
    case SDL_SCANCODE_L:
      return Key::kLowBeam;
    case SDL_SCANCODE_K:
      return Key::kHighBeam;
    case SDL_SCANCODE_F:
      return Key::kFog;
    case SDL_SCANCODE_B:
      return Key::kLightBar;
    case SDL_SCANCODE_N:
      return Key::kSiren;
    case SDL_SCANCODE_H:
      return Key::kHelp;
    case SDL_SCANCODE_ESCAPE:
      return Key::kQuit;
    default:
      return std::nullopt;
  }
}

SdlInput::SdlInput(std::optional<ControllerMapping> mapping) {
  if (mapping)
    controller_.emplace(std::move(*mapping));
}

SdlInput::~SdlInput() {
  close();
}

bool SdlInput::matches(int index) const {
  if (!controller_)
    return false;
  const auto& m = controller_->mapping();
  const char* name = nullptr;
  if (m.api == ControllerApi::kGameController) {
    if (!SDL_IsGameController(index))
      return false;
    name = SDL_GameControllerNameForIndex(index);
  } else {
    name = SDL_JoystickNameForIndex(index);
  }
  if (m.device.empty())
    return true;
  return name != nullptr && lower(name).find(lower(m.device)) != std::string::npos;
}

void SdlInput::open(int index) {
  const auto& m = controller_->mapping();
  const char* name = nullptr;
  if (m.api == ControllerApi::kGameController) {
    pad_ = SDL_GameControllerOpen(index);
    if (pad_ == nullptr) {
      spdlog::warn("cannot open game controller {}: {}", index, SDL_GetError());
      return;
    }
    stick_ = SDL_GameControllerGetJoystick(pad_);
    name = SDL_GameControllerName(pad_);
  } else {
    stick_ = SDL_JoystickOpen(index);
    if (stick_ == nullptr) {
      spdlog::warn("cannot open joystick {}: {}", index, SDL_GetError());
      return;
    }
    name = SDL_JoystickName(stick_);
  }
  instance_ = SDL_JoystickInstanceID(stick_);
  controller_->connect(name != nullptr ? name : "unnamed device");
  spdlog::info("controller \"{}\" connected (mapping {})", controller_->device_name(),
               m.name.empty() ? m.source : m.name);
}

void SdlInput::close() {
  if (pad_ != nullptr) {
    SDL_GameControllerClose(pad_);
  } else if (stick_ != nullptr) {
    SDL_JoystickClose(stick_);
  }
  pad_ = nullptr;
  stick_ = nullptr;
  instance_ = -1;
}

void SdlInput::scan() {
  if (!controller_ || stick_ != nullptr)
    return;
  for (int i = 0; i < SDL_NumJoysticks() && stick_ == nullptr; ++i) {
    if (matches(i))
      open(i);
  }
  if (stick_ == nullptr)
    spdlog::warn("no controller for mapping {} yet: braking until one is plugged in",
                 controller_->mapping().source);
}

void SdlInput::handle(const SDL_Event& e) {
  const bool pad_api = controller_ && controller_->mapping().api == ControllerApi::kGameController;
  switch (e.type) {
    case SDL_QUIT:
      quit_ = true;
      return;
    case SDL_KEYDOWN:
    case SDL_KEYUP: {
      if (e.key.repeat != 0)
        return;
      const auto k = key_for(e.key.keysym.scancode);
      if (!k)
        return;
      // With a controller driving, the keyboard keeps only help and quit.
      if (controller_ && *k != Key::kHelp && *k != Key::kQuit)
        return;
      if (e.type == SDL_KEYDOWN) {
        keyboard_.press(*k);
      } else {
        keyboard_.release(*k);
      }
      return;
    }
    case SDL_CONTROLLERDEVICEADDED:
      if (pad_api && stick_ == nullptr && matches(e.cdevice.which))
        open(e.cdevice.which);
      return;
    case SDL_JOYDEVICEADDED:
      if (controller_ && !pad_api && stick_ == nullptr && matches(e.jdevice.which))
        open(e.jdevice.which);
      return;
    case SDL_CONTROLLERDEVICEREMOVED:
    case SDL_JOYDEVICEREMOVED: {
      const SDL_JoystickID id = e.type == SDL_JOYDEVICEREMOVED ? e.jdevice.which : e.cdevice.which;
      if (stick_ == nullptr || id != instance_)
        return;
      spdlog::warn("controller \"{}\" unplugged: throttle released, braking",
                   controller_->device_name());
      close();
      controller_->disconnect();
      scan();
      return;
    }
    case SDL_CONTROLLERAXISMOTION:
      if (pad_api && e.caxis.which == instance_)
        controller_->axis(e.caxis.axis, scale_axis(e.caxis.value));
      return;
    case SDL_CONTROLLERBUTTONDOWN:
    case SDL_CONTROLLERBUTTONUP:
      if (pad_api && e.cbutton.which == instance_)
        controller_->button(e.cbutton.button, e.type == SDL_CONTROLLERBUTTONDOWN);
      return;
    case SDL_JOYAXISMOTION:
      if (controller_ && !pad_api && e.jaxis.which == instance_)
        controller_->axis(e.jaxis.axis, scale_axis(e.jaxis.value));
      return;
    case SDL_JOYBUTTONDOWN:
    case SDL_JOYBUTTONUP:
      if (controller_ && !pad_api && e.jbutton.which == instance_)
        controller_->button(e.jbutton.button, e.type == SDL_JOYBUTTONDOWN);
      return;
    default:
      return;
  }
}

DriverCommand SdlInput::update(clock::Duration dt) {
  const DriverCommand& keys = keyboard_.update(dt);
  if (controller_)
    return controller_->command();
  return keys;
}

std::string SdlInput::status() const {
  if (!controller_)
    return "keyboard";
  if (!controller_->connected())
    return "controller unplugged: braking";
  return "controller " + controller_->device_name();
}

}  // namespace tb::client
