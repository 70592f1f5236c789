#pragma once
/// @file The CA and DEN services' checks of a received signed message against its sender's
/// permissions, the service-specific permissions (SSP) of its AT:
/// - CAM (TS 103 900 V2.1.1 clause 6.2.2.2): a version octet (1) and two octets of bits, one per
///   special-vehicle container and for some of their fields. An ordinary car's AT cannot claim
///   an emergency vehicle's right of way.
/// - DENM (TS 103 831 V2.2.1 clause 6.2.2.2): a version octet (1, or 2 with a fourth octet of
///   bits) and a bit per cause code the station may report.
/// A message that carries what its signer's bits do not permit is not passed on.

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "its-station/messages/cam.hpp"
#include "its-station/messages/denm.hpp"

namespace tb::its::facilities {

/// An SSP bit: the octet (after the version octet 0) and its mask.
struct SspBit {
  std::uint8_t octet;
  std::uint8_t mask;
  std::string_view name;
};
namespace cam_ssp {
inline constexpr SspBit kCenDsrcTollingZone{1, 0x80, "cenDsrcTollingZone"};
inline constexpr SspBit kPublicTransport{1, 0x40, "publicTransport"};
inline constexpr SspBit kSpecialTransport{1, 0x20, "specialTransport"};
inline constexpr SspBit kDangerousGoods{1, 0x10, "dangerousGoods"};
inline constexpr SspBit kRoadwork{1, 0x08, "roadwork"};
inline constexpr SspBit kRescue{1, 0x04, "rescue"};
inline constexpr SspBit kEmergency{1, 0x02, "emergency"};
inline constexpr SspBit kSafetyCar{1, 0x01, "safetyCar"};
inline constexpr SspBit kClosedLanes{2, 0x80, "closedLanes"};
inline constexpr SspBit kRequestForRightOfWay{2, 0x40, "requestForRightOfWay"};
inline constexpr SspBit kRequestForFreeCrossing{2, 0x20, "requestForFreeCrossingAtATrafficLight"};
inline constexpr SspBit kNoPassing{2, 0x10, "noPassing"};
inline constexpr SspBit kNoPassingForTrucks{2, 0x08, "noPassingForTrucks"};
inline constexpr SspBit kSpeedLimit{2, 0x04, "speedLimit"};
}  // namespace cam_ssp

/// The first permission @p cam needs that @p ssp (the signer AT's CAM SSP octets; empty: no
/// SSP, so no special permission) lacks; nullopt when the CAM is within it. A CAM without a
/// special-vehicle container needs none.
std::optional<SspBit> cam_not_permitted(const messages::Cam& cam,
                                        std::span<const std::uint8_t> ssp);

/// The DENM SSP bit of cause code @p cause (TS 103 831 6.2.2.2: version 1 bits in octets 1-3,
/// version 2 adds octet 4); none for a cause code no bit permits.
std::optional<SspBit> denm_ssp_bit(messages::CauseCodeType cause);

/// The permission @p denm's situation (its cause code) needs that @p ssp lacks; nullopt when
/// the DENM is within it or reports no situation (a cancellation or negation).
std::optional<SspBit> denm_not_permitted(const messages::Denm& denm,
                                         std::span<const std::uint8_t> ssp);

}  // namespace tb::its::facilities
