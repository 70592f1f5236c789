#include "its-station/messages/mapem.hpp"

#include "its-station/messages/dsrc_codec.hpp"
#include "its-station/messages/message_codec.hpp"

namespace tb::its::messages {

using asn1::Error;
using asn1::UperReader;
using asn1::UperWriter;
using namespace detail;

NodeOffsetPointXY node_xy(std::int32_t x, std::int32_t y) {
  using C = NodeOffsetPointXY::Choice;
  // node-XY1..6 hold Offset-B10, B11, B12, B13, B14 and B16.
  static constexpr unsigned kBits[] = {10, 11, 12, 13, 14, 16};
  for (unsigned i = 0; i < 6; ++i) {
    const std::int32_t lo = -(1 << (kBits[i] - 1));
    const std::int32_t hi = (1 << (kBits[i] - 1)) - 1;
    if (x >= lo && x <= hi && y >= lo && y <= hi)
      return {static_cast<C>(i), x, y};
  }
  return {C::node_XY6, x, y};
}

namespace {

using detail::get;
using detail::put;

// Position3D ::= SEQUENCE {lat Latitude, long Longitude, elevation Elevation (-4096..61439)?,
// regional?, ...}
void put(UperWriter& w, const Position3D& p) {
  w.put_bool(false);
  w.put_bool(p.elevation.has_value());
  w.put_bool(false);  // regional
  w.put_constrained<-900000000, 900000001>(p.lat, "lat");
  w.put_constrained<-1800000000, 1800000001>(p.long_, "long");
  if (p.elevation)
    w.put_constrained<-4096, 61439>(*p.elevation, "elevation");
}
void get(UperReader& r, Position3D& p) {
  const bool ext = r.get_bool("refPoint");
  const auto present = r.get_bits(2, "refPoint");
  p.lat = static_cast<Latitude>(r.get_constrained<-900000000, 900000001>("lat"));
  p.long_ = static_cast<Longitude>(r.get_constrained<-1800000000, 1800000001>("long"));
  p.elevation.reset();
  if (present & 0x2)
    p.elevation = static_cast<Elevation>(r.get_constrained<-4096, 61439>("elevation"));
  if (present & 0x1)
    skip_regional_list(r, "Position3D.regional");
  if (ext)
    r.skip_sequence_extensions("refPoint");
}

// SpeedLimitList ::= SEQUENCE (SIZE(1..9)) OF RegulatorySpeedLimit {type SpeedLimitType
// (13 roots, ...), speed Velocity (0..8191)}
void put(UperWriter& w, const SpeedLimitList& l) {
  put_size<1, 9>(w, l.size(), "speedLimits");
  for (const RegulatorySpeedLimit& s : l) {
    put_enum(w, s.type, 13, true, "type");
    w.put_constrained<0, 8191>(s.speed, "speed");
  }
}
void get(UperReader& r, SpeedLimitList& l) {
  l.clear();
  const std::size_t n = get_size<1, 9>(r, l.capacity(), "speedLimits");
  for (std::size_t i = 0; i < n && r.ok(); ++i) {
    RegulatorySpeedLimit& s = l.emplace_back();
    s.type = get_enum<SpeedLimitType>(r, 13, true, "type");
    s.speed = static_cast<Velocity>(r.get_bits(13, "speed"));
  }
}

// LaneAttributes ::= SEQUENCE {directionalUse LaneDirection (SIZE(2)), sharedWith LaneSharing
// (SIZE(10)), laneType LaneTypeAttributes (CHOICE of 8, ...), regional?}, no extension marker.
// The alternatives are BIT STRINGs of SIZE(16), but LaneAttributes-Vehicle (SIZE(8, ...)): an
// extension bit, then 8 bits (X.691 16.6).
void put(UperWriter& w, const LaneAttributes& a) {
  w.put_bool(false);  // regional
  put_named_bits(w, a.directionalUse, 2, "directionalUse");
  put_named_bits(w, a.sharedWith, 10, "sharedWith");
  const auto idx = static_cast<unsigned>(a.laneType.choice);
  w.put_bool(false);
  w.put_constrained<0, kLaneTypeAttributesCount - 1>(idx, "laneType");
  if (a.laneType.choice == LaneTypeAttributes::Choice::vehicle) {
    w.put_bool(false);
    put_named_bits(w, a.laneType.bits, 8, "laneType");
  } else {
    put_named_bits(w, a.laneType.bits, 16, "laneType");
  }
}
void get(UperReader& r, LaneAttributes& a) {
  const bool has_regional = r.get_bool("laneAttributes");
  a.directionalUse = static_cast<LaneDirection>(get_named_bits(r, 2, "directionalUse"));
  a.sharedWith = static_cast<LaneSharing>(get_named_bits(r, 10, "sharedWith"));
  const unsigned idx = get_choice_ext(r, kLaneTypeAttributesCount, "laneType");
  a.laneType.choice = static_cast<LaneTypeAttributes::Choice>(idx);
  if (a.laneType.choice == LaneTypeAttributes::Choice::vehicle) {
    const std::size_t at = r.bit_position();
    if (r.get_bool("laneType")) {
      // A size outside the root: a later version's bits, which cannot be held.
      r.fail_at(Error::kUnknownExtension, "laneType", 0, at);
      return;
    }
    a.laneType.bits = static_cast<std::uint16_t>(get_named_bits(r, 8, "laneType"));
  } else {
    a.laneType.bits = static_cast<std::uint16_t>(get_named_bits(r, 16, "laneType"));
  }
  if (has_regional)
    skip_regional(r, "LaneAttributes.regional");
}

// NodeOffsetPointXY ::= CHOICE {node-XY1 .. node-XY6 (x, y Offset-B10 .. Offset-B16),
// node-LatLon (lon Longitude, lat Latitude), regional}, no extension marker: 3 bits of index.
void put(UperWriter& w, const NodeOffsetPointXY& d) {
  using C = NodeOffsetPointXY::Choice;
  const auto idx = static_cast<unsigned>(d.choice);
  if (idx > 6) {
    w.fail(Error::kValueOutOfRange, "delta", idx);
    return;
  }
  w.put_bits(idx, 3);
  switch (d.choice) {
    case C::node_XY1:
      w.put_constrained<-512, 511>(d.x, "x");
      w.put_constrained<-512, 511>(d.y, "y");
      break;
    case C::node_XY2:
      w.put_constrained<-1024, 1023>(d.x, "x");
      w.put_constrained<-1024, 1023>(d.y, "y");
      break;
    case C::node_XY3:
      w.put_constrained<-2048, 2047>(d.x, "x");
      w.put_constrained<-2048, 2047>(d.y, "y");
      break;
    case C::node_XY4:
      w.put_constrained<-4096, 4095>(d.x, "x");
      w.put_constrained<-4096, 4095>(d.y, "y");
      break;
    case C::node_XY5:
      w.put_constrained<-8192, 8191>(d.x, "x");
      w.put_constrained<-8192, 8191>(d.y, "y");
      break;
    case C::node_XY6:
      w.put_constrained<-32768, 32767>(d.x, "x");
      w.put_constrained<-32768, 32767>(d.y, "y");
      break;
    case C::node_LatLon:
      w.put_constrained<-1800000000, 1800000001>(d.x, "lon");
      w.put_constrained<-900000000, 900000001>(d.y, "lat");
      break;
  }
}
void get(UperReader& r, NodeOffsetPointXY& d) {
  using C = NodeOffsetPointXY::Choice;
  const std::size_t at = r.bit_position();
  const auto idx = static_cast<unsigned>(r.get_bits(3, "delta"));
  if (idx == 7) {
    if (r.ok())
      r.fail_at(Error::kUnsupported, "delta regional", 7, at);
    return;
  }
  d.choice = static_cast<C>(idx);
  switch (d.choice) {
    case C::node_XY1:
      d.x = static_cast<std::int32_t>(r.get_constrained<-512, 511>("x"));
      d.y = static_cast<std::int32_t>(r.get_constrained<-512, 511>("y"));
      break;
    case C::node_XY2:
      d.x = static_cast<std::int32_t>(r.get_constrained<-1024, 1023>("x"));
      d.y = static_cast<std::int32_t>(r.get_constrained<-1024, 1023>("y"));
      break;
    case C::node_XY3:
      d.x = static_cast<std::int32_t>(r.get_constrained<-2048, 2047>("x"));
      d.y = static_cast<std::int32_t>(r.get_constrained<-2048, 2047>("y"));
      break;
    case C::node_XY4:
      d.x = static_cast<std::int32_t>(r.get_constrained<-4096, 4095>("x"));
      d.y = static_cast<std::int32_t>(r.get_constrained<-4096, 4095>("y"));
      break;
    case C::node_XY5:
      d.x = static_cast<std::int32_t>(r.get_constrained<-8192, 8191>("x"));
      d.y = static_cast<std::int32_t>(r.get_constrained<-8192, 8191>("y"));
      break;
    case C::node_XY6:
      d.x = static_cast<std::int32_t>(r.get_constrained<-32768, 32767>("x"));
      d.y = static_cast<std::int32_t>(r.get_constrained<-32768, 32767>("y"));
      break;
    case C::node_LatLon:
      d.x = static_cast<std::int32_t>(r.get_constrained<-1800000000, 1800000001>("lon"));
      d.y = static_cast<std::int32_t>(r.get_constrained<-900000000, 900000001>("lat"));
      break;
  }
}

// Offset-B10 ::= INTEGER (-512..511)
void put_b10(UperWriter& w, std::int16_t v, const char* f) {
  w.put_constrained<-512, 511>(v, f);
}
std::int16_t get_b10(UperReader& r, const char* f) {
  return static_cast<std::int16_t>(r.get_constrained<-512, 511>(f));
}

// NodeAttributeSetXY ::= SEQUENCE {localNode NodeAttributeXYList?, disabled, enabled
// SegmentAttributeXYList?, data LaneDataAttributeList?, dWidth, dElevation Offset-B10?,
// regional?, ...}; the lists are SIZE(1..8) of extensible enumerations.
void put(UperWriter& w, const NodeAttributeSetXY& a) {
  w.put_bool(false);
  w.put_bool(a.localNode.has_value());
  w.put_bool(a.disabled.has_value());
  w.put_bool(a.enabled.has_value());
  w.put_bool(false);  // data: not held
  w.put_bool(a.dWidth.has_value());
  w.put_bool(a.dElevation.has_value());
  w.put_bool(false);  // regional
  if (a.localNode) {
    put_size<1, 8>(w, a.localNode->size(), "localNode");
    for (NodeAttributeXY n : *a.localNode)
      put_enum(w, n, kNodeAttributeXYCount, true, "localNode");
  }
  for (const auto* l : {&a.disabled, &a.enabled}) {
    const char* f = l == &a.disabled ? "disabled" : "enabled";
    if (!*l)
      continue;
    put_size<1, 8>(w, (*l)->size(), f);
    for (SegmentAttributeXY s : **l)
      w.put_enumerated(s, kSegmentAttributeXYCount, true, f);
  }
  if (a.dWidth)
    put_b10(w, *a.dWidth, "dWidth");
  if (a.dElevation)
    put_b10(w, *a.dElevation, "dElevation");
}
void get(UperReader& r, NodeAttributeSetXY& a) {
  a = NodeAttributeSetXY{};
  const bool ext = r.get_bool("attributes");
  const auto present = r.get_bits(7, "attributes");
  if (present & 0x40) {
    auto& l = a.localNode.emplace();
    const std::size_t n = get_size<1, 8>(r, l.capacity(), "localNode");
    for (std::size_t i = 0; i < n && r.ok(); ++i)
      l.push_back(get_enum<NodeAttributeXY>(r, kNodeAttributeXYCount, true, "localNode"));
  }
  for (unsigned k = 0; k < 2; ++k) {
    if (!(present & (k == 0 ? 0x20 : 0x10)))
      continue;
    const char* f = k == 0 ? "disabled" : "enabled";
    auto& l = (k == 0 ? a.disabled : a.enabled).emplace();
    const std::size_t n = get_size<1, 8>(r, l.capacity(), f);
    for (std::size_t i = 0; i < n && r.ok(); ++i)
      l.push_back(
          static_cast<SegmentAttributeXY>(r.get_enumerated(kSegmentAttributeXYCount, true, f)));
  }
  if (present & 0x08) {
    if (r.ok())
      r.fail(Error::kUnsupported, "data", 0);
    return;
  }
  if (present & 0x04)
    a.dWidth = get_b10(r, "dWidth");
  if (present & 0x02)
    a.dElevation = get_b10(r, "dElevation");
  if (present & 0x01)
    skip_regional_list(r, "NodeAttributeSetXY.regional");
  if (ext)
    r.skip_sequence_extensions("attributes");
}

// NodeXY ::= SEQUENCE {delta, attributes?, ...}; NodeSetXY ::= SEQUENCE (SIZE(2..63)) OF NodeXY
void put(UperWriter& w, const NodeSetXY& nodes) {
  put_size<2, 63>(w, nodes.size(), "nodes");
  for (const NodeXY& n : nodes) {
    w.put_bool(false);
    w.put_bool(n.attributes.has_value());
    put(w, n.delta);
    if (n.attributes)
      put(w, *n.attributes);
  }
}
void get(UperReader& r, NodeSetXY& nodes) {
  nodes.clear();
  const std::size_t n = get_size<2, 63>(r, nodes.capacity(), "nodes");
  for (std::size_t i = 0; i < n && r.ok(); ++i) {
    NodeXY& node = nodes.emplace_back();
    const bool ext = r.get_bool("NodeXY");
    const bool has_attributes = r.get_bool("NodeXY");
    get(r, node.delta);
    if (has_attributes)
      get(r, node.attributes.emplace());
    if (ext)
      r.skip_sequence_extensions("NodeXY");
  }
}

// CHOICE {small DrivenLineOffsetSm (-2047..2047), large DrivenLineOffsetLg (-32767..32767)}
void put(UperWriter& w, const DrivenLineOffset& o, const char* f) {
  w.put_bool(o.large);
  if (o.large)
    w.put_constrained<-32767, 32767>(o.value, f);
  else
    w.put_constrained<-2047, 2047>(o.value, f);
}
void get(UperReader& r, DrivenLineOffset& o, const char* f) {
  o.large = r.get_bool(f);
  o.value = static_cast<std::int16_t>(o.large ? r.get_constrained<-32767, 32767>(f)
                                              : r.get_constrained<-2047, 2047>(f));
}

// ComputedLane ::= SEQUENCE {referenceLaneId, offsetXaxis, offsetYaxis, rotateXY Angle
// (0..28800)?, scaleXaxis, scaleYaxis Scale-B12 (-2048..2047)?, regional?, ...}
void put(UperWriter& w, const ComputedLane& c) {
  w.put_bool(false);
  w.put_bool(c.rotateXY.has_value());
  w.put_bool(c.scaleXaxis.has_value());
  w.put_bool(c.scaleYaxis.has_value());
  w.put_bool(false);  // regional
  w.put_bits(c.referenceLaneId, 8);
  put(w, c.offsetXaxis, "offsetXaxis");
  put(w, c.offsetYaxis, "offsetYaxis");
  if (c.rotateXY)
    w.put_constrained<0, 28800>(*c.rotateXY, "rotateXY");
  if (c.scaleXaxis)
    w.put_constrained<-2048, 2047>(*c.scaleXaxis, "scaleXaxis");
  if (c.scaleYaxis)
    w.put_constrained<-2048, 2047>(*c.scaleYaxis, "scaleYaxis");
}
void get(UperReader& r, ComputedLane& c) {
  c = ComputedLane{};
  const bool ext = r.get_bool("computed");
  const auto present = r.get_bits(4, "computed");
  c.referenceLaneId = static_cast<LaneID>(r.get_bits(8, "referenceLaneId"));
  get(r, c.offsetXaxis, "offsetXaxis");
  get(r, c.offsetYaxis, "offsetYaxis");
  if (present & 0x8)
    c.rotateXY = static_cast<std::uint16_t>(r.get_constrained<0, 28800>("rotateXY"));
  if (present & 0x4)
    c.scaleXaxis = static_cast<std::int16_t>(r.get_constrained<-2048, 2047>("scaleXaxis"));
  if (present & 0x2)
    c.scaleYaxis = static_cast<std::int16_t>(r.get_constrained<-2048, 2047>("scaleYaxis"));
  if (present & 0x1)
    skip_regional_list(r, "ComputedLane.regional");
  if (ext)
    r.skip_sequence_extensions("computed");
}

// Connection ::= SEQUENCE {connectingLane ConnectingLane {lane, maneuver AllowedManeuvers?},
// remoteIntersection?, signalGroup?, userClass?, connectionID?}, no extension markers
void put(UperWriter& w, const Connection& c) {
  w.put_bool(c.remoteIntersection.has_value());
  w.put_bool(c.signalGroup.has_value());
  w.put_bool(c.userClass.has_value());
  w.put_bool(c.connectionID.has_value());
  w.put_bool(c.connectingLane.maneuver.has_value());
  w.put_bits(c.connectingLane.lane, 8);
  if (c.connectingLane.maneuver)
    put_named_bits(w, *c.connectingLane.maneuver, 12, "maneuver");
  if (c.remoteIntersection)
    put(w, *c.remoteIntersection);
  if (c.signalGroup)
    w.put_bits(*c.signalGroup, 8);
  if (c.userClass)
    w.put_bits(*c.userClass, 8);
  if (c.connectionID)
    w.put_bits(*c.connectionID, 8);
}
void get(UperReader& r, Connection& c) {
  c = Connection{};
  const auto present = r.get_bits(4, "Connection");
  const bool has_maneuver = r.get_bool("connectingLane");
  c.connectingLane.lane = static_cast<LaneID>(r.get_bits(8, "lane"));
  if (has_maneuver)
    c.connectingLane.maneuver = static_cast<AllowedManeuvers>(get_named_bits(r, 12, "maneuver"));
  if (present & 0x8)
    get(r, c.remoteIntersection.emplace());
  if (present & 0x4)
    c.signalGroup = static_cast<SignalGroupID>(r.get_bits(8, "signalGroup"));
  if (present & 0x2)
    c.userClass = static_cast<RestrictionClassID>(r.get_bits(8, "userClass"));
  if (present & 0x1)
    c.connectionID = static_cast<LaneConnectionID>(r.get_bits(8, "connectionID"));
}

// GenericLane ::= SEQUENCE {laneID, name?, ingressApproach, egressApproach ApproachID
// (0..15)?, laneAttributes, maneuvers AllowedManeuvers?, nodeList NodeListXY (CHOICE {nodes,
// computed, ...}), connectsTo ConnectsToList (SIZE(1..16))?, overlays OverlayLaneList
// (SIZE(1..5))?, regional?, ...}
void put(UperWriter& w, const GenericLane& l) {
  w.put_bool(false);
  w.put_bool(l.name.has_value());
  w.put_bool(l.ingressApproach.has_value());
  w.put_bool(l.egressApproach.has_value());
  w.put_bool(l.maneuvers.has_value());
  w.put_bool(l.connectsTo.has_value());
  w.put_bool(l.overlays.has_value());
  w.put_bool(false);  // regional
  w.put_bits(l.laneID, 8);
  if (l.name)
    put(w, *l.name, "name");
  if (l.ingressApproach)
    w.put_constrained<0, 15>(*l.ingressApproach, "ingressApproach");
  if (l.egressApproach)
    w.put_constrained<0, 15>(*l.egressApproach, "egressApproach");
  put(w, l.laneAttributes);
  if (l.maneuvers)
    put_named_bits(w, *l.maneuvers, 12, "maneuvers");
  w.put_bool(false);  // NodeListXY extension bit
  w.put_bits(l.nodeList.index(), 1);
  if (const auto* nodes = std::get_if<NodeSetXY>(&l.nodeList))
    put(w, *nodes);
  else
    put(w, std::get<ComputedLane>(l.nodeList));
  if (l.connectsTo) {
    put_size<1, 16>(w, l.connectsTo->size(), "connectsTo");
    for (const Connection& c : *l.connectsTo)
      put(w, c);
  }
  if (l.overlays) {
    put_size<1, 5>(w, l.overlays->size(), "overlays");
    for (LaneID o : *l.overlays)
      w.put_bits(o, 8);
  }
}
void get(UperReader& r, GenericLane& l) {
  const bool ext = r.get_bool("GenericLane");
  const auto present = r.get_bits(7, "GenericLane");
  l.name.reset();
  l.ingressApproach.reset();
  l.egressApproach.reset();
  l.maneuvers.reset();
  l.connectsTo.reset();
  l.overlays.reset();
  l.laneID = static_cast<LaneID>(r.get_bits(8, "laneID"));
  if (present & 0x40)
    get(r, l.name.emplace(), "name");
  if (present & 0x20)
    l.ingressApproach = static_cast<ApproachID>(r.get_bits(4, "ingressApproach"));
  if (present & 0x10)
    l.egressApproach = static_cast<ApproachID>(r.get_bits(4, "egressApproach"));
  get(r, l.laneAttributes);
  if (present & 0x08)
    l.maneuvers = static_cast<AllowedManeuvers>(get_named_bits(r, 12, "maneuvers"));
  if (get_choice_ext(r, 2, "nodeList") == 0)
    get(r, std::holds_alternative<NodeSetXY>(l.nodeList) ? std::get<NodeSetXY>(l.nodeList)
                                                         : l.nodeList.emplace<NodeSetXY>());
  else
    get(r, l.nodeList.emplace<ComputedLane>());
  if (present & 0x04) {
    ConnectsToList& c = l.connectsTo.emplace();
    const std::size_t n = get_size<1, 16>(r, c.capacity(), "connectsTo");
    for (std::size_t i = 0; i < n && r.ok(); ++i)
      get(r, c.emplace_back());
  }
  if (present & 0x02) {
    OverlayLaneList& o = l.overlays.emplace();
    const std::size_t n = get_size<1, 5>(r, o.capacity(), "overlays");
    for (std::size_t i = 0; i < n && r.ok(); ++i)
      o.push_back(static_cast<LaneID>(r.get_bits(8, "overlays")));
  }
  if (present & 0x01)
    skip_regional_list(r, "GenericLane.regional");
  if (ext)
    r.skip_sequence_extensions("GenericLane");
}

// PreemptPriorityList ::= SEQUENCE (SIZE(1..32)) OF SignalControlZone ::= SEQUENCE {zone
// RegionalExtension, ...}: skipped, as every regional extension.
void skip_preempt_priority_list(UperReader& r) {
  const auto n = r.get_constrained<1, 32>("preemptPriorityData");
  for (std::int64_t i = 0; i < n && r.ok(); ++i) {
    const bool ext = r.get_bool("SignalControlZone");
    skip_regional(r, "SignalControlZone");
    if (ext)
      r.skip_sequence_extensions("SignalControlZone");
  }
}

// IntersectionGeometry ::= SEQUENCE {name?, id, revision, refPoint, laneWidth LaneWidth
// (0..32767)?, speedLimits?, laneSet LaneList (SIZE(1..255)), preemptPriorityData?, regional?,
// ...}
void put(UperWriter& w, const IntersectionGeometry& g) {
  w.put_bool(false);
  w.put_bool(g.name.has_value());
  w.put_bool(g.laneWidth.has_value());
  w.put_bool(g.speedLimits.has_value());
  w.put_bool(false);  // preemptPriorityData
  w.put_bool(false);  // regional
  if (g.name)
    put(w, *g.name, "name");
  put(w, g.id);
  put_msg_count(w, g.revision, "revision");
  put(w, g.refPoint);
  if (g.laneWidth)
    w.put_constrained<0, 32767>(*g.laneWidth, "laneWidth");
  if (g.speedLimits)
    put(w, *g.speedLimits);
  put_size<1, 255>(w, g.laneSet.size(), "laneSet");
  for (const GenericLane& l : g.laneSet)
    put(w, l);
}
void get(UperReader& r, IntersectionGeometry& g) {
  const bool ext = r.get_bool("IntersectionGeometry");
  const auto present = r.get_bits(5, "IntersectionGeometry");
  g.name.reset();
  g.laneWidth.reset();
  g.speedLimits.reset();
  g.laneSet.clear();
  if (present & 0x10)
    get(r, g.name.emplace(), "name");
  get(r, g.id);
  g.revision = get_msg_count(r, "revision");
  get(r, g.refPoint);
  if (present & 0x08)
    g.laneWidth = static_cast<LaneWidth>(r.get_bits(15, "laneWidth"));
  if (present & 0x04)
    get(r, g.speedLimits.emplace());
  const std::size_t n = get_size<1, 255>(r, g.laneSet.capacity(), "laneSet");
  for (std::size_t i = 0; i < n && r.ok(); ++i)
    get(r, g.laneSet.append_for_overwrite());  // get() assigns every member
  if (present & 0x02)
    skip_preempt_priority_list(r);
  if (present & 0x01)
    skip_regional_list(r, "IntersectionGeometry.regional");
  if (ext)
    r.skip_sequence_extensions("IntersectionGeometry");
}

// DataParameters ::= SEQUENCE {processMethod, processAgency, lastCheckedDate, geoidUsed
// IA5String (SIZE(1..255)) (all OPTIONAL), ...}
void put(UperWriter& w, const DataParameters& d) {
  w.put_bool(false);
  const std::optional<CharString<255>>* fields[] = {&d.processMethod, &d.processAgency,
                                                    &d.lastCheckedDate, &d.geoidUsed};
  static constexpr const char* kNames[] = {"processMethod", "processAgency", "lastCheckedDate",
                                           "geoidUsed"};
  for (const auto* f : fields)
    w.put_bool(f->has_value());
  for (unsigned i = 0; i < 4; ++i)
    if (*fields[i])
      put_ia5<1, 255>(w, **fields[i], kNames[i]);
}
void get(UperReader& r, DataParameters& d) {
  d = DataParameters{};
  const bool ext = r.get_bool("dataParameters");
  const auto present = r.get_bits(4, "dataParameters");
  std::optional<CharString<255>>* fields[] = {&d.processMethod, &d.processAgency,
                                              &d.lastCheckedDate, &d.geoidUsed};
  static constexpr const char* kNames[] = {"processMethod", "processAgency", "lastCheckedDate",
                                           "geoidUsed"};
  for (unsigned i = 0; i < 4; ++i)
    if (present & (0x8u >> i))
      get_ia5<1, 255>(r, fields[i]->emplace(), kNames[i]);
  if (ext)
    r.skip_sequence_extensions("dataParameters");
}

// RestrictionClassList ::= SEQUENCE (SIZE(1..254)) OF RestrictionClassAssignment {id, users
// SEQUENCE (SIZE(1..16)) OF RestrictionUserType (CHOICE {basicType RestrictionAppliesTo
// (14 roots, ...), regional, ...})}
void put(UperWriter& w, const RestrictionClassList& l) {
  put_size<1, 254>(w, l.size(), "restrictionList");
  for (const RestrictionClassAssignment& a : l) {
    w.put_bits(a.id, 8);
    put_size<1, 16>(w, a.users.size(), "users");
    for (RestrictionAppliesTo u : a.users) {
      w.put_bool(false);  // CHOICE extension bit
      w.put_bool(false);  // basicType
      w.put_enumerated(u, kRestrictionAppliesToCount, true, "basicType");
    }
  }
}
void get(UperReader& r, RestrictionClassList& l) {
  l.clear();
  const std::size_t n = get_size<1, 254>(r, l.capacity(), "restrictionList");
  for (std::size_t i = 0; i < n && r.ok(); ++i) {
    RestrictionClassAssignment& a = l.emplace_back();
    a.id = static_cast<RestrictionClassID>(r.get_bits(8, "id"));
    const std::size_t m = get_size<1, 16>(r, a.users.capacity(), "users");
    for (std::size_t k = 0; k < m && r.ok(); ++k) {
      const std::size_t at = r.bit_position();
      if (get_choice_ext(r, 2, "users") == 1) {
        if (r.ok())
          r.fail_at(Error::kUnsupported, "users regional", 1, at);
        return;
      }
      a.users.push_back(static_cast<RestrictionAppliesTo>(
          r.get_enumerated(kRestrictionAppliesToCount, true, "basicType")));
    }
  }
}

void put(UperWriter& w, const Mapem& m) {
  w.put_bits(m.header.protocolVersion, 8);
  w.put_bits(m.header.messageID, 8);
  w.put_bits(m.header.stationID, 32);
  const MapData& d = m.map;
  w.put_bool(false);
  w.put_bool(d.timeStamp.has_value());
  w.put_bool(d.layerType.has_value());
  w.put_bool(d.layerID.has_value());
  w.put_bool(d.intersections.has_value());
  w.put_bool(false);  // roadSegments: not held
  w.put_bool(d.dataParameters.has_value());
  w.put_bool(d.restrictionList.has_value());
  w.put_bool(false);  // regional
  if (d.timeStamp)
    put_moy(w, *d.timeStamp, "timeStamp");
  put_msg_count(w, d.msgIssueRevision, "msgIssueRevision");
  if (d.layerType)
    put_enum(w, *d.layerType, 8, true, "layerType");
  if (d.layerID)
    w.put_constrained<0, 100>(*d.layerID, "layerID");
  if (d.intersections) {
    put_size<1, 32>(w, d.intersections->size(), "intersections");
    for (const IntersectionGeometry& g : *d.intersections)
      put(w, g);
  }
  if (d.dataParameters)
    put(w, *d.dataParameters);
  if (d.restrictionList)
    put(w, *d.restrictionList);
}

void get(UperReader& r, Mapem& m) {
  ItsPduHeader& h = m.header;
  h.protocolVersion = static_cast<std::uint8_t>(r.get_bits(8, "protocolVersion"));
  h.messageID = static_cast<std::uint8_t>(r.get_bits(8, "messageID"));
  h.stationID = static_cast<StationID>(r.get_bits(32, "stationID"));
  if (!r.ok())
    return;
  if (h.messageID != kMessageIdMapem) {
    r.fail_at(Error::kWrongMessageId, "messageID", h.messageID, 8);
    return;
  }
  if (h.protocolVersion != kProtocolVersion) {
    r.fail_at(Error::kUnsupportedVersion, "protocolVersion", h.protocolVersion, 0);
    return;
  }
  MapData& d = m.map;
  const bool ext = r.get_bool("MapData");
  const auto present = r.get_bits(8, "MapData");
  d.timeStamp.reset();
  d.layerType.reset();
  d.layerID.reset();
  d.dataParameters.reset();
  // The large lists keep their storage for the next message (reuse()).
  if (!(present & 0x10))
    d.intersections.reset();
  if (!(present & 0x02))
    d.restrictionList.reset();
  if (present & 0x80)
    d.timeStamp = get_moy(r, "timeStamp");
  d.msgIssueRevision = get_msg_count(r, "msgIssueRevision");
  if (present & 0x40)
    d.layerType = get_enum<LayerType>(r, 8, true, "layerType");
  if (present & 0x20)
    d.layerID = static_cast<LayerID>(r.get_constrained<0, 100>("layerID"));
  if (present & 0x10) {
    IntersectionGeometryList& l = reuse(d.intersections);
    const std::size_t n = get_size<1, 32>(r, l.capacity(), "intersections");
    for (std::size_t i = 0; i < n && r.ok(); ++i)
      get(r, l.append_for_overwrite());  // get() assigns every member
  }
  if (present & 0x08) {
    if (r.ok())
      r.fail(Error::kUnsupported, "roadSegments", 0);
    return;
  }
  if (present & 0x04)
    get(r, d.dataParameters.emplace());
  if (present & 0x02)
    get(r, reuse(d.restrictionList));
  if (present & 0x01)
    skip_regional_list(r, "MapData.regional");
  if (ext)
    r.skip_sequence_extensions("MapData");
}

}  // namespace

Expected<std::size_t, CodecError> encode(const Mapem& mapem, std::span<std::uint8_t> out) {
  if (mapem.header.protocolVersion != kProtocolVersion)
    return Unexpected<CodecError>{
        CodecError{Error::kUnsupportedVersion, "protocolVersion", mapem.header.protocolVersion, 0}};
  if (mapem.header.messageID != kMessageIdMapem)
    return Unexpected<CodecError>{
        CodecError{Error::kWrongMessageId, "messageID", mapem.header.messageID, 8}};
  UperWriter w(out);
  put(w, mapem);
  const std::size_t n = w.finish();
  if (!w.ok())
    return Unexpected<CodecError>{w.error()};
  return n;
}

Expected<std::vector<std::uint8_t>, CodecError> encode(const Mapem& mapem) {
  // A junction's MAPEM is a few hundred bytes to a few kilobytes.
  auto small = encode_to_vector(mapem, 8192);
  if (small || small.error().code != Error::kBufferTooSmall)
    return small;
  return encode_to_vector(mapem, kMapemMaxEncodedSize);
}

Expected<std::size_t, CodecError> decode(std::span<const std::uint8_t> bytes, Mapem& out) {
  return decode_whole(bytes, out, "MAPEM", [](UperReader& r, Mapem& m) { get(r, m); });
}

Expected<Mapem, CodecError> decode_mapem(std::span<const std::uint8_t> bytes) {
  return decode_value<Mapem>(bytes);
}

}  // namespace tb::its::messages
