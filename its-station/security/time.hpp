#pragma once
/// @file 1609.2 time (6.4.12, 6.4.13): Time64 microseconds and Time32 seconds since
/// 2004-01-01 00:00:00 TAI, from the wall clock (UTC).
///
/// TAI counts the leap seconds UTC inserted since 2004 (five by 2017-01-01, none since); stacks
/// such as Vanetza count without them, 5 s behind. Both are in use, so the verifier measures a
/// generation time against both (TimeBase) and tells which one matched. The leap-second table
/// is the one geonet/timestamp.cpp has; the security layer sits below geonet and keeps its own.

#include <array>
#include <chrono>
#include <cstdint>

#include "common/clock/clock.hpp"
#include "its-station/security/ieee1609dot2.hpp"

namespace tb::its::security {

enum class TimeBase : std::uint8_t { kTai, kUtcNoLeapSeconds };

/// Unix time of 2004-01-01 00:00:00 UTC.
inline constexpr std::int64_t kEpoch2004UnixSeconds = 1'072'915'200;

/// Leap seconds inserted after 2004-01-01 and before @p unix_seconds (IERS Bulletin C).
inline int leap_seconds_since_2004(std::int64_t unix_seconds) {
  // The first second after each insertion: 2006-01-01, 2009-01-01, 2012-07-01, 2015-07-01,
  // 2017-01-01.
  constexpr std::array<std::int64_t, 5> kAfter{1136073600, 1230768000, 1341100800, 1435708800,
                                               1483228800};
  int n = 0;
  for (auto t : kAfter)
    n += unix_seconds >= t ? 1 : 0;
  return n;
}

/// The Time64 of the UTC instant @p t on the time base @p base.
inline Time64 to_time64(clock::WallTime t, TimeBase base = TimeBase::kTai) {
  const auto us =
      std::chrono::duration_cast<std::chrono::microseconds>(t.time_since_epoch()).count();
  const std::int64_t unix_s = us / 1000000;
  std::int64_t v = us - kEpoch2004UnixSeconds * 1000000;
  if (base == TimeBase::kTai)
    v += std::int64_t{leap_seconds_since_2004(unix_s)} * 1000000;
  return v < 0 ? 0 : static_cast<Time64>(v);
}

/// Time32 (TAI) of @p t.
inline Time32 to_time32(clock::WallTime t) {
  return static_cast<Time32>(to_time64(t) / 1000000);
}

}  // namespace tb::its::security
