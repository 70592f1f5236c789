#pragma once
/// @file UTC instants as text for logs: 2025-06-02T09:00:00.000Z, and back (command lines).

#include <cctype>
#include <chrono>
#include <ctime>
#include <optional>
#include <string>
#include <string_view>

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

/// The instant of ISO 8601 UTC text `YYYY-MM-DDTHH:MM:SS[.fraction]Z` (2025-06-02T09:00:00Z);
/// nothing when the text is not of that form or names no such date or time of day (a leap
/// second, :60, is refused: the testbed's clocks have none).
inline std::optional<WallTime> parse_utc(std::string_view s) {
  auto digits = [&](std::size_t at, std::size_t n) -> std::optional<int> {
    if (at + n > s.size())
      return std::nullopt;
    int v = 0;
    for (std::size_t i = at; i < at + n; ++i) {
      if (!std::isdigit(static_cast<unsigned char>(s[i])))
        return std::nullopt;
      v = v * 10 + (s[i] - '0');
    }
    return v;
  };
  auto sep = [&](std::size_t at, char c) { return at < s.size() && s[at] == c; };
  const auto y = digits(0, 4), mo = digits(5, 2), d = digits(8, 2), h = digits(11, 2),
             mi = digits(14, 2), sec = digits(17, 2);
  if (!y || !mo || !d || !h || !mi || !sec || !sep(4, '-') || !sep(7, '-') || !sep(10, 'T') ||
      !sep(13, ':') || !sep(16, ':') || *h > 23 || *mi > 59 || *sec > 59)
    return std::nullopt;
  const std::chrono::year_month_day date{std::chrono::year{*y},
                                         std::chrono::month{static_cast<unsigned>(*mo)},
                                         std::chrono::day{static_cast<unsigned>(*d)}};
  if (!date.ok())
    return std::nullopt;
  std::size_t at = 19;
  std::chrono::nanoseconds fraction{0};
  if (sep(at, '.')) {
    ++at;
    std::int64_t scale = 100'000'000;
    const std::size_t first = at;
    while (at < s.size() && std::isdigit(static_cast<unsigned char>(s[at]))) {
      fraction += std::chrono::nanoseconds{(s[at] - '0') * scale};
      scale /= 10;
      ++at;
    }
    if (at == first)
      return std::nullopt;
  }
  if (at + 1 != s.size() || s[at] != 'Z')
    return std::nullopt;
  const auto t = std::chrono::sys_days{date} + std::chrono::hours{*h} + std::chrono::minutes{*mi} +
                 std::chrono::seconds{*sec} + fraction;
  return WallTime{std::chrono::duration_cast<WallClock::duration>(t.time_since_epoch())};
}

}  // namespace tb::clock
