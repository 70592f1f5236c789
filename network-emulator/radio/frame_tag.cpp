#include "network-emulator/radio/frame_tag.hpp"

#include <cstddef>

namespace tb::emu::radio {
namespace {

// EN 302 636-4-1 9.6/9.7/9.8.4: Basic (4) and Common (8) header, SHB extended header: the
// sender's long position vector (24) and 4 bytes of media-dependent data.
constexpr std::size_t kBasicHeader = 4, kCommonHeader = 8, kShbHeader = 28;
constexpr unsigned kNextHeaderCommon = 1;  // Basic header NH
constexpr unsigned kNextHeaderSecured = 2;
constexpr unsigned kNextHeaderBtpB = 2;  // Common header NH
constexpr unsigned kHeaderTypeTsb = 5, kSubtypeSingleHop = 0;
constexpr std::size_t kBtpHeader = 4;        // EN 302 636-5-1 7.3: destination port, port info
constexpr std::uint16_t kBtpPortCam = 2001;  // TS 103 248
// CAM in UPER (EN 302 637-2 B, CDD ItsPduHeader): protocolVersion (8 bits), messageID (8),
// stationID (32), then generationDeltaTime (16); no preamble bits before them.
constexpr std::uint8_t kMessageIdCam = 2;
constexpr std::size_t kCamIdentityBytes = 8;

std::uint16_t be16(std::span<const std::uint8_t> b, std::size_t at) {
  return static_cast<std::uint16_t>((b[at] << 8) | b[at + 1]);
}

/// Where the GeoNetworking packet starts, or nullopt when this is no GN frame.
std::optional<std::size_t> gn_offset(std::span<const std::uint8_t> f, LinkFraming framing) {
  if (framing == LinkFraming::kEthernet) {
    if (f.size() < 14 || be16(f, 12) != kEthertypeGeoNetworking)
      return std::nullopt;
    return 14;
  }
  // IEEE 802.11-2020 9.2.4.1: frame control, then 24 bytes of header; 30 with four addresses;
  // 2 more with QoS control, and 4 more HT control in a QoS frame with the +HTC/Order bit.
  if (f.size() < 2)
    return std::nullopt;
  const unsigned type = (f[0] >> 2) & 0x3, subtype = f[0] >> 4;
  const bool to_ds = f[1] & 0x01, from_ds = f[1] & 0x02, protected_frame = f[1] & 0x40;
  if (type != 2 || protected_frame || (subtype & 0x4))  // not data, or encrypted, or no payload
    return std::nullopt;
  const bool qos = subtype & 0x8;
  std::size_t at = 24 + (to_ds && from_ds ? 6 : 0) + (qos ? 2 : 0) + (qos && (f[1] & 0x80) ? 4 : 0);
  // IEEE 802.2 LLC/SNAP: AA AA 03, OUI 00 00 00, then the ethertype.
  static constexpr std::uint8_t kSnap[] = {0xAA, 0xAA, 0x03, 0x00, 0x00, 0x00};
  if (f.size() < at + 8)
    return std::nullopt;
  for (std::size_t i = 0; i < sizeof kSnap; ++i)
    if (f[at + i] != kSnap[i])
      return std::nullopt;
  if (be16(f, at + 6) != kEthertypeGeoNetworking)
    return std::nullopt;
  return at + 8;
}

/// Where the signed payload (common header onwards) of the secured packet at @p at starts
/// (TS 103 097 / IEEE 1609.2 in COER): Ieee1609Dot2Data {protocolVersion 3, content signedData
/// (tag 0x81)}, SignedData {hashId, tbsData {payload {data present, nothing else: preamble
/// 0x40}: Ieee1609Dot2Data {3, unsecuredData (tag 0x80), OCTET STRING length, octets}}}.
std::optional<std::size_t> signed_payload(std::span<const std::uint8_t> f, std::size_t at) {
  if (f.size() < at + 7 || f[at] != 3 || f[at + 1] != 0x81 || f[at + 3] != 0x40 || f[at + 4] != 3 ||
      f[at + 5] != 0x80)
    return std::nullopt;
  const std::uint8_t first = f[at + 6];
  if (first < 0x80)
    return at + 7;                          // the length in one octet
  const std::size_t octets = first & 0x7F;  // X.696 8.6.5: the length's own length
  if (octets == 0 || octets > 2)
    return std::nullopt;  // a GN payload is shorter than 64 KiB
  return at + 7 + octets;
}

}  // namespace

std::optional<CamTag> peek_cam(std::span<const std::uint8_t> frame, LinkFraming framing) {
  const auto gn = gn_offset(frame, framing);
  if (!gn)
    return std::nullopt;
  if (frame.size() <= *gn)
    return std::nullopt;
  std::size_t common = *gn + kBasicHeader;
  if ((frame[*gn] & 0x0F) == kNextHeaderSecured) {
    const auto inner = signed_payload(frame, common);
    if (!inner)
      return std::nullopt;
    common = *inner;
  } else if ((frame[*gn] & 0x0F) != kNextHeaderCommon) {
    return std::nullopt;
  }
  const std::size_t btp = common + kCommonHeader + kShbHeader, cam = btp + kBtpHeader;
  if (frame.size() < cam + kCamIdentityBytes)
    return std::nullopt;
  if ((frame[common] >> 4) != kNextHeaderBtpB || (frame[common + 1] >> 4) != kHeaderTypeTsb ||
      (frame[common + 1] & 0x0F) != kSubtypeSingleHop || be16(frame, btp) != kBtpPortCam ||
      frame[cam + 1] != kMessageIdCam)
    return std::nullopt;
  CamTag t;
  t.station_id = (std::uint32_t{frame[cam + 2]} << 24) | (std::uint32_t{frame[cam + 3]} << 16) |
                 (std::uint32_t{frame[cam + 4]} << 8) | frame[cam + 5];
  t.generation_delta_time = be16(frame, cam + 6);
  return t;
}

}  // namespace tb::emu::radio
