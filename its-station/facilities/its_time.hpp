#pragma once
/// @file TimestampIts: the ITS time base of CAMs and DENMs.

#include <cstdint>

#include "common/clock/clock.hpp"

namespace tb::its::facilities {

/// Milliseconds between 1970-01-01 and 2004-01-01 00:00:00 UTC.
inline constexpr std::int64_t kItsEpochUnixMs = 1'072'915'200'000;
/// TimestampIts of a UTC instant, ms since 2004-01-01T00:00:00.000Z as TS 102 894-2 V1.3.1 (the
/// CDD of CAM V1.4.1) and REFERENCES.md define it. Later CDD versions count TAI milliseconds,
/// 5 s ahead (the leap seconds since 2004); every station of the testbed uses this definition,
/// so they agree among themselves and with the trace tools. Instants before 2004 are negative.
inline std::int64_t timestamp_its(clock::WallTime utc) {
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(utc.time_since_epoch()).count();
  return ms - kItsEpochUnixMs;
}

/// CAM generationDeltaTime, EN 302 637-2 clause B.3: TimestampIts mod 65 536.
inline std::uint16_t generation_delta_time(std::int64_t timestamp_its_ms) {
  return static_cast<std::uint16_t>(((timestamp_its_ms % 65536) + 65536) % 65536);
}

/// The UTC instant a received generationDeltaTime stands for: the latest instant not after
/// @p received (plus a small allowance for clock offsets between stations) with that value
/// modulo 65 536 ms. Unambiguous while CAMs arrive within a minute of their generation.
inline clock::WallTime generation_time(std::uint16_t gdt, clock::WallTime received) {
  constexpr std::int64_t kAllowanceMs = 2000;
  const std::int64_t now = timestamp_its(received) + kAllowanceMs;
  std::int64_t t = now - (((now - gdt) % 65536) + 65536) % 65536;
  return clock::WallTime{std::chrono::milliseconds{t + kItsEpochUnixMs}};
}

}  // namespace tb::its::facilities
