#include "its-station/geonet/timestamp.hpp"

#include <array>
#include <chrono>

namespace tb::its::geonet {

namespace {
// Unix times at which TAI − UTC grew by one second after 2004 (the leap second preceded each).
constexpr std::array<std::int64_t, 5> kLeapSecondEffective = {
    1'136'073'600,  // 2006-01-01
    1'230'768'000,  // 2009-01-01
    1'341'100'800,  // 2012-07-01
    1'435'708'800,  // 2015-07-01
    1'483'228'800,  // 2017-01-01
};
}  // namespace

int leap_seconds_since_its_epoch(clock::WallTime t) {
  const auto unix_s = std::chrono::floor<std::chrono::seconds>(t.time_since_epoch()).count();
  int n = 0;
  for (const auto effective : kLeapSecondEffective) {
    if (unix_s >= effective)
      ++n;
  }
  return n;
}

Timestamp to_timestamp(clock::WallTime t) {
  const std::int64_t unix_ms =
      std::chrono::floor<std::chrono::milliseconds>(t.time_since_epoch()).count();
  const std::int64_t tai_ms =
      unix_ms - kItsEpochUnixSeconds * 1000 + std::int64_t{leap_seconds_since_its_epoch(t)} * 1000;
  // Modulo 2^32 of a possibly negative count (a clock set before 2004) stays well defined.
  return static_cast<Timestamp>(static_cast<std::uint64_t>(tai_ms));
}

}  // namespace tb::its::geonet
