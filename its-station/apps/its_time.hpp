#pragma once
/// @file ITS time stamps as the applications report them (CDD TimestampIts, GenerationDeltaTime).

#include <chrono>
#include <cstdint>

#include "common/clock/clock.hpp"

namespace tb::its::apps {

/// Unix time of 2004-01-01T00:00:00Z in ms; the same definition as
/// its-station/facilities/its_time.hpp (UTC, no leap seconds), so that MQTT subscribers, trace
/// records and the air agree.
inline constexpr std::int64_t kItsEpochUnixMs = 1'072'915'200'000;

inline std::int64_t unix_ms(clock::WallTime t) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(t.time_since_epoch()).count();
}

/// CDD TimestampIts: ms since 2004-01-01T00:00:00Z.
inline std::int64_t timestamp_its(clock::WallTime t) {
  return unix_ms(t) - kItsEpochUnixMs;
}

/// CDD GenerationDeltaTime of a CAM generated at @p t: TimestampIts mod 65536 (EN 302 637-2).
/// A neighbour's state time is its CAM's generation time, so this names the CAM it came from.
inline std::uint16_t generation_delta_time(clock::WallTime t) {
  const std::int64_t its = timestamp_its(t);
  return static_cast<std::uint16_t>(((its % 65536) + 65536) % 65536);
}

}  // namespace tb::its::apps
