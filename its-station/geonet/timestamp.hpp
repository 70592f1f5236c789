#pragma once
/// @file GeoNetworking timestamps (EN 302 636-4-1 V1.4.1 clause 9.5.2).
///
/// TST = TST(TAI) mod 2^32, where TST(TAI) counts TAI milliseconds since 2004-01-01 00:00:00.000
/// UTC. TAI runs on through leap seconds, UTC does not: so TST(TAI) is the UTC milliseconds since
/// that instant plus the leap seconds inserted since (five by 2017-01-01, none since). We count
/// them because the standard says TAI. Other stacks stamp UTC (Vanetza), so a TST is only ever
/// compared with earlier TSTs of the same source, never used to age a packet; docs/time.md
/// lists every time base of the station. The CAM's TimestampIts (CDD V1.3.1, UTC) is not here.

#include <cstdint>

#include "common/clock/clock.hpp"

namespace tb::its::geonet {

using Timestamp = std::uint32_t;

/// Unix time of the ITS epoch, 2004-01-01 00:00:00 UTC.
inline constexpr std::int64_t kItsEpochUnixSeconds = 1'072'915'200;

/// Leap seconds inserted between the ITS epoch and @p t (IERS Bulletin C).
int leap_seconds_since_its_epoch(clock::WallTime t);

/// The GN timestamp of the UTC instant @p t.
Timestamp to_timestamp(clock::WallTime t);

/// a − b in milliseconds, taking the 2^32 wrap into account (result in [−2^31, 2^31)).
inline std::int32_t timestamp_difference(Timestamp a, Timestamp b) {
  return static_cast<std::int32_t>(a - b);
}

/// True if @p a is later than @p b under the wrap rule of clause C.2: a is newer when it is
/// ahead of b by less than half the timestamp range.
inline bool is_newer(Timestamp a, Timestamp b) {
  return timestamp_difference(a, b) > 0;
}

}  // namespace tb::its::geonet
