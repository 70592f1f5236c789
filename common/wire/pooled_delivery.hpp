#pragma once
/// @file Pooled delivery (TBPD): how the radio medium hands one frame from the air to the
/// stations of a station-host that the channel lets receive it (issue 33; the contract in
/// shared DESIGN.md). One Ethernet frame per (frame, host, due time) instead of one per station:
///
///   Ethernet dst ff:ff:ff:ff:ff:ff | src = the original source MAC | ethertype 0x88B5
///   payload: "TBPD" | version u8 = 1 | reserved u8 = 0 | count u16 BE
///            | count × StationID u32 BE | the original Ethernet frame unchanged (14-byte
///            header + GN packet)
///
/// 0x88B5 is IEEE Std 802 "local experimental ethertype 1" (IEEE 802a-2003): private to the
/// link between the medium and its hosts, never on the air.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "common/util/expected.hpp"

namespace tb::wire {

inline constexpr std::uint16_t kEthertypePooledDelivery = 0x88B5;
inline constexpr std::array<std::uint8_t, 4> kPooledDeliveryMagic = {'T', 'B', 'P', 'D'};
inline constexpr std::uint8_t kPooledDeliveryVersion = 1;
/// Magic, version, reserved, count.
inline constexpr std::size_t kPooledDeliveryHeadSize = 8;
inline constexpr std::size_t kEthernetHeaderSize = 14;
/// The u16 count's limit; a link's MTU usually binds first.
inline constexpr std::size_t kMaxPooledReceivers = 0xFFFF;

/// Payload bytes for @p receivers ids around an inner frame of @p inner_frame_size bytes.
constexpr std::size_t pooled_delivery_size(std::size_t receivers, std::size_t inner_frame_size) {
  return kPooledDeliveryHeadSize + 4 * receivers + inner_frame_size;
}
/// The whole outer Ethernet frame.
constexpr std::size_t pooled_delivery_frame_size(std::size_t receivers,
                                                 std::size_t inner_frame_size) {
  return kEthernetHeaderSize + pooled_delivery_size(receivers, inner_frame_size);
}
/// How many receivers fit in an outer frame whose payload may be @p mtu bytes (0 if none).
constexpr std::size_t pooled_receivers_per_frame(std::size_t mtu, std::size_t inner_frame_size) {
  const std::size_t fixed = kPooledDeliveryHeadSize + inner_frame_size;
  if (mtu < fixed + 4)
    return 0;
  const std::size_t n = (mtu - fixed) / 4;
  return n > kMaxPooledReceivers ? kMaxPooledReceivers : n;
}

enum class PooledDeliveryError {
  kTooShort,            ///< fewer bytes than the head
  kBadMagic,            ///< not "TBPD"
  kUnsupportedVersion,  ///< a version other than kPooledDeliveryVersion
  kNoReceivers,         ///< count 0: the medium never sends a frame nobody receives
  kTruncatedReceivers,  ///< count ids do not fit in the bytes
  kInnerFrameTooShort,  ///< the inner frame has no complete Ethernet header
  kNotPooledDelivery,   ///< (outer frame) shorter than a header, or another ethertype
};
inline constexpr std::size_t kPooledDeliveryErrorCount = 7;
std::string_view to_string(PooledDeliveryError e);

/// A parsed TBPD payload: views into the bytes it was parsed from (no copy, no allocation).
struct PooledDelivery {
  std::span<const std::uint8_t> receiver_bytes;  ///< count × u32 BE
  std::span<const std::uint8_t> inner_frame;     ///< Ethernet header + payload

  std::size_t receiver_count() const { return receiver_bytes.size() / 4; }
  std::uint32_t receiver(std::size_t i) const {
    const auto* p = receiver_bytes.data() + 4 * i;
    return std::uint32_t{p[0]} << 24 | std::uint32_t{p[1]} << 16 | std::uint32_t{p[2]} << 8 |
           std::uint32_t{p[3]};
  }
  std::vector<std::uint32_t> receivers() const;
  /// The inner frame's source MAC (the sending station's).
  std::span<const std::uint8_t, 6> source_mac() const { return inner_frame.subspan<6, 6>(); }
};

/// Writes the TBPD payload (no outer Ethernet header) into @p out, which must hold
/// pooled_delivery_size(); returns the bytes written, or 0 when @p receivers is empty or longer
/// than kMaxPooledReceivers, @p inner_frame is shorter than an Ethernet header, or @p out is
/// too small. Receivers are written in the given order; the parser keeps duplicates (the
/// medium writes none).
std::size_t build_pooled_delivery(std::span<const std::uint32_t> receivers,
                                  std::span<const std::uint8_t> inner_frame,
                                  std::span<std::uint8_t> out);
/// Writes the whole outer frame (broadcast destination, the inner frame's source MAC,
/// ethertype 0x88B5, then the payload) into @p out; same refusals, returns 0 or the size.
std::size_t build_pooled_delivery_frame(std::span<const std::uint32_t> receivers,
                                        std::span<const std::uint8_t> inner_frame,
                                        std::span<std::uint8_t> out);
std::vector<std::uint8_t> build_pooled_delivery_frame(std::span<const std::uint32_t> receivers,
                                                      std::span<const std::uint8_t> inner_frame);

/// Parses a TBPD payload. Never reads outside @p payload. The reserved byte is ignored (a
/// later sender may use it without breaking this version's receivers).
Expected<PooledDelivery, PooledDeliveryError> parse_pooled_delivery(
    std::span<const std::uint8_t> payload);
/// Parses a whole outer Ethernet frame: ethertype 0x88B5, then the payload as above.
Expected<PooledDelivery, PooledDeliveryError> parse_pooled_delivery_frame(
    std::span<const std::uint8_t> frame);

}  // namespace tb::wire
