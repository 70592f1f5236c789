#include "common/scenario/rsus.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include <fmt/format.h>

#include "common/map/opendrive/reader.hpp"

namespace tb::scenario::detail {

namespace {

constexpr double kSampleStepM = 1.0;

/// Distance from a point to the surface of one road near the reference-line sample at s.
double distance_near(const map::odr::Road& road, double s, double x, double y) {
  const map::odr::RefPoint ref = road.reference(s);
  const double dx = x - ref.x, dy = y - ref.y;
  const double along = dx * std::cos(ref.hdg) + dy * std::sin(ref.hdg);
  const double t = -dx * std::sin(ref.hdg) + dy * std::cos(ref.hdg);
  const map::odr::LaneBorders b = road.borders(road.section_index(s), s);
  const double left = b.left.empty() ? b.center : std::max(b.center, b.left.back());
  const double right = b.right.empty() ? b.center : std::min(b.center, b.right.back());
  const double lateral = t > left ? t - left : (t < right ? right - t : 0.0);
  const double longitudinal = std::max(0.0, std::abs(along) - kSampleStepM / 2.0);
  return std::hypot(lateral, longitudinal);
}

std::string quoted_list(const std::vector<std::string>& ids) {
  std::string out;
  for (const auto& id : ids)
    out += (out.empty() ? "\"" : ", \"") + id + "\"";
  return out.empty() ? "none" : out;
}

}  // namespace

double distance_to_road(const map::odr::RoadNetwork& net, double x, double y) {
  double best = std::numeric_limits<double>::infinity();
  for (const map::odr::Road& road : net.roads) {
    if (road.length <= 0.0)
      continue;
    const int n = std::max(1, static_cast<int>(std::ceil(road.length / kSampleStepM)));
    for (int i = 0; i <= n; ++i) {
      const double s = std::min(road.length, i * kSampleStepM);
      best = std::min(best, distance_near(road, s, x, y));
      if (best == 0.0)
        return 0.0;
    }
  }
  return best;
}

std::vector<Rsu> read_rsus(std::optional<Node> node, const Scenario& s, const map::ScenarioMap& map,
                           const std::string& map_name, const std::vector<Node>& vehicle_nodes) {
  std::vector<Rsu> rsus;
  if (!node)
    return rsus;
  const map::odr::RoadNetwork& net = map.network();
  const map::odr::SignalLayout& layout = map.signals();
  // Where each id and station id was first used, for the "also ..." of a clash.
  std::unordered_map<std::string, std::string> ids;
  std::unordered_map<std::uint32_t, std::string> stations;
  for (std::size_t i = 0; i < s.vehicles.size(); ++i) {
    ids.emplace(s.vehicles[i].id, vehicle_nodes[i].path());
    stations.emplace(s.vehicles[i].station_id, vehicle_nodes[i].path());
  }
  const auto& h = net.header;
  const bool has_extent = h.north > h.south && h.east > h.west;
  for (Node& n : node->array(0, 1024)) {
    n.expect_object(
        "a road-side unit (\"id\", \"station_id\", \"junction\", \"position\", "
        "\"height\")");
    Rsu r;
    Node id = n.required("id");
    r.id = id.string();
    if (r.id.empty() || r.id.size() > 64 ||
        r.id.find_first_not_of(
            "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") !=
            std::string::npos) {
      id.fail("RSU id \"" + r.id + "\" must be 1 to 64 letters, digits, '_' or '-'");
    }
    if (const auto [it, fresh] = ids.emplace(r.id, n.path()); !fresh) {
      id.fail(fmt::format("id \"{}\" is already used by {} (vehicles and RSUs need unique ids)",
                          r.id, it->second));
    }
    Node station = n.required("station_id");
    r.station_id = static_cast<std::uint32_t>(station.integer(0, 4294967295LL));
    if (const auto [it, fresh] = stations.emplace(r.station_id, n.path()); !fresh) {
      station.fail(fmt::format(
          "station_id {} is already used by {} (vehicles and RSUs need unique station ids)",
          r.station_id, it->second));
    }
    Node junction = n.required("junction");
    // OpenDRIVE ids are strings; "junction": 100 is read as "100".
    r.junction = junction.json().is_number_integer() ? junction.json().dump() : junction.string();
    if (net.junction_index(r.junction) < 0) {
      std::vector<std::string> all;
      for (const auto& j : net.junctions)
        all.push_back(j.id);
      junction.fail(fmt::format("junction \"{}\" does not exist in {} (its junctions: {})",
                                r.junction, map_name, quoted_list(all)));
    }
    if (layout.junction(r.junction) == nullptr) {
      std::vector<std::string> lit;
      for (const auto& sj : layout.junctions())
        lit.push_back(net.junctions[sj.junction].id);
      junction.fail(fmt::format(
          "junction \"{}\" of {} has no traffic lights, so an RSU has no MAPEM or SPATEM to "
          "send there (junctions with lights: {})",
          r.junction, map_name, quoted_list(lit)));
    }
    Node position = n.required("position");
    position.expect_object("the RSU's position (\"x\", \"y\": map frame, m)");
    r.x = position.required("x").number(-map::odr::kMaxCoordinate, map::odr::kMaxCoordinate);
    r.y = position.required("y").number(-map::odr::kMaxCoordinate, map::odr::kMaxCoordinate);
    position.finish();
    if (has_extent && (r.x < h.west || r.x > h.east || r.y < h.south || r.y > h.north)) {
      position.fail(fmt::format(
          "({}, {}) lies outside the map's extent (the <header> of {}: x {} to {}, y {} to {})",
          r.x, r.y, map_name, h.west, h.east, h.south, h.north));
    }
    const double gap = distance_to_road(net, r.x, r.y);
    if (gap > kMaxRsuRoadDistanceM) {
      position.fail(fmt::format(
          "({}, {}) is {:.0f} m from the nearest road of {}: an RSU must stand within {:.0f} m "
          "of a road",
          r.x, r.y, gap, map_name, kMaxRsuRoadDistanceM));
    }
    // A mast, a gantry or a building's roof; not below the ground, not an aircraft.
    r.height_m = n.required("height").number(0.0, 100.0);
    n.finish();
    rsus.push_back(std::move(r));
  }
  return rsus;
}

}  // namespace tb::scenario::detail
