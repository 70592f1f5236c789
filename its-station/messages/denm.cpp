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

// AlacarteContainer ::= SEQUENCE {lanePosition, impactReduction, externalTemperature,
// roadWorks, positioningSolution, stationaryVehicle (all OPTIONAL), ...}
void put(UperWriter& w, const AlacarteContainer& a) {
  w.put_bool(false);
  w.put_bool(a.lanePosition.has_value());
  w.put_bool(false);
  w.put_bool(a.externalTemperature.has_value());
  w.put_bool(false);
  w.put_bool(a.positioningSolution.has_value());
  w.put_bool(false);
  if (a.lanePosition)
    w.put_constrained<-1, 14>(*a.lanePosition, "lanePosition");
  if (a.externalTemperature)
    w.put_constrained<-60, 67>(*a.externalTemperature, "externalTemperature");
  if (a.positioningSolution)
    put_enum(w, *a.positioningSolution, 6, true, "positioningSolution");
}

void get(UperReader& r, AlacarteContainer& a) {
  const std::size_t at = r.bit_position();
  const bool ext = r.get_bool("alacarte");
  const auto present = r.get_bits(6, "alacarte");
  if (present & 0x10) {
    r.fail_at(Error::kUnsupported, "impactReduction", 1, at + 2);
    return;
  }
  if (present & 0x04) {
    r.fail_at(Error::kUnsupported, "roadWorks", 1, at + 4);
    return;
  }
  if (present & 0x01) {
    r.fail_at(Error::kUnsupported, "stationaryVehicle", 1, at + 6);
    return;
  }
  a.lanePosition.reset();
  a.externalTemperature.reset();
  a.positioningSolution.reset();
  if (present & 0x20)
    a.lanePosition = static_cast<LanePosition>(r.get_constrained<-1, 14>("lanePosition"));
  if (present & 0x08)
    a.externalTemperature =
        static_cast<Temperature>(r.get_constrained<-60, 67>("externalTemperature"));
  if (present & 0x02)
    a.positioningSolution = get_enum<PositioningSolutionType>(r, 6, true, "positioningSolution");
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
    put(w, *m.alacarte);
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
    get(r, m.alacarte.emplace());
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
