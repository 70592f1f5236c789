#include "its-station/messages/spatem.hpp"

#include "its-station/messages/dsrc_codec.hpp"
#include "its-station/messages/message_codec.hpp"

namespace tb::its::messages {

using asn1::Error;
using asn1::UperReader;
using asn1::UperWriter;
using namespace detail;

const char* to_string(MovementPhaseState s) {
  switch (s) {
    case MovementPhaseState::unavailable:
      return "unavailable";
    case MovementPhaseState::dark:
      return "dark";
    case MovementPhaseState::stop_Then_Proceed:
      return "stop-Then-Proceed";
    case MovementPhaseState::stop_And_Remain:
      return "stop-And-Remain";
    case MovementPhaseState::pre_Movement:
      return "pre-Movement";
    case MovementPhaseState::permissive_Movement_Allowed:
      return "permissive-Movement-Allowed";
    case MovementPhaseState::protected_Movement_Allowed:
      return "protected-Movement-Allowed";
    case MovementPhaseState::permissive_clearance:
      return "permissive-clearance";
    case MovementPhaseState::protected_clearance:
      return "protected-clearance";
    case MovementPhaseState::caution_Conflicting_Traffic:
      return "caution-Conflicting-Traffic";
  }
  return "?";
}

namespace {

using detail::get;
using detail::put;

// TimeMark ::= INTEGER (0..36001): 16 bits, 36002..65535 do not exist.
void put_time_mark(UperWriter& w, TimeMark t, const char* f) {
  w.put_constrained<0, 36001>(t, f);
}
TimeMark get_time_mark(UperReader& r, const char* f) {
  return static_cast<TimeMark>(r.get_constrained<0, 36001>(f));
}

// TimeChangeDetails ::= SEQUENCE {startTime?, minEndTime, maxEndTime?, likelyTime?,
// confidence TimeIntervalConfidence (0..15) OPTIONAL, nextTime?}, no extension marker
void put(UperWriter& w, const TimeChangeDetails& t) {
  w.put_bool(t.startTime.has_value());
  w.put_bool(t.maxEndTime.has_value());
  w.put_bool(t.likelyTime.has_value());
  w.put_bool(t.confidence.has_value());
  w.put_bool(t.nextTime.has_value());
  if (t.startTime)
    put_time_mark(w, *t.startTime, "startTime");
  put_time_mark(w, t.minEndTime, "minEndTime");
  if (t.maxEndTime)
    put_time_mark(w, *t.maxEndTime, "maxEndTime");
  if (t.likelyTime)
    put_time_mark(w, *t.likelyTime, "likelyTime");
  if (t.confidence)
    w.put_constrained<0, 15>(*t.confidence, "confidence");
  if (t.nextTime)
    put_time_mark(w, *t.nextTime, "nextTime");
}
void get(UperReader& r, TimeChangeDetails& t) {
  t = TimeChangeDetails{};
  const auto present = r.get_bits(5, "timing");
  if (present & 0x10)
    t.startTime = get_time_mark(r, "startTime");
  t.minEndTime = get_time_mark(r, "minEndTime");
  if (present & 0x08)
    t.maxEndTime = get_time_mark(r, "maxEndTime");
  if (present & 0x04)
    t.likelyTime = get_time_mark(r, "likelyTime");
  if (present & 0x02)
    t.confidence = static_cast<TimeIntervalConfidence>(r.get_bits(4, "confidence"));
  if (present & 0x01)
    t.nextTime = get_time_mark(r, "nextTime");
}

// AdvisorySpeed ::= SEQUENCE {type AdvisorySpeedType (4 roots, ...), speed SpeedAdvice
// (0..500)?, confidence SpeedConfidence (8 values)?, distance ZoneLength (0..10000)?,
// class RestrictionClassID (0..255)?, regional?, ...}
void put(UperWriter& w, const AdvisorySpeed& a) {
  w.put_bool(false);
  w.put_bool(a.speed.has_value());
  w.put_bool(a.confidence.has_value());
  w.put_bool(a.distance.has_value());
  w.put_bool(a.class_.has_value());
  w.put_bool(false);  // regional
  put_enum(w, a.type, 4, true, "type");
  if (a.speed)
    w.put_constrained<0, 500>(*a.speed, "speed");
  if (a.confidence)
    put_enum(w, *a.confidence, 8, false, "confidence");
  if (a.distance)
    w.put_constrained<0, 10000>(*a.distance, "distance");
  if (a.class_)
    w.put_bits(*a.class_, 8);
}
void get(UperReader& r, AdvisorySpeed& a) {
  a = AdvisorySpeed{};
  const bool ext = r.get_bool("AdvisorySpeed");
  const auto present = r.get_bits(5, "AdvisorySpeed");
  a.type = get_enum<AdvisorySpeedType>(r, 4, true, "type");
  if (present & 0x10)
    a.speed = static_cast<SpeedAdvice>(r.get_constrained<0, 500>("speed"));
  if (present & 0x08)
    a.confidence = get_enum<SpeedConfidenceDSRC>(r, 8, false, "confidence");
  if (present & 0x04)
    a.distance = static_cast<ZoneLength>(r.get_constrained<0, 10000>("distance"));
  if (present & 0x02)
    a.class_ = static_cast<RestrictionClassID>(r.get_bits(8, "class"));
  if (present & 0x01)
    skip_regional_list(r, "AdvisorySpeed.regional");
  if (ext)
    r.skip_sequence_extensions("AdvisorySpeed");
}

// MovementEvent ::= SEQUENCE {eventState MovementPhaseState (10 values), timing?, speeds
// AdvisorySpeedList (SIZE(1..16))?, regional?, ...}
void put(UperWriter& w, const MovementEvent& e) {
  w.put_bool(false);
  w.put_bool(e.timing.has_value());
  w.put_bool(e.speeds.has_value());
  w.put_bool(false);  // regional
  put_enum(w, e.eventState, kMovementPhaseStateCount, false, "eventState");
  if (e.timing)
    put(w, *e.timing);
  if (e.speeds) {
    put_size<1, 16>(w, e.speeds->size(), "speeds");
    for (const AdvisorySpeed& a : *e.speeds)
      put(w, a);
  }
}
void get(UperReader& r, MovementEvent& e) {
  e = MovementEvent{};
  const bool ext = r.get_bool("MovementEvent");
  const auto present = r.get_bits(3, "MovementEvent");
  e.eventState = get_enum<MovementPhaseState>(r, kMovementPhaseStateCount, false, "eventState");
  if (present & 0x4)
    get(r, e.timing.emplace());
  if (present & 0x2) {
    AdvisorySpeedList& l = e.speeds.emplace();
    const std::size_t n = get_size<1, 16>(r, l.capacity(), "speeds");
    for (std::size_t i = 0; i < n && r.ok(); ++i)
      get(r, l.emplace_back());
  }
  if (present & 0x1)
    skip_regional_list(r, "MovementEvent.regional");
  if (ext)
    r.skip_sequence_extensions("MovementEvent");
}

// ConnectionManeuverAssist ::= SEQUENCE {connectionID (0..255), queueLength ZoneLength?,
// availableStorageLength ZoneLength?, waitOnStop BOOLEAN?, pedBicycleDetect BOOLEAN?,
// regional?, ...}
void put(UperWriter& w, const ConnectionManeuverAssist& c) {
  w.put_bool(false);
  w.put_bool(c.queueLength.has_value());
  w.put_bool(c.availableStorageLength.has_value());
  w.put_bool(c.waitOnStop.has_value());
  w.put_bool(c.pedBicycleDetect.has_value());
  w.put_bool(false);  // regional
  w.put_bits(c.connectionID, 8);
  if (c.queueLength)
    w.put_constrained<0, 10000>(*c.queueLength, "queueLength");
  if (c.availableStorageLength)
    w.put_constrained<0, 10000>(*c.availableStorageLength, "availableStorageLength");
  if (c.waitOnStop)
    w.put_bool(*c.waitOnStop);
  if (c.pedBicycleDetect)
    w.put_bool(*c.pedBicycleDetect);
}
void get(UperReader& r, ConnectionManeuverAssist& c) {
  c = ConnectionManeuverAssist{};
  const bool ext = r.get_bool("ConnectionManeuverAssist");
  const auto present = r.get_bits(5, "ConnectionManeuverAssist");
  c.connectionID = static_cast<LaneConnectionID>(r.get_bits(8, "connectionID"));
  if (present & 0x10)
    c.queueLength = static_cast<ZoneLength>(r.get_constrained<0, 10000>("queueLength"));
  if (present & 0x08)
    c.availableStorageLength =
        static_cast<ZoneLength>(r.get_constrained<0, 10000>("availableStorageLength"));
  if (present & 0x04)
    c.waitOnStop = r.get_bool("waitOnStop");
  if (present & 0x02)
    c.pedBicycleDetect = r.get_bool("pedBicycleDetect");
  if (present & 0x01)
    skip_regional_list(r, "ConnectionManeuverAssist.regional");
  if (ext)
    r.skip_sequence_extensions("ConnectionManeuverAssist");
}

// ManeuverAssistList ::= SEQUENCE (SIZE(1..16)) OF ConnectionManeuverAssist
void put(UperWriter& w, const ManeuverAssistList& l) {
  put_size<1, 16>(w, l.size(), "maneuverAssistList");
  for (const ConnectionManeuverAssist& c : l)
    put(w, c);
}
void get(UperReader& r, ManeuverAssistList& l) {
  l.clear();
  const std::size_t n = get_size<1, 16>(r, l.capacity(), "maneuverAssistList");
  for (std::size_t i = 0; i < n && r.ok(); ++i)
    get(r, l.emplace_back());
}

// MovementState ::= SEQUENCE {movementName?, signalGroup SignalGroupID (0..255),
// state-time-speed MovementEventList (SIZE(1..16)), maneuverAssistList?, regional?, ...}
void put(UperWriter& w, const MovementState& s) {
  w.put_bool(false);
  w.put_bool(s.movementName.has_value());
  w.put_bool(s.maneuverAssistList.has_value());
  w.put_bool(false);  // regional
  if (s.movementName)
    put(w, *s.movementName, "movementName");
  w.put_bits(s.signalGroup, 8);
  put_size<1, 16>(w, s.state_time_speed.size(), "state-time-speed");
  for (const MovementEvent& e : s.state_time_speed)
    put(w, e);
  if (s.maneuverAssistList)
    put(w, *s.maneuverAssistList);
}
void get(UperReader& r, MovementState& s) {
  const bool ext = r.get_bool("MovementState");
  const auto present = r.get_bits(3, "MovementState");
  s.movementName.reset();
  s.maneuverAssistList.reset();
  s.state_time_speed.clear();
  if (present & 0x4)
    get(r, s.movementName.emplace(), "movementName");
  s.signalGroup = static_cast<SignalGroupID>(r.get_bits(8, "signalGroup"));
  const std::size_t n = get_size<1, 16>(r, s.state_time_speed.capacity(), "state-time-speed");
  for (std::size_t i = 0; i < n && r.ok(); ++i)
    get(r, s.state_time_speed.append_for_overwrite());  // get() assigns every member
  if (present & 0x2)
    get(r, s.maneuverAssistList.emplace());
  if (present & 0x1)
    skip_regional_list(r, "MovementState.regional");
  if (ext)
    r.skip_sequence_extensions("MovementState");
}

// IntersectionState ::= SEQUENCE {name?, id, revision MsgCount, status
// IntersectionStatusObject (SIZE(16)), moy MinuteOfTheYear?, timeStamp DSecond?, enabledLanes
// EnabledLaneList (SIZE(1..16))?, states MovementList (SIZE(1..255)), maneuverAssistList?,
// regional?, ...}
void put(UperWriter& w, const IntersectionState& s) {
  w.put_bool(false);
  w.put_bool(s.name.has_value());
  w.put_bool(s.moy.has_value());
  w.put_bool(s.timeStamp.has_value());
  w.put_bool(s.enabledLanes.has_value());
  w.put_bool(s.maneuverAssistList.has_value());
  w.put_bool(false);  // regional
  if (s.name)
    put(w, *s.name, "name");
  put(w, s.id);
  put_msg_count(w, s.revision, "revision");
  put_named_bits(w, s.status, 16, "status");
  if (s.moy)
    put_moy(w, *s.moy, "moy");
  if (s.timeStamp)
    w.put_bits(*s.timeStamp, 16);
  if (s.enabledLanes) {
    put_size<1, 16>(w, s.enabledLanes->size(), "enabledLanes");
    for (LaneID l : *s.enabledLanes)
      w.put_bits(l, 8);
  }
  put_size<1, 255>(w, s.states.size(), "states");
  for (const MovementState& m : s.states)
    put(w, m);
  if (s.maneuverAssistList)
    put(w, *s.maneuverAssistList);
}
void get(UperReader& r, IntersectionState& s) {
  const bool ext = r.get_bool("IntersectionState");
  const auto present = r.get_bits(6, "IntersectionState");
  s.name.reset();
  s.moy.reset();
  s.timeStamp.reset();
  s.enabledLanes.reset();
  s.maneuverAssistList.reset();
  s.states.clear();
  if (present & 0x20)
    get(r, s.name.emplace(), "name");
  get(r, s.id);
  s.revision = get_msg_count(r, "revision");
  s.status = static_cast<IntersectionStatusObject>(get_named_bits(r, 16, "status"));
  if (present & 0x10)
    s.moy = get_moy(r, "moy");
  if (present & 0x08)
    s.timeStamp = static_cast<DSecond>(r.get_bits(16, "timeStamp"));
  if (present & 0x04) {
    EnabledLaneList& l = s.enabledLanes.emplace();
    const std::size_t n = get_size<1, 16>(r, l.capacity(), "enabledLanes");
    for (std::size_t i = 0; i < n && r.ok(); ++i)
      l.push_back(static_cast<LaneID>(r.get_bits(8, "enabledLanes")));
  }
  const std::size_t n = get_size<1, 255>(r, s.states.capacity(), "states");
  for (std::size_t i = 0; i < n && r.ok(); ++i)
    get(r, s.states.append_for_overwrite());  // get() assigns every member
  if (present & 0x02)
    get(r, s.maneuverAssistList.emplace());
  if (present & 0x01)
    skip_regional_list(r, "IntersectionState.regional");
  if (ext)
    r.skip_sequence_extensions("IntersectionState");
}

void put(UperWriter& w, const Spatem& m) {
  w.put_bits(m.header.protocolVersion, 8);
  w.put_bits(m.header.messageID, 8);
  w.put_bits(m.header.stationID, 32);
  // SPAT ::= SEQUENCE {timeStamp?, name?, intersections (SIZE(1..32)), regional?, ...}
  const SPAT& s = m.spat;
  w.put_bool(false);
  w.put_bool(s.timeStamp.has_value());
  w.put_bool(s.name.has_value());
  w.put_bool(false);  // regional
  if (s.timeStamp)
    put_moy(w, *s.timeStamp, "timeStamp");
  if (s.name)
    put(w, *s.name, "name");
  put_size<1, 32>(w, s.intersections.size(), "intersections");
  for (const IntersectionState& i : s.intersections)
    put(w, i);
}

void get(UperReader& r, Spatem& m) {
  ItsPduHeader& h = m.header;
  h.protocolVersion = static_cast<std::uint8_t>(r.get_bits(8, "protocolVersion"));
  h.messageID = static_cast<std::uint8_t>(r.get_bits(8, "messageID"));
  h.stationID = static_cast<StationID>(r.get_bits(32, "stationID"));
  if (!r.ok())
    return;
  if (h.messageID != kMessageIdSpatem) {
    r.fail_at(Error::kWrongMessageId, "messageID", h.messageID, 8);
    return;
  }
  if (h.protocolVersion != kProtocolVersion) {
    r.fail_at(Error::kUnsupportedVersion, "protocolVersion", h.protocolVersion, 0);
    return;
  }
  SPAT& s = m.spat;
  const bool ext = r.get_bool("SPAT");
  const auto present = r.get_bits(3, "SPAT");
  s.timeStamp.reset();
  s.name.reset();
  s.intersections.clear();
  if (present & 0x4)
    s.timeStamp = get_moy(r, "timeStamp");
  if (present & 0x2)
    get(r, s.name.emplace(), "name");
  const std::size_t n = get_size<1, 32>(r, s.intersections.capacity(), "intersections");
  for (std::size_t i = 0; i < n && r.ok(); ++i)
    get(r, s.intersections.append_for_overwrite());  // get() assigns every member
  if (present & 0x1)
    skip_regional_list(r, "SPAT.regional");
  if (ext)
    r.skip_sequence_extensions("SPAT");
}

}  // namespace

Expected<std::size_t, CodecError> encode(const Spatem& spatem, std::span<std::uint8_t> out) {
  if (spatem.header.protocolVersion != kProtocolVersion)
    return Unexpected<CodecError>{CodecError{Error::kUnsupportedVersion, "protocolVersion",
                                             spatem.header.protocolVersion, 0}};
  if (spatem.header.messageID != kMessageIdSpatem)
    return Unexpected<CodecError>{
        CodecError{Error::kWrongMessageId, "messageID", spatem.header.messageID, 8}};
  UperWriter w(out);
  put(w, spatem);
  const std::size_t n = w.finish();
  if (!w.ok())
    return Unexpected<CodecError>{w.error()};
  return n;
}

Expected<std::vector<std::uint8_t>, CodecError> encode(const Spatem& spatem) {
  // Most SPATEMs are a few hundred bytes: try a small buffer before the largest one.
  auto small = encode_to_vector(spatem, 4096);
  if (small || small.error().code != Error::kBufferTooSmall)
    return small;
  return encode_to_vector(spatem, kSpatemMaxEncodedSize);
}

Expected<std::size_t, CodecError> decode(std::span<const std::uint8_t> bytes, Spatem& out) {
  return decode_whole(bytes, out, "SPATEM", [](UperReader& r, Spatem& m) { get(r, m); });
}

Expected<Spatem, CodecError> decode_spatem(std::span<const std::uint8_t> bytes) {
  return decode_value<Spatem>(bytes);
}

}  // namespace tb::its::messages
