#pragma once
/// @file What the medium's trace may say about a frame on the air without decoding it: the
/// station and generation time of the CAM it carries, the identity DESIGN.md's tracing follows
/// (a CAM names its sender and its generationDeltaTime). Read at the fixed offsets of a
/// GeoNetworking single-hop broadcast with BTP-B to port 2001, unsecured or as the unsecured
/// payload of a TS 103 097 signed packet (whose head has one variable part, the payload's
/// length); anything else, or too short, is no CAM. Frames come from the stations, so every
/// read is bounds-checked.

#include <cstdint>
#include <optional>
#include <span>

namespace tb::emu::radio {

/// GeoNetworking's ethertype (EN 302 636-4-1, IEEE registration).
inline constexpr std::uint16_t kEthertypeGeoNetworking = 0x8947;

struct CamTag {
  std::uint32_t station_id = 0;
  std::uint16_t generation_delta_time = 0;
  bool operator==(const CamTag&) const = default;
};

/// How the link layer frames the GeoNetworking packet.
enum class LinkFraming {
  kEthernet,   ///< Ethernet II, ethertype 0x8947 (the veth stand-in's wlan0)
  kIeee80211,  ///< an 802.11 data frame with LLC/SNAP, ethertype 0x8947 (hwsim)
};

std::optional<CamTag> peek_cam(std::span<const std::uint8_t> frame, LinkFraming framing);

}  // namespace tb::emu::radio
