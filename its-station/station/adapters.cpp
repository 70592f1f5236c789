#include "its-station/station/adapters.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <spdlog/spdlog.h>

#include "its-station/facilities/cdd_convert.hpp"
#include "its-station/facilities/its_time.hpp"
#include "its-station/geonet/area.hpp"

namespace tb::its::station {

std::optional<geonet::EgoPosition> GnPositionAdapter::current_position() const {
  const auto& fix = position_.current();
  if (!fix)
    return std::nullopt;
  geonet::EgoPosition p;
  p.time = fix->time;
  p.latitude_deg = fix->latitude_deg;
  p.longitude_deg = fix->longitude_deg;
  p.speed_mps = fix->speed_mps.value_or(0.0);
  p.heading_deg = fix->heading_deg.value_or(0.0);
  // PAI (EN 302 636-4-1 clause 9.5.2): the 95 % confidence is within itsGnPaiInterval.
  p.accurate = fix->position_confidence && fix->position_confidence->semi_major_m <= kPaiIntervalM;
  return p;
}

facilities::SendResult to_send_result(geonet::DataConfirm c) {
  switch (c) {
    case geonet::DataConfirm::kAccepted:
      return facilities::SendResult::kSent;
    case geonet::DataConfirm::kNoPosition:
      return facilities::SendResult::kNoPosition;
    case geonet::DataConfirm::kMaxSduSizeExceeded:
      return facilities::SendResult::kTooLarge;
    default:
      spdlog::debug("GN-DATA.confirm: {}", geonet::to_string(c));
      return facilities::SendResult::kLinkError;
  }
}

facilities::SendResult BtpMessageSender::send_single_hop(std::uint16_t port,
                                                         std::span<const std::uint8_t> payload) {
  return to_send_result(btp_.send_b(geonet::DataRequest::single_hop(kCamTrafficClass, kCamLifetime),
                                    port, 0, payload));
}

facilities::SendResult BtpMessageSender::send_geobroadcast(std::uint16_t port,
                                                           const facilities::GeoArea& area,
                                                           std::span<const std::uint8_t> payload,
                                                           std::uint32_t lifetime_ms,
                                                           std::uint8_t traffic_class) {
  geonet::AreaShape shape = geonet::AreaShape::kCircle;
  if (area.shape == facilities::GeoArea::Shape::kRectangle)
    shape = geonet::AreaShape::kRectangle;
  else if (area.shape == facilities::GeoArea::Shape::kEllipse)
    shape = geonet::AreaShape::kEllipse;
  auto r = geonet::DataRequest::geo_broadcast(
      geonet::make_geo_area(shape, {area.latitude_deg, area.longitude_deg}, area.distance_a_m,
                            area.distance_b_m, area.angle_deg));
  r.lifetime = std::chrono::milliseconds{lifetime_ms};
  r.traffic_class = geonet::TrafficClass{false, false, traffic_class};
  return to_send_result(btp_.send_b(r, port, 0, payload));
}

facilities::DenmReception den_reception(const btp::Indication& ind) {
  facilities::DenmReception rx;
  if (ind.gn == nullptr)
    return rx;
  rx.traffic_class = ind.gn->traffic_class.id;
  // A permissive station's unverified DENMs have nothing trustworthy to check against.
  if (ind.gn->security_report == security::VerifyResult::kOk)
    rx.ssp = ind.gn->permissions;
  if (const auto& a = ind.gn->destination_area) {
    facilities::GeoArea area;
    area.shape = a->shape == geonet::AreaShape::kRectangle ? facilities::GeoArea::Shape::kRectangle
                 : a->shape == geonet::AreaShape::kEllipse ? facilities::GeoArea::Shape::kEllipse
                                                           : facilities::GeoArea::Shape::kCircle;
    area.latitude_deg = geonet::to_degrees(a->latitude);
    area.longitude_deg = geonet::to_degrees(a->longitude);
    area.distance_a_m = a->distance_a;
    area.distance_b_m = a->distance_b;
    area.angle_deg = a->angle;
    rx.destination_area = area;
  }
  return rx;
}

bool GnAreaLocator::inside(const facilities::GeoArea& area) const {
  const auto& fix = position_.current();
  if (!fix)
    return true;
  geonet::AreaShape shape = geonet::AreaShape::kCircle;
  if (area.shape == facilities::GeoArea::Shape::kRectangle)
    shape = geonet::AreaShape::kRectangle;
  else if (area.shape == facilities::GeoArea::Shape::kEllipse)
    shape = geonet::AreaShape::kEllipse;
  return geonet::is_inside_or_at_border(
      geonet::make_geo_area(shape, {area.latitude_deg, area.longitude_deg}, area.distance_a_m,
                            area.distance_b_m, area.angle_deg),
      {fix->latitude_deg, fix->longitude_deg});
}

facilities::DenRequest DenPortAdapter::to_request(const apps::DenEventRequest& r) const {
  facilities::DenRequest q;
  q.event_type = {r.cause_code, r.sub_cause_code};
  q.information_quality = r.information_quality;
  q.event_latitude_deg = r.event_position.latitude_deg;
  q.event_longitude_deg = r.event_position.longitude_deg;
  q.event_altitude_m = r.event_position.altitude_m;
  if (r.detection_time != clock::WallTime{})
    q.detection_time = r.detection_time;
  q.relevance_distance = static_cast<messages::RelevanceDistance>(r.relevance_distance);
  q.relevance_traffic_direction =
      static_cast<messages::RelevanceTrafficDirection>(r.relevance_traffic_direction);
  q.validity_s = static_cast<messages::ValidityDuration>(
      std::clamp<std::int64_t>(r.validity_duration.count(), 0, 86400));
  q.repetition_interval = interval_;
  q.repetition_duration = std::min<clock::Duration>(duration_, r.validity_duration);
  q.traffic_class = r.traffic_class;
  const double radius = facilities::cdd::relevance_radius_m(
      static_cast<messages::RelevanceDistance>(r.relevance_distance));
  q.destination_area = {facilities::GeoArea::Shape::kCircle,
                        q.event_latitude_deg,
                        q.event_longitude_deg,
                        radius,
                        radius,
                        0.0};
  if (r.event_heading_deg) {
    messages::LocationContainer loc;
    loc.eventPositionHeading = facilities::cdd::heading(r.event_heading_deg, std::nullopt);
    loc.traces.emplace_back();  // SIZE(1..7): one (empty) trace
    q.location = loc;
  }
  return q;
}

std::optional<apps::ActionId> DenPortAdapter::trigger(const apps::DenEventRequest& request) {
  auto id = den_.trigger(to_request(request));
  if (!id) {
    spdlog::warn("DEN port: trigger refused: {}", facilities::to_string(id.error()));
    return std::nullopt;
  }
  return apps::ActionId{id->originatingStationID, id->sequenceNumber};
}

bool DenPortAdapter::update(const apps::ActionId& id, const apps::DenEventRequest& request) {
  auto r = den_.update({id.originating_station_id, id.sequence_number}, to_request(request));
  return r.has_value();
}

bool DenPortAdapter::terminate(const apps::ActionId& id) {
  return den_.terminate({id.originating_station_id, id.sequence_number}).has_value();
}

apps::mqtt::Kinematics own_kinematics(const facilities::PositionFix& fix,
                                      const facilities::VehicleData* vehicle,
                                      std::optional<double> length_m,
                                      std::optional<double> width_m) {
  apps::mqtt::Kinematics k;
  k.latitude_deg = fix.latitude_deg;
  k.longitude_deg = fix.longitude_deg;
  k.altitude_m = fix.altitude_m;
  k.heading_deg = fix.heading_deg;
  k.speed_mps = fix.speed_mps;
  if (fix.backward)
    k.reversing = *fix.backward;
  if (vehicle) {
    if (!fix.backward)
      k.reversing = vehicle->reversing.value_or(false);
    k.longitudinal_accel_mps2 = vehicle->longitudinal_acceleration_mps2;
    k.yaw_rate_dps = vehicle->yaw_rate_dps;
  }
  k.length_m = length_m;
  k.width_m = width_m;
  return k;
}

apps::mqtt::Kinematics neighbour_kinematics(const facilities::Neighbour& n) {
  apps::mqtt::Kinematics k;
  const auto& s = n.latest();
  k.latitude_deg = s.latitude_deg;
  k.longitude_deg = s.longitude_deg;
  if (!n.last_cam)
    return k;  // not from the LDM, which keeps every neighbour's CAM
  const auto& p = n.last_cam->cam.camParameters;
  if (p.basicContainer.referencePosition.altitude.altitudeValue !=
      messages::kAltitudeValueUnavailable)
    k.altitude_m = p.basicContainer.referencePosition.altitude.altitudeValue / 100.0;
  k.heading_deg = s.heading_deg;
  if (s.speed_mps)
    k.speed_mps = std::abs(*s.speed_mps);
  const auto* vhf = messages::vehicle_hf(p);
  if (vhf == nullptr)
    return k;  // a road-side unit: a position, nothing of a vehicle's motion
  const auto& hf = *vhf;
  k.reversing = hf.driveDirection == messages::DriveDirection::backward;
  if (hf.longitudinalAcceleration.longitudinalAccelerationValue !=
      messages::kAccelerationValueUnavailable)
    k.longitudinal_accel_mps2 = hf.longitudinalAcceleration.longitudinalAccelerationValue / 10.0;
  if (hf.yawRate.yawRateValue != messages::kYawRateValueUnavailable)
    k.yaw_rate_dps = hf.yawRate.yawRateValue / 100.0;
  // CDD CurvatureValue: 1/10000 m⁻¹ with ±1023 out of range / unavailable; protocolVersion 1
  // 1/30000 m⁻¹ with 30001 unavailable.
  const bool v1 = n.last_cam->header.protocolVersion == messages::kProtocolVersion1;
  const int c = hf.curvature.curvatureValue;
  if (v1 ? c != messages::kCurvatureValueUnavailableV1 && std::abs(c) < 30000
         : std::abs(c) < messages::kCurvatureValueUnavailable)
    k.curvature_per_m = c / (v1 ? 30000.0 : 10000.0);
  if (hf.vehicleLength.vehicleLengthValue < messages::kVehicleLengthValueOutOfRange)
    k.length_m = hf.vehicleLength.vehicleLengthValue / 10.0;
  if (hf.vehicleWidth < messages::kVehicleWidthOutOfRange)
    k.width_m = hf.vehicleWidth / 10.0;
  return k;
}

apps::mqtt::DenmView denm_view(const messages::Denm& d) {
  apps::mqtt::DenmView v;
  const auto& mc = d.denm.management;
  v.action_id = {mc.actionID.originatingStationID, mc.actionID.sequenceNumber};
  if (d.denm.situation) {
    v.cause_code = d.denm.situation->eventType.causeCode;
    v.sub_cause_code = d.denm.situation->eventType.subCauseCode;
  }
  v.event_latitude_deg = facilities::cdd::latitude_deg(mc.eventPosition.latitude).value_or(0.0);
  v.event_longitude_deg = facilities::cdd::longitude_deg(mc.eventPosition.longitude).value_or(0.0);
  auto wall = [](messages::TimestampIts its) {
    return clock::WallTime{
        std::chrono::milliseconds{static_cast<std::int64_t>(its) + facilities::kItsEpochUnixMs}};
  };
  v.detection_time = wall(mc.detectionTime);
  v.reference_time = wall(mc.referenceTime);
  if (mc.termination)
    v.termination = static_cast<int>(*mc.termination);
  if (mc.relevanceDistance)
    v.relevance_distance = static_cast<apps::RelevanceDistance>(*mc.relevanceDistance);
  if (mc.relevanceTrafficDirection)
    v.relevance_traffic_direction =
        static_cast<apps::RelevanceTrafficDirection>(*mc.relevanceTrafficDirection);
  v.validity_duration_s = mc.validityDuration;
  return v;
}

apps::VehicleKinematics lcrw_kinematics(std::uint32_t station_id, const apps::mqtt::Kinematics& k,
                                        clock::WallTime time, const geodesy::LocalFrame& frame) {
  apps::VehicleKinematics v;
  v.station_id = station_id;
  v.heading_deg = k.heading_deg.value_or(0.0);
  v.speed_mps = k.speed_mps.value_or(0.0);
  v.reversing = k.reversing;
  v.longitudinal_accel_mps2 = k.longitudinal_accel_mps2;
  v.yaw_rate_dps = k.yaw_rate_dps;
  v.curvature_per_m = k.curvature_per_m;
  if (k.length_m)
    v.length_m = *k.length_m;
  if (k.width_m)
    v.width_m = *k.width_m;
  v.time = time;
  v = apps::with_geodetic_position(v, frame, k.latitude_deg, k.longitude_deg);
  return apps::centre_from_front_reference(v);
}

}  // namespace tb::its::station
