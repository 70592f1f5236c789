#pragma once
/// @file TimestampIts: the ITS time base of CAMs and DENMs.

#include <cstdint>

#include "common/clock/clock.hpp"

namespace tb::its::facilities {

/// Milliseconds between 1970-01-01 and 2004-01-01 00:00:00 UTC.
inline constexpr std::int64_t kItsEpochUnixMs = 1'072'915'200'000;
/// TimestampIts of a UTC instant, ms since 2004-01-01T00:00:00.000Z as TS 102 894-2 V1.3.1 (the
/// CDD of CAM V1.4.1) defines it. Later CDD versions count TAI milliseconds, 5 s ahead (the
/// leap seconds since 2004); we send UTC and accept either (docs/time.md, the one place that
/// says which clock each field uses). Instants before 2004 are negative.
inline std::int64_t timestamp_its(clock::WallTime utc) {
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(utc.time_since_epoch()).count();
  return ms - kItsEpochUnixMs;
}

/// CAM generationDeltaTime, EN 302 637-2 clause B.3: TimestampIts mod 65 536.
inline std::uint16_t generation_delta_time(std::int64_t timestamp_its_ms) {
  return static_cast<std::uint16_t>(((timestamp_its_ms % 65536) + 65536) % 65536);
}

/// How far ahead of our clock a received generationDeltaTime may name its generation: CDD V2.x
/// peers stamp TAI, 5 s ahead of our UTC (docs/time.md), and stations' clocks differ by a
/// little more. Anything later would be a CAM from the future; read as the past, a TAI peer's
/// CAM would be dated 60 s back and look lost.
inline constexpr std::int64_t kGenerationTimeAheadAllowanceMs = 10'000;

/// The UTC instant a received generationDeltaTime stands for: the one instant with that value
/// modulo 65 536 ms in (received − 55.5 s, received + 10 s]. Unambiguous while CAMs arrive
/// within 55 s of their generation, whether the sender counts UTC (CDD V1.3.1) or TAI (V2.x).
inline clock::WallTime generation_time(std::uint16_t gdt, clock::WallTime received) {
  const std::int64_t now = timestamp_its(received) + kGenerationTimeAheadAllowanceMs;
  std::int64_t t = now - (((now - gdt) % 65536) + 65536) % 65536;
  return clock::WallTime{std::chrono::milliseconds{t + kItsEpochUnixMs}};
}

}  // namespace tb::its::facilities
