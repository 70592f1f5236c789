#pragma once
/// @file UTC instants as text for logs: 2025-06-02T09:00:00.000Z.

#include <ctime>
#include <string>

#include <fmt/format.h>

#include "common/clock/clock.hpp"

namespace tb::clock {

/// ISO 8601 with milliseconds and a Z.
inline std::string format_utc(WallTime t) {
  const std::int64_t ms = to_unix_ns(t) / 1'000'000 - (to_unix_ns(t) % 1'000'000 < 0 ? 1 : 0);
  const std::time_t s = static_cast<std::time_t>(ms / 1000 - (ms % 1000 < 0 ? 1 : 0));
  std::tm tm{};
  gmtime_r(&s, &tm);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", tm.tm_year + 1900, tm.tm_mon + 1,
                     tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec, ((ms % 1000) + 1000) % 1000);
}

}  // namespace tb::clock
