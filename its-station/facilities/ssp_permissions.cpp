#include "its-station/facilities/ssp_permissions.hpp"

#include <variant>

namespace tb::its::facilities {

namespace {

bool has(std::span<const std::uint8_t> ssp, const SspBit& bit) {
  return ssp.size() > bit.octet && (ssp[bit.octet] & bit.mask) != 0;
}

/// What each special-vehicle container and its fields need (TS 103 900 6.2.2.2).
struct Needs {
  std::span<const std::uint8_t> ssp;
  std::optional<SspBit> missing;

  void need(const SspBit& bit) {
    if (!missing && !has(ssp, bit))
      missing = bit;
  }
  void operator()(const messages::PublicTransportContainer&) { need(cam_ssp::kPublicTransport); }
  void operator()(const messages::SpecialTransportContainer&) { need(cam_ssp::kSpecialTransport); }
  void operator()(const messages::DangerousGoodsContainer&) { need(cam_ssp::kDangerousGoods); }
  void operator()(const messages::RoadWorksContainerBasic& c) {
    need(cam_ssp::kRoadwork);
    if (c.closedLanes)
      need(cam_ssp::kClosedLanes);
  }
  void operator()(const messages::RescueContainer&) { need(cam_ssp::kRescue); }
  void operator()(const messages::EmergencyContainer& c) {
    need(cam_ssp::kEmergency);
    // EmergencyPriority: requestForRightOfWay (bit 0), requestForFreeCrossingAtATrafficLight (1).
    if (c.emergencyPriority && (*c.emergencyPriority & 0x01) != 0)
      need(cam_ssp::kRequestForRightOfWay);
    if (c.emergencyPriority && (*c.emergencyPriority & 0x02) != 0)
      need(cam_ssp::kRequestForFreeCrossing);
  }
  void operator()(const messages::SafetyCarContainer& c) {
    need(cam_ssp::kSafetyCar);
    if (c.trafficRule == messages::TrafficRule::noPassing)
      need(cam_ssp::kNoPassing);
    if (c.trafficRule == messages::TrafficRule::noPassingForTrucks)
      need(cam_ssp::kNoPassingForTrucks);
    if (c.speedLimit)
      need(cam_ssp::kSpeedLimit);
  }
};

}  // namespace

std::optional<SspBit> cam_not_permitted(const messages::Cam& cam,
                                        std::span<const std::uint8_t> ssp) {
  const auto& special = cam.cam.camParameters.specialVehicleContainer;
  if (!special)
    return std::nullopt;
  Needs needs{ssp, std::nullopt};
  std::visit(needs, *special);
  return needs.missing;
}

std::optional<SspBit> denm_ssp_bit(messages::CauseCodeType cause) {
  switch (cause) {
    case 1:
      return SspBit{1, 0x80, "trafficCondition"};
    case 2:
      return SspBit{1, 0x40, "accident"};
    case 3:
      return SspBit{1, 0x20, "roadworks"};
    case 6:
      return SspBit{1, 0x10, "adverseWeatherCondition-Adhesion"};
    case 9:
      return SspBit{1, 0x08, "hazardousLocation-SurfaceCondition"};
    case 10:
      return SspBit{1, 0x04, "hazardousLocation-ObstacleOnTheRoad"};
    case 11:
      return SspBit{1, 0x02, "hazardousLocation-AnimalOnTheRoad"};
    case 12:
      return SspBit{1, 0x01, "humanPresenceOnTheRoad"};
    case 14:
      return SspBit{2, 0x80, "wrongWayDriving"};
    case 15:
      return SspBit{2, 0x40, "rescueAndRecoveryWorkInProgress"};
    case 17:
      return SspBit{2, 0x20, "adverseWeatherCondition-ExtremeWeatherCondition"};
    case 18:
      return SspBit{2, 0x10, "adverseWeatherCondition-Visibility"};
    case 19:
      return SspBit{2, 0x08, "adverseWeatherCondition-Precipitation"};
    case 26:
      return SspBit{2, 0x04, "slowVehicle"};
    case 27:
      return SspBit{2, 0x02, "dangerousEndOfQueue"};
    case 91:
      return SspBit{2, 0x01, "vehicleBreakdown"};
    case 92:
      return SspBit{3, 0x80, "postCrash"};
    case 93:
      return SspBit{3, 0x40, "humanProblem"};
    case 94:
      return SspBit{3, 0x20, "stationaryVehicle"};
    case 95:
      return SspBit{3, 0x10, "emergencyVehicleApproaching"};
    case 96:
      return SspBit{3, 0x08, "hazardousLocation-DangerousCurve"};
    case 97:
      return SspBit{3, 0x04, "collisionRisk"};
    case 98:
      return SspBit{3, 0x02, "signalViolation"};
    case 99:
      return SspBit{3, 0x01, "dangerousSituation"};
    // Version 2 only.
    case 5:
      return SspBit{4, 0x80, "impassability"};
    case 7:
      return SspBit{4, 0x40, "aquaplaning"};
    case 28:
      return SspBit{4, 0x20, "publicTransportVehicleApproaching"};
    case 100:
      return SspBit{4, 0x10, "railwayLevelCrossing"};
    default:
      return std::nullopt;
  }
}

std::optional<SspBit> denm_not_permitted(const messages::Denm& denm,
                                         std::span<const std::uint8_t> ssp) {
  if (!denm.denm.situation)
    return std::nullopt;
  const auto cause = denm.denm.situation->eventType.causeCode;
  const auto bit = denm_ssp_bit(cause);
  if (!bit)
    return SspBit{0, 0, "a cause code no SSP bit permits"};
  if (!has(ssp, *bit))
    return bit;
  return std::nullopt;
}

}  // namespace tb::its::facilities
