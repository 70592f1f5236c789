#include "common/map/describe.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "common/map/opendrive/mesh.hpp"
#include "common/map/opendrive/signal_layout.hpp"

namespace tb::map {

nlohmann::json describe(const odr::RoadNetwork& net, const OriginSource& origin) {
  using nlohmann::json;
  std::map<std::string, double> metres;  // lane length along the reference line, by type
  std::size_t connecting = 0, signals = 0, objects = 0;
  double x0 = std::numeric_limits<double>::max(), y0 = x0, z0 = x0;
  double x1 = std::numeric_limits<double>::lowest(), y1 = x1, z1 = x1;
  for (const odr::Road& r : net.roads) {
    if (r.junction != "-1")
      ++connecting;
    signals += r.signals.size();
    objects += r.objects.size();
    for (std::size_t k = 0; k < r.sections.size(); ++k) {
      const odr::LaneSection& ls = r.sections[k];
      for (const auto* side : {&ls.left, &ls.right}) {
        for (const odr::Lane& l : *side) {
          // Only where the lane has width: lanes that open or close count from/to there.
          const int n = 32;
          const double h = (ls.s_end - ls.s) / n;
          double len = 0.0;
          for (int i = 0; i < n; ++i) {
            const double s = ls.s + (i + 0.5) * h;
            const odr::LaneBorders b = r.borders(k, s);
            if (std::fabs(b.outer(l.id) - b.inner(l.id)) > 0.01)
              len += h;
          }
          metres[l.type] += len;
        }
      }
      const std::vector<double> ss = odr::sample_s(r, ls.s, ls.s_end, 0.1, 0.0, 10.0);
      for (double s : ss) {
        const odr::LaneBorders b = r.borders(k, s);
        for (double t : {b.left.empty() ? b.center : b.left.back(),
                         b.right.empty() ? b.center : b.right.back()}) {
          const odr::SurfacePose p = r.surface(s, t);
          x0 = std::min(x0, p.x);
          y0 = std::min(y0, p.y);
          z0 = std::min(z0, p.z);
          x1 = std::max(x1, p.x);
          y1 = std::max(y1, p.y);
          z1 = std::max(z1, p.z);
        }
      }
    }
  }
  json lanes = json::object();
  for (const auto& [type, m] : metres)
    lanes[type] = std::round(m * 10) / 10;
  json roads = json::array();
  for (const odr::Road& r : net.roads) {
    json j = {{"id", r.id}, {"length", r.length}, {"junction", r.junction}};
    if (!r.name.empty())
      j["name"] = r.name;
    roads.push_back(j);
  }
  json junctions = json::array();
  for (const odr::Junction& jn : net.junctions) {
    std::vector<std::string> connecting_roads;
    for (const odr::Connection& c : jn.connections) {
      if (std::find(connecting_roads.begin(), connecting_roads.end(), c.connecting) ==
          connecting_roads.end()) {
        connecting_roads.push_back(c.connecting);
      }
    }
    junctions.push_back({{"id", jn.id},
                         {"type", jn.type},
                         {"connections", jn.connections.size()},
                         {"connecting_roads", connecting_roads}});
  }
  // Traffic lights (issue 34): per signalised junction its signal groups, their heads and the
  // lanes they govern with the stop line.
  const odr::SignalLayout layout(net);
  json lights = json::array();
  for (const odr::SignalisedJunction& sj : layout.junctions()) {
    json groups = json::array();
    for (int id : sj.groups) {
      const odr::SignalGroup& g = *layout.group(id);
      json heads = json::array();
      for (std::size_t h : g.heads) {
        const odr::SignalHead& sh = layout.heads()[h];
        heads.push_back({{"signal", sh.signal->id},
                         {"road", net.roads[static_cast<std::size_t>(sh.road)].id},
                         {"s", sh.s},
                         {"t", sh.t},
                         {"x", sh.pose.x},
                         {"y", sh.pose.y},
                         {"z", sh.pose.z},
                         {"heading", sh.pose.heading}});
      }
      json lanes = json::array();
      for (const odr::SignalApproach& a : layout.approaches()) {
        if (a.signal_group != id)
          continue;
        lanes.push_back({{"road", net.roads[static_cast<std::size_t>(a.road)].id},
                         {"lane", a.lane},
                         {"stop_s", a.stop_s},
                         {"stop_line", a.has_stop_line},
                         {"x", a.stop.x},
                         {"y", a.stop.y}});
      }
      groups.push_back({{"signal_group", id}, {"heads", heads}, {"lanes", lanes}});
    }
    lights.push_back({{"junction", net.junctions[sj.junction].id},
                      {"intersection_id", sj.intersection_id},
                      {"signal_groups", groups}});
  }
  json out = {
      {"source", net.source},
      {"opendrive",
       std::to_string(net.header.rev_major) + "." + std::to_string(net.header.rev_minor)},
      {"roads", roads.size()},
      {"connecting_roads", connecting},
      {"junctions", junctions},
      {"lane_metres_by_type", lanes},
      {"bounding_box",
       {{"x_min", x0}, {"y_min", y0}, {"z_min", z0}, {"x_max", x1}, {"y_max", y1}, {"z_max", z1}}},
      {"geo_reference",
       net.header.geo_reference.empty() ? json(nullptr) : json(net.header.geo_reference)},
      {"origin", {{"source", origin.source}}},
      {"signals", signals},
      {"traffic_lights", lights},
      {"objects", objects},
      {"warnings", net.warnings},
      {"road_list", roads},
  };
  if (origin.origin) {
    out["origin"]["latitude_deg"] = origin.origin->latitude_deg;
    out["origin"]["longitude_deg"] = origin.origin->longitude_deg;
    out["origin"]["altitude_m"] = origin.origin->altitude_m;
  }
  return out;
}

nlohmann::json where(const odr::RoadNetwork& net, double x, double y) {
  const odr::LaneLocator loc(net);
  const auto at = loc.locate(x, y);
  if (!at)
    return nullptr;
  const odr::Road& r = net.roads[static_cast<std::size_t>(at->ref.road)];
  const odr::Lane& l = *r.sections[at->section].lane(at->ref.lane);
  return {{"road", r.id},
          {"lane", at->ref.lane},
          {"s", at->s},
          {"t", at->t},
          {"z", at->z},
          {"lane_type", l.type},
          {"drivable", l.drivable},
          {"junction", r.junction}};
}

}  // namespace tb::map
