#include "its-station/rsu/mapem_builder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <utility>

#include "common/map/opendrive/queries.hpp"

namespace tb::its::rsu {

namespace odr = map::odr;
namespace msg = messages;

namespace {

constexpr double kPi = std::numbers::pi;

struct Point {
  double x = 0.0, y = 0.0;
};

std::string junction_path(const std::string& id) {
  return "junction[@id='" + id + "']";
}

double distance_to_segment(const Point& p, const Point& a, const Point& b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double len2 = dx * dx + dy * dy;
  double u = len2 > 0.0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0.0;
  u = std::clamp(u, 0.0, 1.0);
  return std::hypot(p.x - (a.x + u * dx), p.y - (a.y + u * dy));
}

// Douglas-Peucker: the fewest nodes that keep the lane centre within the tolerance, so straight
// lanes are two nodes and curves get as many as their bend needs.
void simplify(const std::vector<Point>& pts, std::size_t first, std::size_t last, double tol,
              std::vector<bool>& keep) {
  if (last <= first + 1)
    return;
  double worst = -1.0;
  std::size_t at = first;
  for (std::size_t i = first + 1; i < last; ++i) {
    const double d = distance_to_segment(pts[i], pts[first], pts[last]);
    if (d > worst) {
      worst = d;
      at = i;
    }
  }
  if (worst <= tol)
    return;
  keep[at] = true;
  simplify(pts, first, at, tol, keep);
  simplify(pts, at, last, tol, keep);
}

double wrap(double a) {
  while (a > kPi)
    a -= 2 * kPi;
  while (a <= -kPi)
    a += 2 * kPi;
  return a;
}

// The lane centre from s0 in direction dir (+1 along s, -1 against) for at most max_len metres,
// sampled every step; sampling stops where the lane ends (a section without it).
std::vector<Point> sample_lane(const odr::RoadNetwork& net, int road, int lane, double s0, int dir,
                               double max_len, double step) {
  const odr::Road& r = net.roads[static_cast<std::size_t>(road)];
  const double available = dir < 0 ? s0 : r.length - s0;
  const double len = std::max(0.0, std::min(max_len, available));
  const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
  std::vector<Point> pts;
  for (int k = 0; k <= n; ++k) {
    const double s = std::clamp(s0 + dir * std::min(len, k * step), 0.0, r.length);
    try {
      const odr::SurfacePose p = odr::lane_pose(net, road, lane, s);
      pts.push_back({p.x, p.y});
    } catch (const odr::MapError&) {
      break;  // the lane ends here (or changes its id in the next section)
    }
  }
  return pts;
}

double lane_width(const odr::Road& r, int lane, double s) {
  const std::size_t sec = r.section_index(s);
  const odr::LaneBorders b = r.borders(sec, s);
  return std::fabs(b.outer(lane) - b.inner(lane));
}

// A lane's own <speed> where it holds at s, else the road type's (m/s).
std::optional<double> speed_limit(const odr::Road& r, int lane, double s) {
  const std::size_t sec = r.section_index(s);
  if (const odr::Lane* l = r.sections[sec].lane(lane); l != nullptr) {
    std::optional<double> v;
    for (const odr::SpeedLimit& sl : l->speeds)
      if (r.sections[sec].s + sl.s <= s)
        v = sl.max;
    if (v)
      return v;
  }
  return r.speed_limit(s);
}

// FNV-1a: the revision must change when the map does and stay while it does not (ISO TS 19091
// MsgCount revision), so it is derived from the content rather than counted.
std::uint32_t fnv1a(const std::vector<std::uint8_t>& bytes) {
  std::uint32_t h = 2166136261u;
  for (const std::uint8_t b : bytes) {
    h ^= b;
    h *= 16777619u;
  }
  return h;
}

struct EgressLane {
  int road = -1;
  int lane = 0;
  double s = 0.0;  ///< the junction end
  int dir = 1;     ///< travel direction along s
};

}  // namespace

geodesy::Enu junction_centre(const odr::RoadNetwork& net, std::size_t junction) {
  const odr::Junction& j = net.junctions.at(junction);
  double x = 0.0, y = 0.0, z = 0.0;
  int n = 0;
  for (const odr::Road& r : net.roads) {
    if (r.junction_index != static_cast<int>(junction))
      continue;
    const odr::SurfacePose p = r.surface(0.0, 0.0);
    x += p.x;
    y += p.y;
    z += p.z;
    ++n;
  }
  if (n == 0)
    throw odr::MapError(net.source, junction_path(j.id), "the junction has no connecting roads");
  return {x / n, y / n, z / n};
}

MapemBuilder::MapemBuilder(const odr::RoadNetwork& net, const odr::SignalLayout& layout,
                           const geodesy::Georeferencing& geo, MapemOptions options)
    : net_(net), layout_(layout), geo_(geo), options_(options) {}

IntersectionMap MapemBuilder::build(const std::string& junction_id) const {
  const std::string path = junction_path(junction_id);
  const odr::SignalisedJunction* sj = layout_.junction(junction_id);
  if (sj == nullptr)
    throw odr::MapError(net_.source, path,
                        net_.junction_index(junction_id) < 0
                            ? "no such junction"
                            : "the junction has no traffic lights (no controller's signal "
                              "governs a lane into it)");
  const std::size_t jx = sj->junction;
  const odr::Junction& junction = net_.junctions[jx];
  const int jxi = static_cast<int>(jx);

  // ---- reference point: the junction's centre, and the frame's grid north there ----------
  const geodesy::Enu centre = junction_centre(net_, jx);
  const geodesy::Geodetic ref_geo = geo_.to_geodetic(centre);
  // A projected map's grid north differs from true north by the meridian convergence; MapData
  // offsets are east/north (ISO TS 19091 NodeOffsetPointXY), so they are turned by it.
  const double gamma = wrap(geo_.heading_deg(centre, kPi / 2) * kPi / 180.0);
  const double cg = std::cos(gamma), sg = std::sin(gamma);
  auto to_cm = [&](const Point& p) {
    const double e = p.x - centre.east, n = p.y - centre.north;
    const double east = e * cg + n * sg, north = -e * sg + n * cg;
    return std::pair<std::int32_t, std::int32_t>{
        static_cast<std::int32_t>(std::lround(east * 100)),
        static_cast<std::int32_t>(std::lround(north * 100))};
  };

  // ---- arms: the roads that touch the junction, numbered 1.. by file order (ApproachID) -----
  std::map<int, msg::ApproachID> arm_of;
  std::vector<EgressLane> egress;
  for (std::size_t ri = 0; ri < net_.roads.size(); ++ri) {
    const odr::Road& r = net_.roads[ri];
    if (r.junction_index >= 0)
      continue;
    for (const bool at_start : {true, false}) {
      const std::optional<odr::RoadLink>& link = at_start ? r.predecessor : r.successor;
      if (!link || !link->to_junction || link->index != jxi)
        continue;
      if (!arm_of.contains(static_cast<int>(ri)))
        arm_of.emplace(static_cast<int>(ri), static_cast<msg::ApproachID>(arm_of.size() + 1));
      const double s = at_start ? 0.0 : r.length;
      const odr::LaneSection& sec = r.sections[r.section_index(s)];
      // Lanes that leave the junction at this end: along s from the start, against s at the end.
      std::vector<const odr::Lane*> lanes;
      for (const odr::Lane& l : sec.right)
        lanes.push_back(&l);
      for (const odr::Lane& l : sec.left)
        lanes.push_back(&l);
      for (const odr::Lane* l : lanes)
        if (l->drivable && r.forward(l->id) == at_start)
          egress.push_back({static_cast<int>(ri), l->id, s, at_start ? 1 : -1});
    }
  }
  auto arm = [&](int road) -> std::optional<msg::ApproachID> {
    const auto it = arm_of.find(road);
    if (it == arm_of.end() || it->second > 15)  // ApproachID (0..15)
      return std::nullopt;
    return it->second;
  };

  // ---- ingress lanes: every approach of this junction, by road then |lane| ------------------
  std::vector<const odr::SignalApproach*> approaches;
  for (const odr::SignalApproach& a : layout_.approaches())
    if (a.junction == jx)
      approaches.push_back(&a);
  std::sort(approaches.begin(), approaches.end(), [](const auto* a, const auto* b) {
    return std::pair(a->road, std::abs(a->lane)) < std::pair(b->road, std::abs(b->lane));
  });
  std::sort(egress.begin(), egress.end(), [](const EgressLane& a, const EgressLane& b) {
    return std::pair(a.road, std::abs(a.lane)) < std::pair(b.road, std::abs(b.lane));
  });
  if (approaches.size() + egress.size() > msg::kLanesMax)
    throw odr::MapError(net_.source, path,
                        "the junction has " + std::to_string(approaches.size() + egress.size()) +
                            " lanes; a MAPEM holds " + std::to_string(msg::kLanesMax));

  auto result_mapem = std::make_shared<msg::Mapem>();
  msg::Mapem& mapem = *result_mapem;
  IntersectionMap out;
  out.intersection_id = sj->intersection_id;

  mapem.map.layerType = msg::LayerType::intersectionData;
  mapem.map.intersections.emplace();
  msg::IntersectionGeometry& ig = mapem.map.intersections->emplace_back();
  if (!junction.name.empty()) {
    std::string name;
    for (const char c : junction.name)  // IA5String: 7-bit characters only
      if (static_cast<unsigned char>(c) < 0x80 && name.size() < 63)
        name.push_back(c);
    if (!name.empty())
      ig.name = msg::char_string<63>(name.c_str());
  }
  ig.id.id = sj->intersection_id;
  ig.refPoint.lat = static_cast<msg::Latitude>(std::lround(ref_geo.latitude_deg * 1e7));
  ig.refPoint.long_ = static_cast<msg::Longitude>(std::lround(ref_geo.longitude_deg * 1e7));
  const long elevation_dm = std::lround(ref_geo.altitude_m * 10);
  if (elevation_dm >= -4095 && elevation_dm <= 61439)
    ig.refPoint.elevation = static_cast<msg::Elevation>(elevation_dm);

  auto node_list = [&](const std::vector<Point>& pts, bool stop_line, double width_m,
                       msg::LaneWidth default_width, const std::string& what) {
    if (pts.size() < 2)
      throw odr::MapError(net_.source, path, what + ": less than two points of lane centre");
    std::vector<bool> keep(pts.size(), false);
    keep.front() = keep.back() = true;
    double tol = options_.node_tolerance_m;
    std::vector<std::size_t> idx;
    for (;;) {
      std::fill(keep.begin(), keep.end(), false);
      keep.front() = keep.back() = true;
      simplify(pts, 0, pts.size() - 1, tol, keep);
      idx.clear();
      for (std::size_t i = 0; i < pts.size(); ++i)
        if (keep[i])
          idx.push_back(i);
      if (idx.size() <= msg::kNodesMax)
        break;
      tol *= 2;  // a lane too winding for 63 nodes: coarser, never cut short
    }
    msg::NodeSetXY nodes;
    std::pair<std::int32_t, std::int32_t> prev{0, 0};
    for (std::size_t k = 0; k < idx.size(); ++k) {
      // Offsets from rounded absolute positions, so rounding never accumulates along the lane.
      const auto abs_cm = to_cm(pts[idx[k]]);
      msg::NodeXY& node = nodes.emplace_back();
      node.delta = msg::node_xy(abs_cm.first - prev.first, abs_cm.second - prev.second);
      prev = abs_cm;
      if (k == 0) {
        msg::NodeAttributeSetXY attrs;
        bool any = false;
        if (stop_line) {
          attrs.localNode.emplace();
          attrs.localNode->push_back(msg::NodeAttributeXY::stopLine);
          any = true;
        }
        const long dw = std::lround(width_m * 100) - default_width;
        if (dw != 0) {
          attrs.dWidth = static_cast<std::int16_t>(std::clamp(dw, -512L, 511L));
          any = true;
        }
        if (any)
          node.attributes = attrs;
      }
    }
    return nodes;
  };

  if (approaches.empty())
    throw odr::MapError(net_.source, path, "no lane enters the junction under a traffic light");
  // laneWidth: the first ingress lane's at its stop line; other widths as the first node's dWidth.
  const odr::SignalApproach& first = *approaches.front();
  const auto default_width = static_cast<msg::LaneWidth>(std::lround(
      lane_width(net_.roads[static_cast<std::size_t>(first.road)], first.lane, first.stop_s) *
      100));
  ig.laneWidth = default_width;

  msg::LaneID next_id = 1;
  std::vector<msg::LaneID> egress_ids;
  std::vector<double> egress_heading;

  // Egress lanes are numbered after the ingress lanes but built first so that connections can
  // name them.
  const auto first_egress_id = static_cast<msg::LaneID>(approaches.size() + 1);
  std::vector<msg::GenericLane> egress_lanes;
  for (std::size_t e = 0; e < egress.size(); ++e) {
    const EgressLane& el = egress[e];
    const odr::Road& r = net_.roads[static_cast<std::size_t>(el.road)];
    const std::vector<Point> pts = sample_lane(net_, el.road, el.lane, el.s, el.dir,
                                               options_.max_lane_length_m, options_.sample_step_m);
    const std::string what = "egress lane " + std::to_string(el.lane) + " of road " + r.id;
    msg::GenericLane gl;
    gl.laneID = static_cast<msg::LaneID>(first_egress_id + e);
    gl.egressApproach = arm(el.road);
    gl.laneAttributes.directionalUse = msg::lane_direction::kEgressPath;
    gl.laneAttributes.sharedWith = msg::lane_sharing::kIndividualMotorizedVehicleTraffic;
    gl.laneAttributes.laneType.choice = msg::LaneTypeAttributes::Choice::vehicle;
    gl.nodeList = node_list(pts, false, lane_width(r, el.lane, el.s), default_width, what);
    egress_lanes.push_back(gl);
    egress_ids.push_back(gl.laneID);
    egress_heading.push_back(std::atan2(pts[1].y - pts[0].y, pts[1].x - pts[0].x));
    out.lanes.push_back({gl.laneID, false, el.road, el.lane, pts[0].x, pts[0].y});
  }
  auto egress_index = [&](int road, int lane) -> int {
    for (std::size_t e = 0; e < egress.size(); ++e)
      if (egress[e].road == road && egress[e].lane == lane)
        return static_cast<int>(e);
    return -1;
  };

  std::optional<double> min_speed;
  msg::LaneConnectionID next_connection = 0;
  for (const odr::SignalApproach* a : approaches) {
    const odr::Road& r = net_.roads[static_cast<std::size_t>(a->road)];
    const int dir = r.forward(a->lane) ? -1 : 1;  // upstream: against the direction of travel
    const std::vector<Point> pts = sample_lane(net_, a->road, a->lane, a->stop_s, dir,
                                               options_.max_lane_length_m, options_.sample_step_m);
    const std::string what = "ingress lane " + std::to_string(a->lane) + " of road " + r.id;
    msg::GenericLane& gl = ig.laneSet.emplace_back();
    gl.laneID = next_id++;
    gl.ingressApproach = arm(a->road);
    gl.laneAttributes.directionalUse = msg::lane_direction::kIngressPath;
    gl.laneAttributes.sharedWith = msg::lane_sharing::kIndividualMotorizedVehicleTraffic;
    gl.laneAttributes.laneType.choice = msg::LaneTypeAttributes::Choice::vehicle;
    gl.nodeList = node_list(pts, true, lane_width(r, a->lane, a->stop_s), default_width, what);
    out.lanes.push_back({gl.laneID, true, a->road, a->lane, pts[0].x, pts[0].y});
    if (const std::optional<double> v = speed_limit(r, a->lane, a->stop_s);
        v && std::isfinite(*v) && *v > 0)
      min_speed = min_speed ? std::min(*min_speed, *v) : *v;

    // connectsTo: each connecting road that this lane links into, followed to the lane it
    // leaves the junction on.
    msg::AllowedManeuvers lane_maneuvers = 0;
    for (const odr::Connection& c : junction.connections) {
      if (c.incoming_index != a->road || c.connecting_index < 0)
        continue;
      for (const odr::LaneLink& ll : c.lane_links) {
        if (ll.from != a->lane)
          continue;
        const odr::Road& cr = net_.roads[static_cast<std::size_t>(c.connecting_index)];
        const bool along = c.contact != odr::ContactPoint::kEnd;
        std::optional<int> lane = ll.to;
        // Through the connecting road's sections to its far end.
        const std::size_t ns = cr.sections.size();
        for (std::size_t k = 0; k < ns && lane; ++k) {
          const odr::LaneSection& sec = cr.sections[along ? k : ns - 1 - k];
          const odr::Lane* l = sec.lane(*lane);
          lane = l == nullptr ? std::nullopt : (along ? l->successor : l->predecessor);
        }
        const std::optional<odr::RoadLink>& far = along ? cr.successor : cr.predecessor;
        if (!lane || !far || far->to_junction || far->index < 0)
          continue;  // a connecting road that leads nowhere: no egress lane to name
        const int e = egress_index(far->index, *lane);
        if (e < 0)
          continue;
        if (gl.connectsTo && gl.connectsTo->full())
          throw odr::MapError(net_.source, path,
                              what + " has more than 16 connections (ConnectsToList)");
        const double turn = wrap(egress_heading[static_cast<std::size_t>(e)] - a->stop.heading);
        msg::AllowedManeuvers m = msg::allowed_maneuvers::kManeuverStraightAllowed;
        if (std::fabs(turn) > 3 * kPi / 4)
          m = msg::allowed_maneuvers::kManeuverUTurnAllowed;
        else if (turn > kPi / 4)
          m = msg::allowed_maneuvers::kManeuverLeftAllowed;
        else if (turn < -kPi / 4)
          m = msg::allowed_maneuvers::kManeuverRightAllowed;
        lane_maneuvers |= m;
        if (!gl.connectsTo)
          gl.connectsTo.emplace();
        msg::Connection& conn = gl.connectsTo->emplace_back();
        conn.connectingLane.lane = egress_ids[static_cast<std::size_t>(e)];
        conn.connectingLane.maneuver = m;
        conn.signalGroup = static_cast<msg::SignalGroupID>(a->signal_group);
        conn.connectionID = next_connection++;
      }
    }
    if (lane_maneuvers != 0)
      gl.maneuvers = lane_maneuvers;
  }
  for (const msg::GenericLane& gl : egress_lanes)
    ig.laneSet.push_back(gl);
  if (min_speed) {
    // The lowest of the approaches' limits: one list holds for the whole intersection.
    ig.speedLimits.emplace();
    ig.speedLimits->push_back(
        {msg::SpeedLimitType::vehicleMaxSpeed,
         static_cast<msg::Velocity>(std::clamp(std::lround(*min_speed / 0.02), 0L, 8190L))});
  }
  std::sort(out.lanes.begin(), out.lanes.end(),
            [](const MappedLane& a, const MappedLane& b) { return a.lane_id < b.lane_id; });

  // Revision from the content with revision 0, then the final encoding.
  auto encoded = msg::encode(mapem);
  if (!encoded)
    throw odr::MapError(net_.source, path,
                        "the MAPEM does not encode: " + asn1::to_string(encoded.error()));
  out.revision = static_cast<msg::MsgCount>(fnv1a(*encoded) % 128);
  mapem.map.msgIssueRevision = out.revision;
  ig.revision = out.revision;
  encoded = msg::encode(mapem);
  if (!encoded)
    throw odr::MapError(net_.source, path, "the MAPEM does not encode");
  out.encoded = std::move(*encoded);
  out.mapem = std::move(result_mapem);
  return out;
}

}  // namespace tb::its::rsu
