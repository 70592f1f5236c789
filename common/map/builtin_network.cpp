#include "common/map/builtin_network.hpp"

#include <numbers>
#include <stdexcept>

#include "common/map/road_map.hpp"

namespace tb::map {

namespace {

odr::Lane make_lane(int id, double width) {
  odr::Lane l;
  l.id = id;
  l.type = "driving";
  l.drivable = true;
  l.width = odr::CubicProfile({{0.0, width, 0, 0, 0}});
  odr::RoadMark m;
  m.type = "broken";
  m.color = "white";
  l.marks.push_back(m);
  return l;
}

odr::Road make_road(const std::string& id, std::unique_ptr<odr::Geometry> g,
                    const scenario::MapSpec& spec) {
  odr::Road r;
  r.id = id;
  r.length = g->length();
  r.geometries.push_back(std::move(g));
  const int forward = spec.lanes - spec.oncoming_lanes;
  const double width = spec.lanes * spec.lane_width;
  const double offset = -width / 2 + forward * spec.lane_width;
  if (offset != 0.0)
    r.lane_offset = odr::CubicProfile({{0.0, offset, 0, 0, 0}});
  odr::LaneSection ls;
  ls.s = 0.0;
  ls.s_end = r.length;
  for (int i = 1; i <= spec.oncoming_lanes; ++i)
    ls.left.push_back(make_lane(i, spec.lane_width));
  for (int i = 1; i <= forward; ++i)
    ls.right.push_back(make_lane(-i, spec.lane_width));
  // The outermost marks are edges (solid); the centre line is solid between the directions.
  if (!ls.left.empty())
    ls.left.back().marks[0].type = "solid";
  if (!ls.right.empty())
    ls.right.back().marks[0].type = "solid";
  odr::RoadMark centre;
  centre.type = spec.oncoming_lanes > 0 && forward > 0 ? "solid" : "none";
  centre.color = "white";
  ls.center.marks.push_back(centre);
  r.sections.push_back(std::move(ls));
  odr::RoadType t;
  t.type = "rural";
  r.types.push_back(t);
  return r;
}

}  // namespace

int opendrive_lane_id(const scenario::MapSpec& spec, int index) {
  const int forward = spec.lanes - spec.oncoming_lanes;
  return index < forward ? -(forward - index) : index - forward + 1;
}

odr::RoadNetwork generate_network(const scenario::MapSpec& spec) {
  const RoadMap checked(spec);  // same validation, same messages as the built-in model
  odr::RoadNetwork net;
  net.source = "built-in";
  net.header.name = "testbed built-in layout";
  net.header.vendor = "v2x-testbed";
  switch (spec.type) {
    case scenario::MapType::kStraight:
      net.roads.push_back(make_road(
          "0", std::make_unique<odr::Line>(0.0, odr::RefPoint{0, 0, 0}, spec.length), spec));
      break;
    case scenario::MapType::kRing: {
      // s = 0 at the easternmost point, counter-clockwise, as RoadMap's circle.
      const double len = 2 * std::numbers::pi * spec.radius;
      net.roads.push_back(make_road(
          "0",
          std::make_unique<odr::Arc>(0.0, odr::RefPoint{spec.radius, 0, std::numbers::pi / 2}, len,
                                     1.0 / spec.radius),
          spec));
      odr::Road& r = net.roads.back();
      r.predecessor = odr::RoadLink{false, "0", odr::ContactPoint::kEnd, 0};
      r.successor = odr::RoadLink{false, "0", odr::ContactPoint::kStart, 0};
      for (auto* side : {&r.sections[0].left, &r.sections[0].right}) {
        for (odr::Lane& l : *side) {
          l.predecessor = l.id;
          l.successor = l.id;
          l.has_link = true;
        }
      }
      break;
    }
    case scenario::MapType::kCrossing: {
      const double a = spec.arm_length;
      net.roads.push_back(
          make_road("0", std::make_unique<odr::Line>(0.0, odr::RefPoint{-a, 0, 0}, 2 * a), spec));
      net.roads.push_back(make_road(
          "1", std::make_unique<odr::Line>(0.0, odr::RefPoint{0, -a, std::numbers::pi / 2}, 2 * a),
          spec));
      break;
    }
    case scenario::MapType::kOpenDrive:
      throw std::invalid_argument("an OpenDRIVE map is not a built-in layout");
  }
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const odr::Road& r : net.roads) {
    for (double s = 0; s <= r.length; s += r.length / 64) {
      for (double t : {-spec.lanes * spec.lane_width / 2, spec.lanes * spec.lane_width / 2}) {
        const odr::SurfacePose p = r.surface(s, t);
        x0 = std::min(x0, p.x);
        y0 = std::min(y0, p.y);
        x1 = std::max(x1, p.x);
        y1 = std::max(y1, p.y);
      }
    }
  }
  net.header.west = x0;
  net.header.south = y0;
  net.header.east = x1;
  net.header.north = y1;
  return net;
}

}  // namespace tb::map
