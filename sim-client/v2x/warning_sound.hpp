#pragma once
/// @file The driver's warning sound for as long as an LCRW or a red-light (RLVW) warning lasts:
/// a beep pattern, faster for a critical warning (TTC below the critical threshold), a double
/// beep of its own for the red light, played through SDL audio.
/// The pattern is a pure generator (WarningTone) so that tests can check the samples.

#include <SDL.h>

#include <atomic>
#include <cstdint>
#include <span>

#include "sim-client/v2x/monitor.hpp"

namespace tb::client::v2x {

/// In rising priority: when several warnings are active the sound is the highest one's.
enum class Alarm : std::uint8_t { kOff, kWarning, kRedLight, kCritical };

/// The alarm for @p station's warnings: a critical LCRW warning first (a collision within its
/// critical TTC), then the red light (the car will cross the stop line on red), then an LCRW
/// warning.
Alarm alarm_for(const V2xPicture& picture, std::uint32_t station);

/// Square-ish beeps (a sine with soft edges, so no clicks): warning 1 kHz, 150 ms on / 150 ms
/// off; critical 1.5 kHz, 80 ms on / 60 ms off; red light 1.25 kHz, two 90 ms beeps 60 ms
/// apart every 600 ms (a rhythm of its own, so that a driver who hears it without looking knows
/// it is not the collision warning). The pattern restarts with its beep when the alarm goes
/// from off to on, so the first sample the driver hears is a beep.
class WarningTone {
 public:
  explicit WarningTone(int sample_rate) : rate_(sample_rate) {}
  void set(Alarm a);
  Alarm alarm() const { return alarm_; }
  /// Writes the next samples (mono, signed 16 bit).
  void fill(std::span<std::int16_t> out);

  struct Pattern {
    double frequency_hz;
    double on_s;         ///< each beep
    double off_s;        ///< after the last beep of a group
    int beeps = 1;       ///< beeps in a group
    double gap_s = 0.0;  ///< between the beeps of a group
    double period_s() const { return beeps * on_s + (beeps - 1) * gap_s + off_s; }
  };
  static Pattern pattern(Alarm a);

 private:
  int rate_;
  Alarm alarm_ = Alarm::kOff;
  std::uint64_t n_ = 0;  ///< samples since the pattern started
};

/// An SDL audio device playing WarningTone. Without an audio device (containers, CI) it stays
/// silent and says so once; the banner still shows.
class WarningSound {
 public:
  WarningSound();
  ~WarningSound();
  WarningSound(const WarningSound&) = delete;
  WarningSound& operator=(const WarningSound&) = delete;

  void set(Alarm a);
  bool playing_device() const { return device_ != 0; }

 private:
  static void callback(void* self, Uint8* stream, int len);
  SDL_AudioDeviceID device_ = 0;
  bool subsystem_ = false;
  WarningTone tone_{48000};
  std::atomic<Alarm> wanted_{Alarm::kOff};
};

}  // namespace tb::client::v2x
