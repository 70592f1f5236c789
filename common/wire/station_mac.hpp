#pragma once
/// @file A station's radio MAC address: `02:00` + its StationID big-endian (locally
/// administered, unicast). Every station sends with it, full or pooled; radio-medium tells
/// senders apart by it and station-host gives it to each of its pooled stations, so the rule
/// lives here once.

#include <array>
#include <cstdint>

namespace tb::wire {

constexpr std::array<std::uint8_t, 6> station_mac(std::uint32_t station_id) {
  return {0x02,
          0x00,
          static_cast<std::uint8_t>(station_id >> 24),
          static_cast<std::uint8_t>(station_id >> 16),
          static_cast<std::uint8_t>(station_id >> 8),
          static_cast<std::uint8_t>(station_id)};
}

}  // namespace tb::wire
