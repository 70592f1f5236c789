#include "its-station/messages/cam.hpp"

#include "its-station/messages/cdd_codec.hpp"

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

void put(UperWriter& w, const Cam& cam) {
  put_header(w, cam.header);
  const CoopAwareness& ca = cam.cam;
  w.put_bits(ca.generationDeltaTime, 16);
  const CamParameters& p = ca.camParameters;
  // CamParameters: extension bit, then the presence of lowFrequencyContainer and
  // specialVehicleContainer.
  w.put_bits(p.lowFrequencyContainer ? 0b010 : 0b000, 3);
  // BasicContainer ::= SEQUENCE {stationType, referencePosition, ...}
  w.put_bool(false);
  w.put_bits(p.basicContainer.stationType, 8);
  put(w, p.basicContainer.referencePosition);
  // HighFrequencyContainer CHOICE {basicVehicleContainerHighFrequency, rsu…, ...}: extension
  // bit 0, index 0 in one bit.
  w.put_bits(0b00, 2);
  put(w, p.highFrequencyContainer, cam.header.protocolVersion == kProtocolVersion1);
  if (p.lowFrequencyContainer) {
    // LowFrequencyContainer CHOICE {basicVehicleContainerLowFrequency, ...}: extension bit 0;
    // a single root alternative takes no index bits.
    w.put_bool(false);
    const BasicVehicleContainerLowFrequency& lf = *p.lowFrequencyContainer;
    put_enum(w, lf.vehicleRole, 16, false, "vehicleRole");
    put_named_bits(w, lf.exteriorLights, 8, "exteriorLights");
    put(w, lf.pathHistory);
  }
}

void get(UperReader& r, Cam& cam) {
  if (!get_header(r, cam.header, kMessageIdCam))
    return;
  CoopAwareness& ca = cam.cam;
  ca.generationDeltaTime = static_cast<GenerationDeltaTime>(r.get_bits(16, "generationDeltaTime"));
  CamParameters& p = ca.camParameters;
  const bool params_ext = r.get_bool("camParameters");
  const bool has_lf = r.get_bool("camParameters");
  const std::size_t special_at = r.bit_position();
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
  if (r.get_bool("highFrequencyContainer")) {
    r.fail_at(Error::kUnsupported, "rsuContainerHighFrequency", 1, hf_at);
    return;
  }
  get(r, p.highFrequencyContainer, cam.header.protocolVersion == kProtocolVersion1);
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
  if (has_special) {
    r.fail_at(Error::kUnsupported, "specialVehicleContainer", 1, special_at);
    return;
  }
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
  std::vector<std::uint8_t> out(kCamMaxEncodedSize);
  auto n = encode(cam, out);
  if (!n)
    return Unexpected<CodecError>{n.error()};
  out.resize(*n);
  return out;
}

Expected<std::size_t, CodecError> decode(std::span<const std::uint8_t> bytes, Cam& out) {
  UperReader r(bytes);
  get(r, out);
  if (!r.ok())
    return Unexpected<CodecError>{r.error()};
  if (r.octets_consumed() != bytes.size())
    return Unexpected<CodecError>{CodecError{
        Error::kTrailingData, "CAM", static_cast<std::int64_t>(bytes.size() - r.octets_consumed()),
        r.octets_consumed() * 8}};
  return r.octets_consumed();
}

Expected<Cam, CodecError> decode_cam(std::span<const std::uint8_t> bytes) {
  Cam cam;
  auto n = decode(bytes, cam);
  if (!n)
    return Unexpected<CodecError>{n.error()};
  return cam;
}

}  // namespace tb::its::messages
