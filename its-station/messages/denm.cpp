#include "its-station/messages/denm.hpp"

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

void put(UperWriter& w, const ManagementContainer& m) {
  const bool has_validity = m.validityDuration != kDefaultValidity;
  // Extension bit, then termination, relevanceDistance, relevanceTrafficDirection,
  // validityDuration (DEFAULT) and transmissionInterval.
  w.put_bool(false);
  w.put_bool(m.termination.has_value());
  w.put_bool(m.relevanceDistance.has_value());
  w.put_bool(m.relevanceTrafficDirection.has_value());
  w.put_bool(has_validity);
  w.put_bool(m.transmissionInterval.has_value());
  w.put_bits(m.actionID.originatingStationID, 32);
  w.put_bits(m.actionID.sequenceNumber, 16);
  w.put_constrained<0, 4398046511103>(static_cast<std::int64_t>(m.detectionTime), "detectionTime");
  w.put_constrained<0, 4398046511103>(static_cast<std::int64_t>(m.referenceTime), "referenceTime");
  if (m.termination)
    put_enum(w, *m.termination, 2, false, "termination");
  put(w, m.eventPosition);
  if (m.relevanceDistance)
    put_enum(w, *m.relevanceDistance, 8, false, "relevanceDistance");
  if (m.relevanceTrafficDirection)
    put_enum(w, *m.relevanceTrafficDirection, 4, false, "relevanceTrafficDirection");
  if (has_validity)
    w.put_constrained<0, 86400>(m.validityDuration, "validityDuration");
  if (m.transmissionInterval)
    w.put_constrained<1, 10000>(*m.transmissionInterval, "transmissionInterval");
  w.put_bits(m.stationType, 8);
}

void get(UperReader& r, ManagementContainer& m) {
  const bool ext = r.get_bool("management");
  const auto present = r.get_bits(5, "management");
  m.actionID.originatingStationID = static_cast<StationID>(r.get_bits(32, "originatingStationID"));
  m.actionID.sequenceNumber = static_cast<SequenceNumber>(r.get_bits(16, "sequenceNumber"));
  m.detectionTime = static_cast<TimestampIts>(r.get_bits(42, "detectionTime"));
  m.referenceTime = static_cast<TimestampIts>(r.get_bits(42, "referenceTime"));
  m.termination.reset();
  m.relevanceDistance.reset();
  m.relevanceTrafficDirection.reset();
  m.transmissionInterval.reset();
  m.validityDuration = kDefaultValidity;
  if (present & 0x10)
    m.termination = static_cast<Termination>(r.get_bits(1, "termination"));
  get(r, m.eventPosition);
  if (present & 0x08)
    m.relevanceDistance = static_cast<RelevanceDistance>(r.get_bits(3, "relevanceDistance"));
  if (present & 0x04)
    m.relevanceTrafficDirection =
        static_cast<RelevanceTrafficDirection>(r.get_bits(2, "relevanceTrafficDirection"));
  if (present & 0x02)
    m.validityDuration =
        static_cast<ValidityDuration>(r.get_constrained<0, 86400>("validityDuration"));
  if (present & 0x01)
    m.transmissionInterval =
        static_cast<TransmissionInterval>(r.get_constrained<1, 10000>("transmissionInterval"));
  m.stationType = static_cast<StationType>(r.get_bits(8, "stationType"));
  if (ext)
    r.skip_sequence_extensions("management");
}

// EventPoint ::= SEQUENCE {eventPosition, eventDeltaTime OPTIONAL, informationQuality}
void put(UperWriter& w, const SituationContainer& s, bool v1) {
  w.put_bool(false);
  w.put_bool(s.linkedCause.has_value());
  w.put_bool(s.eventHistory.has_value());
  w.put_constrained<0, 7>(s.informationQuality, "informationQuality");
  put(w, s.eventType, v1);
  if (s.linkedCause)
    put(w, *s.linkedCause, v1);
  if (s.eventHistory) {
    const EventHistory& h = *s.eventHistory;
    // SIZE(1..23)
    w.put_constrained<1, 23>(static_cast<std::int64_t>(h.size()), "eventHistory");
    for (const EventPoint& p : h) {
      w.put_bool(p.eventDeltaTime.has_value());
      put(w, p.eventPosition);
      if (p.eventDeltaTime)
        put_path_delta_time(w, *p.eventDeltaTime, "eventDeltaTime");
      w.put_constrained<0, 7>(p.informationQuality, "informationQuality");
    }
  }
}

void get(UperReader& r, SituationContainer& s, bool v1) {
  const bool ext = r.get_bool("situation");
  const bool has_linked = r.get_bool("situation");
  const bool has_history = r.get_bool("situation");
  s.informationQuality = static_cast<InformationQuality>(r.get_bits(3, "informationQuality"));
  get(r, s.eventType, "eventType", v1);
  s.linkedCause.reset();
  s.eventHistory.reset();
  if (has_linked)
    get(r, s.linkedCause.emplace(), "linkedCause", v1);
  if (has_history) {
    EventHistory& h = s.eventHistory.emplace();
    const auto n = static_cast<std::size_t>(r.get_constrained<1, 23>("eventHistory"));
    for (std::size_t i = 0; i < n && r.ok(); ++i) {
      EventPoint& p = h.emplace_back();
      const bool has_time = r.get_bool("eventPoint");
      get(r, p.eventPosition);
      if (has_time)
        p.eventDeltaTime = get_path_delta_time(r, "eventDeltaTime");
      p.informationQuality = static_cast<InformationQuality>(r.get_bits(3, "informationQuality"));
    }
  }
  if (ext)
    r.skip_sequence_extensions("situation");
}

void put(UperWriter& w, const LocationContainer& l) {
  w.put_bool(false);
  w.put_bool(l.eventSpeed.has_value());
  w.put_bool(l.eventPositionHeading.has_value());
  w.put_bool(l.roadType.has_value());
  if (l.eventSpeed)
    put(w, *l.eventSpeed);
  if (l.eventPositionHeading)
    put(w, *l.eventPositionHeading);
  // Traces ::= SEQUENCE SIZE(1..7) OF PathHistory
  w.put_constrained<1, 7>(static_cast<std::int64_t>(l.traces.size()), "traces");
  for (const PathHistory& h : l.traces)
    put(w, h);
  if (l.roadType)
    put_enum(w, *l.roadType, 4, false, "roadType");
}

void get(UperReader& r, LocationContainer& l) {
  const bool ext = r.get_bool("location");
  const bool has_speed = r.get_bool("location");
  const bool has_heading = r.get_bool("location");
  const bool has_road = r.get_bool("location");
  l.eventSpeed.reset();
  l.eventPositionHeading.reset();
  l.roadType.reset();
  l.traces.clear();
  if (has_speed)
    get(r, l.eventSpeed.emplace());
  if (has_heading)
    get(r, l.eventPositionHeading.emplace());
  const auto n = static_cast<std::size_t>(r.get_constrained<1, 7>("traces"));
  for (std::size_t i = 0; i < n && r.ok(); ++i)
    get(r, l.traces.emplace_back());
  if (has_road)
    l.roadType = static_cast<RoadType>(r.get_bits(2, "roadType"));
  if (ext)
    r.skip_sequence_extensions("location");
}

void put(UperWriter& w, const ImpactReductionContainer& c) {
  w.put_constrained<1, 100>(c.heightLonCarrLeft, "heightLonCarrLeft");
  w.put_constrained<1, 100>(c.heightLonCarrRight, "heightLonCarrRight");
  w.put_constrained<1, 127>(c.posLonCarrLeft, "posLonCarrLeft");
  w.put_constrained<1, 127>(c.posLonCarrRight, "posLonCarrRight");
  put_size_ext<1, 3>(w, c.positionOfPillars.size(), "positionOfPillars");
  for (PosPillar p : c.positionOfPillars)
    w.put_constrained<1, 30>(p, "posPillar");
  w.put_constrained<1, 63>(c.posCentMass, "posCentMass");
  w.put_constrained<1, 127>(c.wheelBaseVehicle, "wheelBaseVehicle");
  w.put_constrained<1, 255>(c.turningRadius, "turningRadius");
  w.put_constrained<1, 20>(c.posFrontAx, "posFrontAx");
  put_named_bits(w, c.positionOfOccupants, 20, "positionOfOccupants");
  w.put_constrained<1, 1024>(c.vehicleMass, "vehicleMass");
  put_enum(w, c.requestResponseIndication, 2, false, "requestResponseIndication");
}

void get(UperReader& r, ImpactReductionContainer& c) {
  c.heightLonCarrLeft = static_cast<HeightLonCarr>(r.get_constrained<1, 100>("heightLonCarrLeft"));
  c.heightLonCarrRight =
      static_cast<HeightLonCarr>(r.get_constrained<1, 100>("heightLonCarrRight"));
  c.posLonCarrLeft = static_cast<PosLonCarr>(r.get_constrained<1, 127>("posLonCarrLeft"));
  c.posLonCarrRight = static_cast<PosLonCarr>(r.get_constrained<1, 127>("posLonCarrRight"));
  c.positionOfPillars.clear();
  const std::size_t pillars = get_size_ext<1, 3>(r, "positionOfPillars");
  for (std::size_t i = 0; i < pillars && r.ok(); ++i)
    c.positionOfPillars.push_back(static_cast<PosPillar>(r.get_constrained<1, 30>("posPillar")));
  c.posCentMass = static_cast<PosCentMass>(r.get_constrained<1, 63>("posCentMass"));
  c.wheelBaseVehicle = static_cast<WheelBaseVehicle>(r.get_constrained<1, 127>("wheelBaseVehicle"));
  c.turningRadius = static_cast<TurningRadius>(r.get_constrained<1, 255>("turningRadius"));
  c.posFrontAx = static_cast<PosFrontAx>(r.get_constrained<1, 20>("posFrontAx"));
  c.positionOfOccupants =
      static_cast<PositionOfOccupants>(get_named_bits(r, 20, "positionOfOccupants"));
  c.vehicleMass = static_cast<VehicleMass>(r.get_constrained<1, 1024>("vehicleMass"));
  c.requestResponseIndication =
      get_enum<RequestResponseIndication>(r, 2, false, "requestResponseIndication");
}

void put(UperWriter& w, const RoadWorksContainerExtended& c, bool v1) {
  w.put_bool(c.lightBarSirenInUse.has_value());
  w.put_bool(c.closedLanes.has_value());
  w.put_bool(c.restriction.has_value());
  w.put_bool(c.speedLimit.has_value());
  w.put_bool(c.incidentIndication.has_value());
  w.put_bool(c.recommendedPath.has_value());
  w.put_bool(c.startingPointSpeedLimit.has_value());
  w.put_bool(c.trafficFlowRule.has_value());
  w.put_bool(c.referenceDenms.has_value());
  if (c.lightBarSirenInUse)
    put_named_bits(w, *c.lightBarSirenInUse, 2, "lightBarSirenInUse");
  if (c.closedLanes)
    put(w, *c.closedLanes, v1);
  if (c.restriction) {
    put_size_ext<1, 3>(w, c.restriction->size(), "restriction");
    for (StationType t : *c.restriction)
      w.put_bits(t, 8);
  }
  if (c.speedLimit)
    w.put_constrained<1, 255>(*c.speedLimit, "speedLimit");
  if (c.incidentIndication)
    put(w, *c.incidentIndication, v1);
  if (c.recommendedPath) {
    put_size<1, 40>(w, c.recommendedPath->size(), "recommendedPath");
    for (const ReferencePosition& p : *c.recommendedPath)
      put(w, p);
  }
  if (c.startingPointSpeedLimit)
    put(w, *c.startingPointSpeedLimit);
  if (c.trafficFlowRule)
    put_enum(w, *c.trafficFlowRule, 4, true, "trafficFlowRule");
  if (c.referenceDenms) {
    put_size_ext<1, 8>(w, c.referenceDenms->size(), "referenceDenms");
    for (const ActionID& a : *c.referenceDenms) {
      w.put_bits(a.originatingStationID, 32);
      w.put_bits(a.sequenceNumber, 16);
    }
  }
}

void get(UperReader& r, RoadWorksContainerExtended& c, bool v1) {
  c = RoadWorksContainerExtended{};
  const auto present = r.get_bits(9, "roadWorks");
  if (present & 0x100)
    c.lightBarSirenInUse =
        static_cast<LightBarSirenInUse>(get_named_bits(r, 2, "lightBarSirenInUse"));
  if (present & 0x80)
    get(r, c.closedLanes.emplace(), v1);
  if (present & 0x40) {
    RestrictedTypes& t = c.restriction.emplace();
    const std::size_t n = get_size_ext<1, 3>(r, "restriction");
    for (std::size_t i = 0; i < n && r.ok(); ++i)
      t.push_back(static_cast<StationType>(r.get_bits(8, "restriction")));
  }
  if (present & 0x20)
    c.speedLimit = static_cast<SpeedLimit>(r.get_constrained<1, 255>("speedLimit"));
  if (present & 0x10)
    get(r, c.incidentIndication.emplace(), "incidentIndication", v1);
  if (present & 0x08) {
    ItineraryPath& path = c.recommendedPath.emplace();
    const auto n = static_cast<std::size_t>(r.get_constrained<1, 40>("recommendedPath"));
    for (std::size_t i = 0; i < n && r.ok(); ++i)
      get(r, path.emplace_back());
  }
  if (present & 0x04)
    get(r, c.startingPointSpeedLimit.emplace());
  if (present & 0x02)
    c.trafficFlowRule = get_enum<TrafficRule>(r, 4, true, "trafficFlowRule");
  if (present & 0x01) {
    ReferenceDenms& refs = c.referenceDenms.emplace();
    const std::size_t n = get_size_ext<1, 8>(r, "referenceDenms");
    for (std::size_t i = 0; i < n && r.ok(); ++i) {
      ActionID& a = refs.emplace_back();
      a.originatingStationID = static_cast<StationID>(r.get_bits(32, "originatingStationID"));
      a.sequenceNumber = static_cast<SequenceNumber>(r.get_bits(16, "sequenceNumber"));
    }
  }
}

void put(UperWriter& w, const StationaryVehicleContainer& c, bool v1) {
  w.put_bool(c.stationarySince.has_value());
  w.put_bool(c.stationaryCause.has_value());
  w.put_bool(c.carryingDangerousGoods.has_value());
  w.put_bool(c.numberOfOccupants.has_value());
  w.put_bool(c.vehicleIdentification.has_value());
  w.put_bool(c.energyStorageType.has_value());
  if (c.stationarySince)
    put_enum(w, *c.stationarySince, 4, false, "stationarySince");
  if (c.stationaryCause)
    put(w, *c.stationaryCause, v1);
  if (c.carryingDangerousGoods)
    put(w, *c.carryingDangerousGoods, v1);
  if (c.numberOfOccupants)
    w.put_constrained<0, 127>(*c.numberOfOccupants, "numberOfOccupants");
  if (c.vehicleIdentification) {
    const VehicleIdentification& id = *c.vehicleIdentification;
    w.put_bool(false);
    w.put_bool(id.wMInumber.has_value());
    w.put_bool(id.vDS.has_value());
    if (id.wMInumber)
      put_ia5<1, 3>(w, *id.wMInumber, "wMInumber");
    if (id.vDS)
      put_ia5<6, 6>(w, *id.vDS, "vDS");
  }
  if (c.energyStorageType)
    put_named_bits(w, *c.energyStorageType, 7, "energyStorageType");
}

void get(UperReader& r, StationaryVehicleContainer& c, bool v1) {
  c = StationaryVehicleContainer{};
  const auto present = r.get_bits(6, "stationaryVehicle");
  if (present & 0x20)
    c.stationarySince = get_enum<StationarySince>(r, 4, false, "stationarySince");
  if (present & 0x10)
    get(r, c.stationaryCause.emplace(), "stationaryCause", v1);
  if (present & 0x08)
    get(r, c.carryingDangerousGoods.emplace(), v1);
  if (present & 0x04)
    c.numberOfOccupants =
        static_cast<NumberOfOccupants>(r.get_constrained<0, 127>("numberOfOccupants"));
  if (present & 0x02) {
    VehicleIdentification& id = c.vehicleIdentification.emplace();
    const bool ext = r.get_bool("vehicleIdentification");
    const bool has_wmi = r.get_bool("vehicleIdentification");
    const bool has_vds = r.get_bool("vehicleIdentification");
    if (has_wmi)
      get_ia5<1, 3>(r, id.wMInumber.emplace(), "wMInumber");
    if (has_vds)
      get_ia5<6, 6>(r, id.vDS.emplace(), "vDS");
    if (ext)
      r.skip_sequence_extensions("vehicleIdentification");
  }
  if (present & 0x01)
    c.energyStorageType = static_cast<EnergyStorageType>(get_named_bits(r, 7, "energyStorageType"));
}

// AlacarteContainer ::= SEQUENCE {lanePosition, impactReduction, externalTemperature,
// roadWorks, positioningSolution, stationaryVehicle (all OPTIONAL), ...}
void put(UperWriter& w, const AlacarteContainer& a, bool v1) {
  w.put_bool(false);
  w.put_bool(a.lanePosition.has_value());
  w.put_bool(a.impactReduction.has_value());
  w.put_bool(a.externalTemperature.has_value());
  w.put_bool(a.roadWorks.has_value());
  w.put_bool(a.positioningSolution.has_value());
  w.put_bool(a.stationaryVehicle.has_value());
  if (a.lanePosition)
    w.put_constrained<-1, 14>(*a.lanePosition, "lanePosition");
  if (a.impactReduction)
    put(w, *a.impactReduction);
  if (a.externalTemperature)
    w.put_constrained<-60, 67>(*a.externalTemperature, "externalTemperature");
  if (a.roadWorks)
    put(w, *a.roadWorks, v1);
  if (a.positioningSolution)
    put_enum(w, *a.positioningSolution, 6, true, "positioningSolution");
  if (a.stationaryVehicle)
    put(w, *a.stationaryVehicle, v1);
}

void get(UperReader& r, AlacarteContainer& a, bool v1) {
  a = AlacarteContainer{};
  const bool ext = r.get_bool("alacarte");
  const auto present = r.get_bits(6, "alacarte");
  if (present & 0x20)
    a.lanePosition = static_cast<LanePosition>(r.get_constrained<-1, 14>("lanePosition"));
  if (present & 0x10)
    get(r, a.impactReduction.emplace());
  if (present & 0x08)
    a.externalTemperature =
        static_cast<Temperature>(r.get_constrained<-60, 67>("externalTemperature"));
  if (present & 0x04)
    get(r, a.roadWorks.emplace(), v1);
  if (present & 0x02)
    a.positioningSolution = get_enum<PositioningSolutionType>(r, 6, true, "positioningSolution");
  if (present & 0x01)
    get(r, a.stationaryVehicle.emplace(), v1);
  if (ext)
    r.skip_sequence_extensions("alacarte");
}

void put(UperWriter& w, const Denm& d) {
  w.put_bits(d.header.protocolVersion, 8);
  w.put_bits(d.header.messageID, 8);
  w.put_bits(d.header.stationID, 32);
  const DecentralizedEnvironmentalNotificationMessage& m = d.denm;
  // No extension marker; situation, location, alacarte OPTIONAL.
  w.put_bool(m.situation.has_value());
  w.put_bool(m.location.has_value());
  w.put_bool(m.alacarte.has_value());
  put(w, m.management);
  if (m.situation)
    put(w, *m.situation, d.header.protocolVersion == kProtocolVersion1);
  if (m.location)
    put(w, *m.location);
  if (m.alacarte)
    put(w, *m.alacarte, d.header.protocolVersion == kProtocolVersion1);
}

void get(UperReader& r, Denm& d) {
  ItsPduHeader& h = d.header;
  h.protocolVersion = static_cast<std::uint8_t>(r.get_bits(8, "protocolVersion"));
  h.messageID = static_cast<std::uint8_t>(r.get_bits(8, "messageID"));
  h.stationID = static_cast<StationID>(r.get_bits(32, "stationID"));
  if (!r.ok())
    return;
  if (h.messageID != kMessageIdDenm) {
    r.fail_at(Error::kWrongMessageId, "messageID", h.messageID, 8);
    return;
  }
  if (h.protocolVersion != kProtocolVersion && h.protocolVersion != kProtocolVersion1) {
    r.fail_at(Error::kUnsupportedVersion, "protocolVersion", h.protocolVersion, 0);
    return;
  }
  DecentralizedEnvironmentalNotificationMessage& m = d.denm;
  const bool has_situation = r.get_bool("denm");
  const bool has_location = r.get_bool("denm");
  const bool has_alacarte = r.get_bool("denm");
  get(r, m.management);
  m.situation.reset();
  m.location.reset();
  m.alacarte.reset();
  if (has_situation)
    get(r, m.situation.emplace(), h.protocolVersion == kProtocolVersion1);
  if (has_location)
    get(r, m.location.emplace());
  if (has_alacarte)
    get(r, m.alacarte.emplace(), h.protocolVersion == kProtocolVersion1);
}

}  // namespace

Expected<std::size_t, CodecError> encode(const Denm& denm, std::span<std::uint8_t> out) {
  if (denm.header.protocolVersion != kProtocolVersion &&
      denm.header.protocolVersion != kProtocolVersion1)
    return Unexpected<CodecError>{
        CodecError{Error::kUnsupportedVersion, "protocolVersion", denm.header.protocolVersion, 0}};
  if (denm.header.messageID != kMessageIdDenm)
    return Unexpected<CodecError>{
        CodecError{Error::kWrongMessageId, "messageID", denm.header.messageID, 8}};
  if (denm.denm.location && denm.denm.location->traces.empty())
    return Unexpected<CodecError>{CodecError{Error::kSizeOutOfRange, "traces", 0, 0}};
  if (denm.denm.situation && denm.denm.situation->eventHistory &&
      denm.denm.situation->eventHistory->empty())
    return Unexpected<CodecError>{CodecError{Error::kSizeOutOfRange, "eventHistory", 0, 0}};
  UperWriter w(out);
  put(w, denm);
  const std::size_t n = w.finish();
  if (!w.ok())
    return Unexpected<CodecError>{w.error()};
  return n;
}

Expected<std::vector<std::uint8_t>, CodecError> encode(const Denm& denm) {
  return encode_to_vector(denm, kDenmMaxEncodedSize);
}

Expected<std::size_t, CodecError> decode(std::span<const std::uint8_t> bytes, Denm& out) {
  return decode_whole(bytes, out, "DENM", [](UperReader& r, Denm& m) { get(r, m); });
}

Expected<Denm, CodecError> decode_denm(std::span<const std::uint8_t> bytes) {
  return decode_value<Denm>(bytes);
}

}  // namespace tb::its::messages
