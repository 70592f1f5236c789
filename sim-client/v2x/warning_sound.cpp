#include "sim-client/v2x/warning_sound.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <spdlog/spdlog.h>

namespace tb::client::v2x {

Alarm alarm_for(const V2xPicture& picture, std::uint32_t station) {
  const LcrwAlert* a = picture.alert_for(station);
  if (a != nullptr && a->severity == "critical")
    return Alarm::kCritical;
  if (picture.rlvw_for(station) != nullptr)
    return Alarm::kRedLight;
  return a != nullptr ? Alarm::kWarning : Alarm::kOff;
}

WarningTone::Pattern WarningTone::pattern(Alarm a) {
  switch (a) {
    case Alarm::kCritical:
      return {1500.0, 0.08, 0.06};
    case Alarm::kWarning:
      return {1000.0, 0.15, 0.15};
    case Alarm::kRedLight:
      return {1250.0, 0.09, 0.36, 2, 0.06};
    case Alarm::kOff:
      break;
  }
  return {0.0, 0.0, 1.0};
}

void WarningTone::set(Alarm a) {
  if (a == alarm_)
    return;
  if (alarm_ == Alarm::kOff)
    n_ = 0;
  alarm_ = a;
}

void WarningTone::fill(std::span<std::int16_t> out) {
  if (alarm_ == Alarm::kOff) {
    std::fill(out.begin(), out.end(), std::int16_t{0});
    return;
  }
  const Pattern p = pattern(alarm_);
  const double period = p.period_s();
  const double ramp = 0.005;  // 5 ms fade in and out
  for (auto& s : out) {
    const double t = static_cast<double>(n_++) / rate_;
    const double phase = std::fmod(t, period);
    // Which beep of the group, and how far into it.
    const int beep = static_cast<int>(phase / (p.on_s + p.gap_s));
    const double in_beep = phase - beep * (p.on_s + p.gap_s);
    double gain = 0.0;
    if (beep < p.beeps && in_beep < p.on_s)
      gain = std::min({1.0, in_beep / ramp, (p.on_s - in_beep) / ramp});
    s = static_cast<std::int16_t>(
        std::lround(9000.0 * gain * std::sin(2.0 * std::numbers::pi * p.frequency_hz * t)));
  }
}

WarningSound::WarningSound() {
  if (SDL_InitSubSystem(SDL_INIT_AUDIO) != 0) {
    spdlog::warn("no audio ({}): warnings are shown without sound", SDL_GetError());
    return;
  }
  subsystem_ = true;
  SDL_AudioSpec want{};
  want.freq = 48000;
  want.format = AUDIO_S16SYS;
  want.channels = 1;
  want.samples = 512;  // ~11 ms: the sound starts with the banner
  want.callback = &WarningSound::callback;
  want.userdata = this;
  SDL_AudioSpec have{};
  device_ = SDL_OpenAudioDevice(nullptr, 0, &want, &have, 0);
  if (device_ == 0) {
    spdlog::warn("no audio device ({}): warnings are shown without sound", SDL_GetError());
    return;
  }
  SDL_PauseAudioDevice(device_, 0);
}

WarningSound::~WarningSound() {
  if (device_ != 0)
    SDL_CloseAudioDevice(device_);
  if (subsystem_)
    SDL_QuitSubSystem(SDL_INIT_AUDIO);
}

void WarningSound::set(Alarm a) {
  wanted_.store(a, std::memory_order_relaxed);
}

void WarningSound::callback(void* self_ptr, Uint8* stream, int len) {
  auto* self = static_cast<WarningSound*>(self_ptr);
  // The tone is touched only here, in SDL's audio thread; the alarm crosses over atomically.
  self->tone_.set(self->wanted_.load(std::memory_order_relaxed));
  self->tone_.fill(std::span(reinterpret_cast<std::int16_t*>(stream),
                             static_cast<std::size_t>(len) / sizeof(std::int16_t)));
}

}  // namespace tb::client::v2x
