#include "station-host/feed/epoch_phase.hpp"

namespace tb::host {

namespace {
__extension__ using Wide = unsigned __int128;  // GCC's and Clang's; -Wpedantic wants it marked
}  // namespace

std::chrono::nanoseconds epoch_phase(std::uint32_t station_id, std::chrono::nanoseconds period) {
  // 2^64 / golden ratio: station_id × this mod 2^64 is frac(station_id / φ) as a 64-bit
  // fraction; its product with the period, shifted down, is that fraction of the period.
  constexpr std::uint64_t kInverseGoldenRatio = 0x9E3779B97F4A7C15ULL;
  const std::uint64_t fraction = static_cast<std::uint64_t>(station_id) * kInverseGoldenRatio;
  if (period.count() <= 0)
    return std::chrono::nanoseconds{0};
  const auto scaled =
      (static_cast<Wide>(fraction) * static_cast<std::uint64_t>(period.count())) >> 64;
  return std::chrono::nanoseconds{static_cast<std::int64_t>(scaled)};
}

}  // namespace tb::host
