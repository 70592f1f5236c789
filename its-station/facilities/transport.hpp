#pragma once
/// @file What the services need from the networking layers below them: single-hop broadcast
/// for CAMs, GeoBroadcast for DENMs (EN 302 636-5-1 BTP-B over EN 302 636-4-1 GeoNetworking).
/// The station program implements it over its BTP/GN router; tests over an in-memory medium.

#include <cstdint>
#include <span>
#include <string_view>

namespace tb::its::facilities {

/// BTP-B well-known ports (TS 103 248).
inline constexpr std::uint16_t kBtpPortCam = 2001;
inline constexpr std::uint16_t kBtpPortDenm = 2002;
inline constexpr std::uint16_t kBtpPortMapem = 2003;
inline constexpr std::uint16_t kBtpPortSpatem = 2004;

/// A GeoNetworking destination area (EN 302 636-4-1 clause 9.8.5, EN 302 931).
struct GeoArea {
  enum class Shape : std::uint8_t { kCircle = 0, kRectangle = 1, kEllipse = 2 };
  Shape shape = Shape::kCircle;
  double latitude_deg = 0.0;   ///< centre
  double longitude_deg = 0.0;  ///< centre
  double distance_a_m = 0.0;   ///< radius, or half length along the azimuth
  double distance_b_m = 0.0;   ///< half width (rectangle, ellipse)
  double angle_deg = 0.0;      ///< azimuth of the a axis, clockwise from north
  friend bool operator==(const GeoArea&, const GeoArea&) = default;
};

enum class SendResult { kSent, kNoPosition, kTooLarge, kLinkError };
std::string_view to_string(SendResult r);

class MessageSender {
 public:
  virtual ~MessageSender() = default;
  /// GN single-hop broadcast, BTP-B to @p port.
  virtual SendResult send_single_hop(std::uint16_t port, std::span<const std::uint8_t> payload) = 0;
  /// GN GeoBroadcast to @p area, BTP-B to @p port; @p lifetime_ms bounds forwarding;
  /// @p traffic_class is the GN TC ID (0..63, EN 302 636-4-1 clause 9.7.5).
  virtual SendResult send_geobroadcast(std::uint16_t port, const GeoArea& area,
                                       std::span<const std::uint8_t> payload,
                                       std::uint32_t lifetime_ms, std::uint8_t traffic_class) = 0;
};

}  // namespace tb::its::facilities
