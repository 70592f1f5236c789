#include "its-station/messages/cam.hpp"

#include "its-station/messages/cdd_codec.hpp"
#include "its-station/messages/message_codec.hpp"

namespace tb::its::messages {

using asn1::Error;
using asn1::UperReader;
using asn1::UperWriter;
using namespace detail;

namespace {

// Overloads for the shared CDD types join the ones below (a using-directive would be hidden).
using detail::get;
using detail::put;

void put_header(UperWriter& w, const ItsPduHeader& h) {
  w.put_bits(h.protocolVersion, 8);
  w.put_bits(h.messageID, 8);
  w.put_bits(h.stationID, 32);
}

/// ItsPduHeader, checked before anything else so that a DENM handed to the CAM decoder (or a
/// future protocol version) is named as such rather than as a field error further in.
bool get_header(UperReader& r, ItsPduHeader& h, std::uint8_t expected_id) {
  h.protocolVersion = static_cast<std::uint8_t>(r.get_bits(8, "protocolVersion"));
  h.messageID = static_cast<std::uint8_t>(r.get_bits(8, "messageID"));
  h.stationID = static_cast<StationID>(r.get_bits(32, "stationID"));
  if (!r.ok())
    return false;
  if (h.messageID != expected_id) {
    r.fail_at(Error::kWrongMessageId, "messageID", h.messageID, 8);
    return false;
  }
  if (h.protocolVersion != kProtocolVersion && h.protocolVersion != kProtocolVersion1) {
    r.fail_at(Error::kUnsupportedVersion, "protocolVersion", h.protocolVersion, 0);
    return false;
  }
  return true;
}

// BasicVehicleContainerHighFrequency: no extension marker, seven OPTIONAL components.
void put(UperWriter& w, const BasicVehicleContainerHighFrequency& hf, bool v1) {
  const std::uint64_t present = (std::uint64_t{hf.accelerationControl.has_value()} << 6) |
                                (std::uint64_t{hf.lanePosition.has_value()} << 5) |
                                (std::uint64_t{hf.steeringWheelAngle.has_value()} << 4) |
                                (std::uint64_t{hf.lateralAcceleration.has_value()} << 3) |
                                (std::uint64_t{hf.verticalAcceleration.has_value()} << 2) |
                                (std::uint64_t{hf.performanceClass.has_value()} << 1) |
                                std::uint64_t{hf.cenDsrcTollingZone.has_value()};
  w.put_bits(present, 7);
  put(w, hf.heading);
  put(w, hf.speed);
  put_enum(w, hf.driveDirection, 3, false, "driveDirection");
  w.put_constrained<1, 1023>(hf.vehicleLength.vehicleLengthValue, "vehicleLengthValue");
  put_enum(w, hf.vehicleLength.vehicleLengthConfidenceIndication, 5, false,
           "vehicleLengthConfidenceIndication");
  w.put_constrained<1, 62>(hf.vehicleWidth, "vehicleWidth");
  put_acceleration(w, hf.longitudinalAcceleration.longitudinalAccelerationValue,
                   hf.longitudinalAcceleration.longitudinalAccelerationConfidence,
                   "longitudinalAccelerationValue", "longitudinalAccelerationConfidence");
  // CurvatureValue: (-1023..1023) in CDD version 2, (-30000..30001) in version 1.
  if (v1)
    w.put_constrained<-30000, 30001>(hf.curvature.curvatureValue, "curvatureValue");
  else
    w.put_constrained<-1023, 1023>(hf.curvature.curvatureValue, "curvatureValue");
  put_enum(w, hf.curvature.curvatureConfidence, 8, false, "curvatureConfidence");
  put_enum(w, hf.curvatureCalculationMode, 3, true, "curvatureCalculationMode");
  w.put_constrained<-32766, 32767>(hf.yawRate.yawRateValue, "yawRateValue");
  put_enum(w, hf.yawRate.yawRateConfidence, 9, false, "yawRateConfidence");
  if (hf.accelerationControl)
    put_named_bits(w, *hf.accelerationControl, 7, "accelerationControl");
  if (hf.lanePosition)
    w.put_constrained<-1, 14>(*hf.lanePosition, "lanePosition");
  if (hf.steeringWheelAngle) {
    w.put_constrained<-511, 512>(hf.steeringWheelAngle->steeringWheelAngleValue,
                                 "steeringWheelAngleValue");
    w.put_constrained<1, 127>(hf.steeringWheelAngle->steeringWheelAngleConfidence,
                              "steeringWheelAngleConfidence");
  }
  if (hf.lateralAcceleration)
    put_acceleration(w, hf.lateralAcceleration->lateralAccelerationValue,
                     hf.lateralAcceleration->lateralAccelerationConfidence,
                     "lateralAccelerationValue", "lateralAccelerationConfidence");
  if (hf.verticalAcceleration)
    put_acceleration(w, hf.verticalAcceleration->verticalAccelerationValue,
                     hf.verticalAcceleration->verticalAccelerationConfidence,
                     "verticalAccelerationValue", "verticalAccelerationConfidence");
  if (hf.performanceClass)
    w.put_constrained<0, 7>(*hf.performanceClass, "performanceClass");
  if (hf.cenDsrcTollingZone) {
    // CenDsrcTollingZone ::= SEQUENCE {lat, lon, cenDsrcTollingZoneID OPTIONAL, ...}; no
    // extension marker in CDD version 1.
    const CenDsrcTollingZone& z = *hf.cenDsrcTollingZone;
    if (!v1)
      w.put_bool(false);
    w.put_bool(z.cenDsrcTollingZoneID.has_value());
    w.put_constrained<-900000000, 900000001>(z.protectedZoneLatitude, "protectedZoneLatitude");
    w.put_constrained<-1800000000, 1800000001>(z.protectedZoneLongitude, "protectedZoneLongitude");
    if (z.cenDsrcTollingZoneID)
      w.put_constrained<0, 134217727>(*z.cenDsrcTollingZoneID, "cenDsrcTollingZoneID");
  }
}

void get(UperReader& r, BasicVehicleContainerHighFrequency& hf, bool v1) {
  const auto present = r.get_bits(7, "basicVehicleContainerHighFrequency");
  get(r, hf.heading);
  get(r, hf.speed);
  hf.driveDirection = get_enum<DriveDirection>(r, 3, false, "driveDirection");
  hf.vehicleLength.vehicleLengthValue =
      static_cast<VehicleLengthValue>(r.get_constrained<1, 1023>("vehicleLengthValue"));
  hf.vehicleLength.vehicleLengthConfidenceIndication =
      get_enum<VehicleLengthConfidenceIndication>(r, 5, false, "vehicleLengthConfidenceIndication");
  hf.vehicleWidth = static_cast<VehicleWidth>(r.get_constrained<1, 62>("vehicleWidth"));
  get_acceleration(r, hf.longitudinalAcceleration.longitudinalAccelerationValue,
                   hf.longitudinalAcceleration.longitudinalAccelerationConfidence,
                   "longitudinalAccelerationValue", "longitudinalAccelerationConfidence");
  hf.curvature.curvatureValue =
      static_cast<CurvatureValue>(v1 ? r.get_constrained<-30000, 30001>("curvatureValue")
                                     : r.get_constrained<-1023, 1023>("curvatureValue"));
  hf.curvature.curvatureConfidence =
      static_cast<CurvatureConfidence>(r.get_bits(3, "curvatureConfidence"));
  hf.curvatureCalculationMode =
      get_enum<CurvatureCalculationMode>(r, 3, true, "curvatureCalculationMode");
  hf.yawRate.yawRateValue =
      static_cast<YawRateValue>(r.get_constrained<-32766, 32767>("yawRateValue"));
  hf.yawRate.yawRateConfidence = get_enum<YawRateConfidence>(r, 9, false, "yawRateConfidence");
  hf.accelerationControl.reset();
  hf.lanePosition.reset();
  hf.steeringWheelAngle.reset();
  hf.lateralAcceleration.reset();
  hf.verticalAcceleration.reset();
  hf.performanceClass.reset();
  hf.cenDsrcTollingZone.reset();
  if (present & 0x40)
    hf.accelerationControl =
        static_cast<AccelerationControl>(get_named_bits(r, 7, "accelerationControl"));
  if (present & 0x20)
    hf.lanePosition = static_cast<LanePosition>(r.get_constrained<-1, 14>("lanePosition"));
  if (present & 0x10) {
    SteeringWheelAngle& s = hf.steeringWheelAngle.emplace();
    s.steeringWheelAngleValue = static_cast<SteeringWheelAngleValue>(
        r.get_constrained<-511, 512>("steeringWheelAngleValue"));
    s.steeringWheelAngleConfidence = static_cast<SteeringWheelAngleConfidence>(
        r.get_constrained<1, 127>("steeringWheelAngleConfidence"));
  }
  if (present & 0x08) {
    LateralAcceleration& a = hf.lateralAcceleration.emplace();
    get_acceleration(r, a.lateralAccelerationValue, a.lateralAccelerationConfidence,
                     "lateralAccelerationValue", "lateralAccelerationConfidence");
  }
  if (present & 0x04) {
    VerticalAcceleration& a = hf.verticalAcceleration.emplace();
    get_acceleration(r, a.verticalAccelerationValue, a.verticalAccelerationConfidence,
                     "verticalAccelerationValue", "verticalAccelerationConfidence");
  }
  if (present & 0x02)
    hf.performanceClass = static_cast<PerformanceClass>(r.get_bits(3, "performanceClass"));
  if (present & 0x01) {
    CenDsrcTollingZone& z = hf.cenDsrcTollingZone.emplace();
    const bool ext = !v1 && r.get_bool("cenDsrcTollingZone");
    const bool has_id = r.get_bool("cenDsrcTollingZone");
    z.protectedZoneLatitude =
        static_cast<Latitude>(r.get_constrained<-900000000, 900000001>("protectedZoneLatitude"));
    z.protectedZoneLongitude = static_cast<Longitude>(
        r.get_constrained<-1800000000, 1800000001>("protectedZoneLongitude"));
    if (has_id)
      z.cenDsrcTollingZoneID =
          static_cast<ProtectedZoneID>(r.get_constrained<0, 134217727>("cenDsrcTollingZoneID"));
    if (ext)
      r.skip_sequence_extensions("cenDsrcTollingZone");
  }
}

// RSUContainerHighFrequency ::= SEQUENCE {protectedCommunicationZonesRSU OPTIONAL, ...}; each
// ProtectedCommunicationZone has an extension marker in CDD version 2 only.
void put(UperWriter& w, const ProtectedCommunicationZone& z, bool v1) {
  if (!v1)
    w.put_bool(false);
  w.put_bool(z.expiryTime.has_value());
  w.put_bool(z.protectedZoneRadius.has_value());
  w.put_bool(z.protectedZoneID.has_value());
  // ProtectedZoneType: one root value (no index bits) behind the extension bit; version 2's
  // temporaryCenDsrcTolling is extension addition 0, a normally small number (X.691 14.3).
  if (z.protectedZoneType == ProtectedZoneType::permanentCenDsrcTolling) {
    w.put_bool(false);
  } else if (z.protectedZoneType == ProtectedZoneType::temporaryCenDsrcTolling && !v1) {
    w.put_bool(true);
    w.put_normally_small(0);
  } else {
    w.fail(Error::kValueOutOfRange, "protectedZoneType",
           static_cast<std::int64_t>(z.protectedZoneType));
    return;
  }
  if (z.expiryTime)
    w.put_constrained<0, 4398046511103>(static_cast<std::int64_t>(*z.expiryTime), "expiryTime");
  w.put_constrained<-900000000, 900000001>(z.protectedZoneLatitude, "protectedZoneLatitude");
  w.put_constrained<-1800000000, 1800000001>(z.protectedZoneLongitude, "protectedZoneLongitude");
  if (z.protectedZoneRadius) {  // (1..255, ...): root values only, 0 is out of range here
    w.put_bool(false);
    w.put_constrained<1, 255>(*z.protectedZoneRadius, "protectedZoneRadius");
  }
  if (z.protectedZoneID)
    w.put_constrained<0, 134217727>(*z.protectedZoneID, "protectedZoneID");
}

void get(UperReader& r, ProtectedCommunicationZone& z, bool v1) {
  z = ProtectedCommunicationZone{};
  const bool ext = !v1 && r.get_bool("protectedCommunicationZone");
  const auto present = r.get_bits(3, "protectedCommunicationZone");
  const std::size_t type_at = r.bit_position();
  if (r.get_bool("protectedZoneType")) {
    const auto index = r.get_normally_small("protectedZoneType");
    if (!r.ok())
      return;
    if (v1 || index != 0) {  // version 1 knows no extension value
      r.fail_at(Error::kUnknownExtension, "protectedZoneType", static_cast<std::int64_t>(index),
                type_at);
      return;
    }
    z.protectedZoneType = ProtectedZoneType::temporaryCenDsrcTolling;
  }
  if (present & 4)
    z.expiryTime = static_cast<TimestampIts>(r.get_bits(42, "expiryTime"));
  z.protectedZoneLatitude =
      static_cast<Latitude>(r.get_constrained<-900000000, 900000001>("protectedZoneLatitude"));
  z.protectedZoneLongitude =
      static_cast<Longitude>(r.get_constrained<-1800000000, 1800000001>("protectedZoneLongitude"));
  if (present & 2)
    z.protectedZoneRadius =
        static_cast<ProtectedZoneRadius>(r.get_constrained_ext<1, 255>("protectedZoneRadius"));
  if (present & 1)
    z.protectedZoneID =
        static_cast<ProtectedZoneID>(r.get_constrained<0, 134217727>("protectedZoneID"));
  if (ext)
    r.skip_sequence_extensions("protectedCommunicationZone");
}

void put(UperWriter& w, const RSUContainerHighFrequency& rsu, bool v1) {
  w.put_bool(false);
  w.put_bool(rsu.protectedCommunicationZonesRSU.has_value());
  if (!rsu.protectedCommunicationZonesRSU)
    return;
  const auto& zones = *rsu.protectedCommunicationZonesRSU;
  put_size<1, 16>(w, zones.size(), "protectedCommunicationZonesRSU");
  for (const ProtectedCommunicationZone& z : zones)
    put(w, z, v1);
}

void get(UperReader& r, RSUContainerHighFrequency& rsu, bool v1) {
  rsu = RSUContainerHighFrequency{};
  const bool ext = r.get_bool("rsuContainerHighFrequency");
  if (r.get_bool("rsuContainerHighFrequency")) {
    auto& zones = rsu.protectedCommunicationZonesRSU.emplace();
    const auto n =
        static_cast<std::size_t>(r.get_constrained<1, 16>("protectedCommunicationZonesRSU"));
    for (std::size_t i = 0; i < n && r.ok(); ++i)
      get(r, zones.emplace_back(), v1);
  }
  if (ext)
    r.skip_sequence_extensions("rsuContainerHighFrequency");
}

// ---- Special-vehicle containers: SEQUENCEs without extension marker, OPTIONAL bits first ----
void put_causecode_opt(UperWriter& w, const std::optional<CauseCode>& c, bool v1) {
  if (c)
    put(w, *c, v1);
}

struct SpecialPut {
  UperWriter& w;
  bool v1;
  void operator()(const PublicTransportContainer& c) const {
    w.put_bool(c.ptActivation.has_value());
    w.put_bool(c.embarkationStatus);
    if (c.ptActivation) {
      w.put_bits(c.ptActivation->ptActivationType, 8);
      const auto& data = c.ptActivation->ptActivationData;
      // OCTET STRING (SIZE(1..20)): size - 1 in 5 bits, then the octets (X.691 17.8).
      w.put_constrained<1, 20>(static_cast<std::int64_t>(data.size()), "ptActivationData");
      for (std::uint8_t b : data)
        w.put_bits(b, 8);
    }
  }
  void operator()(const SpecialTransportContainer& c) const {
    put_named_bits(w, c.specialTransportType, 4, "specialTransportType");
    put_named_bits(w, c.lightBarSirenInUse, 2, "lightBarSirenInUse");
  }
  void operator()(const DangerousGoodsContainer& c) const {
    w.put_enumerated(c.dangerousGoodsBasic, 20, false, "dangerousGoodsBasic");
  }
  void operator()(const RoadWorksContainerBasic& c) const {
    w.put_bool(c.roadworksSubCauseCode.has_value());
    w.put_bool(c.closedLanes.has_value());
    if (c.roadworksSubCauseCode)
      w.put_bits(*c.roadworksSubCauseCode, 8);
    put_named_bits(w, c.lightBarSirenInUse, 2, "lightBarSirenInUse");
    if (c.closedLanes)
      put(w, *c.closedLanes, v1);
  }
  void operator()(const RescueContainer& c) const {
    put_named_bits(w, c.lightBarSirenInUse, 2, "lightBarSirenInUse");
  }
  void operator()(const EmergencyContainer& c) const {
    w.put_bool(c.incidentIndication.has_value());
    w.put_bool(c.emergencyPriority.has_value());
    put_named_bits(w, c.lightBarSirenInUse, 2, "lightBarSirenInUse");
    put_causecode_opt(w, c.incidentIndication, v1);
    if (c.emergencyPriority)
      put_named_bits(w, *c.emergencyPriority, 2, "emergencyPriority");
  }
  void operator()(const SafetyCarContainer& c) const {
    w.put_bool(c.incidentIndication.has_value());
    w.put_bool(c.trafficRule.has_value());
    w.put_bool(c.speedLimit.has_value());
    put_named_bits(w, c.lightBarSirenInUse, 2, "lightBarSirenInUse");
    put_causecode_opt(w, c.incidentIndication, v1);
    if (c.trafficRule)
      put_enum(w, *c.trafficRule, 4, true, "trafficRule");
    if (c.speedLimit)
      w.put_constrained<1, 255>(*c.speedLimit, "speedLimit");
  }
};

void put(UperWriter& w, const SpecialVehicleContainer& c, bool v1) {
  w.put_bool(false);  // CHOICE extension bit: a root alternative
  w.put_bits(c.index(), 3);
  std::visit(SpecialPut{w, v1}, c);
}

void get(UperReader& r, SpecialVehicleContainer& out, bool v1) {
  const std::size_t at = r.bit_position();
  if (r.get_bool("specialVehicleContainer")) {
    if (r.ok())
      r.fail_at(Error::kUnknownExtension, "specialVehicleContainer", 0, at);
    return;
  }
  const auto index = r.get_bits(3, "specialVehicleContainer");
  switch (index) {
    case 0: {
      auto& c = out.emplace<PublicTransportContainer>();
      const bool has_pt = r.get_bool("publicTransportContainer");
      c.embarkationStatus = r.get_bool("embarkationStatus");
      if (has_pt) {
        PtActivation& pt = c.ptActivation.emplace();
        pt.ptActivationType = static_cast<std::uint8_t>(r.get_bits(8, "ptActivationType"));
        const auto n = static_cast<std::size_t>(r.get_constrained<1, 20>("ptActivationData"));
        for (std::size_t i = 0; i < n && r.ok(); ++i)
          pt.ptActivationData.push_back(
              static_cast<std::uint8_t>(r.get_bits(8, "ptActivationData")));
      }
      break;
    }
    case 1: {
      auto& c = out.emplace<SpecialTransportContainer>();
      c.specialTransportType =
          static_cast<SpecialTransportType>(get_named_bits(r, 4, "specialTransportType"));
      c.lightBarSirenInUse =
          static_cast<LightBarSirenInUse>(get_named_bits(r, 2, "lightBarSirenInUse"));
      break;
    }
    case 2: {
      auto& c = out.emplace<DangerousGoodsContainer>();
      c.dangerousGoodsBasic =
          static_cast<DangerousGoodsBasic>(r.get_enumerated(20, false, "dangerousGoodsBasic"));
      break;
    }
    case 3: {
      auto& c = out.emplace<RoadWorksContainerBasic>();
      const bool has_sub = r.get_bool("roadWorksContainerBasic");
      const bool has_lanes = r.get_bool("roadWorksContainerBasic");
      if (has_sub)
        c.roadworksSubCauseCode =
            static_cast<SubCauseCodeType>(r.get_bits(8, "roadworksSubCauseCode"));
      c.lightBarSirenInUse =
          static_cast<LightBarSirenInUse>(get_named_bits(r, 2, "lightBarSirenInUse"));
      if (has_lanes)
        get(r, c.closedLanes.emplace(), v1);
      break;
    }
    case 4: {
      auto& c = out.emplace<RescueContainer>();
      c.lightBarSirenInUse =
          static_cast<LightBarSirenInUse>(get_named_bits(r, 2, "lightBarSirenInUse"));
      break;
    }
    case 5: {
      auto& c = out.emplace<EmergencyContainer>();
      const bool has_incident = r.get_bool("emergencyContainer");
      const bool has_priority = r.get_bool("emergencyContainer");
      c.lightBarSirenInUse =
          static_cast<LightBarSirenInUse>(get_named_bits(r, 2, "lightBarSirenInUse"));
      if (has_incident)
        get(r, c.incidentIndication.emplace(), "incidentIndication", v1);
      if (has_priority)
        c.emergencyPriority =
            static_cast<EmergencyPriority>(get_named_bits(r, 2, "emergencyPriority"));
      break;
    }
    case 6: {
      auto& c = out.emplace<SafetyCarContainer>();
      const bool has_incident = r.get_bool("safetyCarContainer");
      const bool has_rule = r.get_bool("safetyCarContainer");
      const bool has_limit = r.get_bool("safetyCarContainer");
      c.lightBarSirenInUse =
          static_cast<LightBarSirenInUse>(get_named_bits(r, 2, "lightBarSirenInUse"));
      if (has_incident)
        get(r, c.incidentIndication.emplace(), "incidentIndication", v1);
      if (has_rule)
        c.trafficRule = get_enum<TrafficRule>(r, 4, true, "trafficRule");
      if (has_limit)
        c.speedLimit = static_cast<SpeedLimit>(r.get_constrained<1, 255>("speedLimit"));
      break;
    }
    default:  // index 7 of a 7-alternative root
      if (r.ok())
        r.fail_at(Error::kValueOutOfRange, "specialVehicleContainer",
                  static_cast<std::int64_t>(index), at + 1);
  }
}

void put(UperWriter& w, const Cam& cam) {
  put_header(w, cam.header);
  const CoopAwareness& ca = cam.cam;
  w.put_bits(ca.generationDeltaTime, 16);
  const CamParameters& p = ca.camParameters;
  // CamParameters: extension bit, then the presence of lowFrequencyContainer and
  // specialVehicleContainer.
  w.put_bool(false);
  w.put_bool(p.lowFrequencyContainer.has_value());
  w.put_bool(p.specialVehicleContainer.has_value());
  // BasicContainer ::= SEQUENCE {stationType, referencePosition, ...}
  w.put_bool(false);
  w.put_bits(p.basicContainer.stationType, 8);
  put(w, p.basicContainer.referencePosition);
  // HighFrequencyContainer CHOICE {basicVehicleContainerHighFrequency,
  // rsuContainerHighFrequency, ...}: extension bit 0, the index in one bit.
  const bool v1 = cam.header.protocolVersion == kProtocolVersion1;
  w.put_bool(false);
  w.put_bits(p.highFrequencyContainer.index(), 1);
  if (const auto* hf = vehicle_hf(p))
    put(w, *hf, v1);
  else
    put(w, std::get<RSUContainerHighFrequency>(p.highFrequencyContainer), v1);
  if (p.lowFrequencyContainer) {
    // LowFrequencyContainer CHOICE {basicVehicleContainerLowFrequency, ...}: extension bit 0;
    // a single root alternative takes no index bits.
    w.put_bool(false);
    const BasicVehicleContainerLowFrequency& lf = *p.lowFrequencyContainer;
    put_enum(w, lf.vehicleRole, 16, false, "vehicleRole");
    put_named_bits(w, lf.exteriorLights, 8, "exteriorLights");
    put(w, lf.pathHistory);
  }
  if (p.specialVehicleContainer)
    put(w, *p.specialVehicleContainer, cam.header.protocolVersion == kProtocolVersion1);
}

void get(UperReader& r, Cam& cam) {
  if (!get_header(r, cam.header, kMessageIdCam))
    return;
  CoopAwareness& ca = cam.cam;
  ca.generationDeltaTime = static_cast<GenerationDeltaTime>(r.get_bits(16, "generationDeltaTime"));
  CamParameters& p = ca.camParameters;
  const bool params_ext = r.get_bool("camParameters");
  const bool has_lf = r.get_bool("camParameters");
  const bool has_special = r.get_bool("camParameters");
  const bool basic_ext = r.get_bool("basicContainer");
  p.basicContainer.stationType = static_cast<StationType>(r.get_bits(8, "stationType"));
  get(r, p.basicContainer.referencePosition);
  if (basic_ext)
    r.skip_sequence_extensions("basicContainer");
  const std::size_t hf_at = r.bit_position();
  if (r.get_bool("highFrequencyContainer")) {
    r.fail_at(Error::kUnknownExtension, "highFrequencyContainer", 0, hf_at);
    return;
  }
  if (r.get_bool("highFrequencyContainer"))
    get(r, p.highFrequencyContainer.emplace<RSUContainerHighFrequency>(),
        cam.header.protocolVersion == kProtocolVersion1);
  else
    get(r, p.highFrequencyContainer.emplace<BasicVehicleContainerHighFrequency>(),
        cam.header.protocolVersion == kProtocolVersion1);
  p.lowFrequencyContainer.reset();
  if (has_lf) {
    const std::size_t lf_at = r.bit_position();
    if (r.get_bool("lowFrequencyContainer")) {
      r.fail_at(Error::kUnknownExtension, "lowFrequencyContainer", 0, lf_at);
      return;
    }
    BasicVehicleContainerLowFrequency& lf = p.lowFrequencyContainer.emplace();
    lf.vehicleRole = static_cast<VehicleRole>(r.get_bits(4, "vehicleRole"));
    lf.exteriorLights = static_cast<ExteriorLights>(get_named_bits(r, 8, "exteriorLights"));
    get(r, lf.pathHistory);
  }
  p.specialVehicleContainer.reset();
  if (has_special)
    get(r, p.specialVehicleContainer.emplace(), cam.header.protocolVersion == kProtocolVersion1);
  if (params_ext)
    r.skip_sequence_extensions("camParameters");
}

}  // namespace

Expected<std::size_t, CodecError> encode(const Cam& cam, std::span<std::uint8_t> out) {
  if (cam.header.protocolVersion != kProtocolVersion &&
      cam.header.protocolVersion != kProtocolVersion1)
    return Unexpected<CodecError>{
        CodecError{Error::kUnsupportedVersion, "protocolVersion", cam.header.protocolVersion, 0}};
  if (cam.header.messageID != kMessageIdCam)
    return Unexpected<CodecError>{
        CodecError{Error::kWrongMessageId, "messageID", cam.header.messageID, 8}};
  UperWriter w(out);
  put(w, cam);
  const std::size_t n = w.finish();
  if (!w.ok())
    return Unexpected<CodecError>{w.error()};
  return n;
}

Expected<std::vector<std::uint8_t>, CodecError> encode(const Cam& cam) {
  return encode_to_vector(cam, kCamMaxEncodedSize);
}

Expected<std::size_t, CodecError> decode(std::span<const std::uint8_t> bytes, Cam& out) {
  return decode_whole(bytes, out, "CAM", [](UperReader& r, Cam& m) { get(r, m); });
}

Expected<Cam, CodecError> decode_cam(std::span<const std::uint8_t> bytes) {
  return decode_value<Cam>(bytes);
}

}  // namespace tb::its::messages
