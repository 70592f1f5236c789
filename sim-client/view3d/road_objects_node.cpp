#include "sim-client/view3d/road_objects_node.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <utility>

#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Group>
#include <osg/LOD>

#include "common/map/opendrive/road_objects.hpp"
#include "sim-client/view3d/shapes.hpp"

namespace tb::client::view3d {
namespace {

namespace odr = map::odr;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

/// Triangles with face normals and per-vertex colours, merged into one drawable.
class ShapeBatch {
 public:
  ShapeBatch() : v_(new osg::Vec3Array), n_(new osg::Vec3Array), c_(new osg::Vec4Array) {}

  bool empty() const { return v_->empty(); }
  std::size_t triangles() const { return v_->size() / 3; }

  void triangle(const osg::Vec3& a, const osg::Vec3& b, const osg::Vec3& c,
                const osg::Vec4& colour) {
    osg::Vec3 n = (b - a) ^ (c - a);
    n.normalize();
    for (const auto& p : {a, b, c}) {
      v_->push_back(p);
      n_->push_back(n);
      c_->push_back(colour);
    }
  }
  void quad(const osg::Vec3& a, const osg::Vec3& b, const osg::Vec3& c, const osg::Vec3& d,
            const osg::Vec4& colour) {
    triangle(a, b, c, colour);
    triangle(a, c, d, colour);
  }

  /// A box standing on @p base (the middle of its footprint), turned by @p heading: @p length
  /// along it, @p width across, @p height up; the top in @p top.
  void box(const osg::Vec3& base, double heading, double length, double width, double height,
           const osg::Vec4& side, const osg::Vec4& top) {
    const osg::Vec3 u(static_cast<float>(std::cos(heading) * length / 2),
                      static_cast<float>(std::sin(heading) * length / 2), 0);
    const osg::Vec3 v(static_cast<float>(-std::sin(heading) * width / 2),
                      static_cast<float>(std::cos(heading) * width / 2), 0);
    const osg::Vec3 h(0, 0, static_cast<float>(height));
    const osg::Vec3 p0 = base - u - v, p1 = base + u - v, p2 = base + u + v, p3 = base - u + v;
    quad(p0 + h, p1 + h, p2 + h, p3 + h, top);
    quad(p0, p1, p1 + h, p0 + h, side);
    quad(p1, p2, p2 + h, p1 + h, side);
    quad(p2, p3, p3 + h, p2 + h, side);
    quad(p3, p0, p0 + h, p3 + h, side);
  }

  /// A cone (a pyramid of @p sides) from a circle of @p radius at @p base up to its tip.
  void cone(const osg::Vec3& base, double radius, double height, const osg::Vec4& colour,
            int sides = 7) {
    const osg::Vec3 tip = base + osg::Vec3(0, 0, static_cast<float>(height));
    for (int i = 0; i < sides; ++i) {
      const double a0 = 2 * std::numbers::pi * i / sides,
                   a1 = 2 * std::numbers::pi * (i + 1) / sides;
      const osg::Vec3 p0 = base + osg::Vec3(static_cast<float>(radius * std::cos(a0)),
                                            static_cast<float>(radius * std::sin(a0)), 0);
      const osg::Vec3 p1 = base + osg::Vec3(static_cast<float>(radius * std::cos(a1)),
                                            static_cast<float>(radius * std::sin(a1)), 0);
      triangle(p0, p1, tip, colour);
    }
  }

  osg::ref_ptr<osg::Geode> build(const char* name) {
    osg::ref_ptr<osg::Geometry> g = lit_geometry(v_, n_, c_, GL_TRIANGLES);
    osg::ref_ptr<osg::Geode> geode = new osg::Geode;
    geode->setName(name);
    geode->addDrawable(g);
    return geode;
  }

 private:
  osg::ref_ptr<osg::Vec3Array> v_;
  osg::ref_ptr<osg::Vec3Array> n_;
  osg::ref_ptr<osg::Vec4Array> c_;
};

struct Tile {
  ShapeBatch big, small;
};

osg::Vec4 rgba(float r, float g, float b) {
  return {r, g, b, 1.0f};
}

osg::Vec4 rgba(const std::array<float, 3>& c) {
  return {c[0], c[1], c[2], 1.0f};
}

const osg::Vec4 kGrey = rgba(0.55f, 0.55f, 0.53f);
const osg::Vec4 kPole = rgba(0.42f, 0.43f, 0.45f);
const osg::Vec4 kTrunk = rgba(0.36f, 0.25f, 0.15f);
const osg::Vec4 kLeaves = rgba(0.16f, 0.40f, 0.15f);
const osg::Vec4 kHedge = rgba(0.20f, 0.42f, 0.17f);

double or_default(double v, double fallback) {
  return v > 0.0 ? v : fallback;
}

void add_object(const odr::PlacedObject& p, const std::string& shape, std::size_t copy,
                Tile& tile) {
  const odr::RoadObject& o = *p.object;
  const osg::Vec3 base(static_cast<float>(p.pose.x), static_cast<float>(p.pose.y),
                       static_cast<float>(p.pose.z));
  const double hdg = p.pose.heading;
  if (shape == "building") {
    tile.big.box(base, hdg, or_default(p.length, 10), or_default(p.width, 10),
                 or_default(p.height, 8), rgba(wall_colour(o.id, copy)),
                 rgba(roof_colour(o.id, copy)));
  } else if (shape == "tree") {
    const double h = or_default(p.height, 6.0);
    const double r = or_default(p.radius, or_default(std::max(p.length, p.width) / 2, 1.8));
    tile.big.box(base, hdg, 0.35, 0.35, 0.35 * h, kTrunk, kTrunk);
    tile.big.cone(base + osg::Vec3(0, 0, static_cast<float>(0.25 * h)), r, 0.75 * h, kLeaves);
  } else if (shape == "hedge") {
    tile.small.box(base, hdg, or_default(p.length, 1.0), or_default(p.width, 0.8),
                   or_default(p.height, 1.2), kHedge, kHedge);
  } else if (shape == "wall") {
    tile.big.box(base, hdg, or_default(p.length, 1.0), or_default(p.width, 0.3),
                 or_default(p.height, 1.0), kGrey, kGrey);
  } else if (shape == "pole") {
    const double h = or_default(p.height, 4.0);
    const double d = std::max(0.08, 2 * p.radius);
    tile.small.box(base, hdg, d, d, h, kPole, kPole);
    if (lower(o.name).find("lamp") != std::string::npos || lower(o.type) == "streetlamp") {
      // Which way the road lies from a pole is not in the object, so no arm over it: a short
      // head on top reads as a lamp from any side.
      tile.small.box(base + osg::Vec3(0, 0, static_cast<float>(h)), hdg, 0.6, 0.3, 0.15,
                     rgba(0.9f, 0.9f, 0.8f), kPole);
    }
  } else if (shape == "box") {
    const double r = p.radius;
    tile.big.box(base, hdg, or_default(p.length, r > 0 ? 2 * r : 1.0),
                 or_default(p.width, r > 0 ? 2 * r : 1.0), or_default(p.height, 1.0), kGrey, kGrey);
  }
}

void add_signal(const odr::Road& road, const odr::RoadSignal& g, Tile& tile) {
  const odr::ItemPose p = odr::signal_pose(road, g);
  // The plate's lower edge is zOffset above the road (signs stand on a pole to it); the pole's
  // foot is on the road surface at (s, t).
  const double bottom = std::max(0.0, g.z_offset);
  const osg::Vec3 foot(static_cast<float>(p.x), static_cast<float>(p.y),
                       static_cast<float>(p.z - g.z_offset));
  const double w = or_default(g.width, 0.6), h = or_default(g.height, 0.6);
  const bool light = g.dynamic || g.type == "1000001";
  tile.small.box(foot, p.heading, 0.08, 0.08, bottom + (light ? 0.0 : h * 0.5), kPole, kPole);
  const osg::Vec3 at = foot + osg::Vec3(0, 0, static_cast<float>(bottom));
  if (light) {
    // A dynamic signal's head, with lamps lit by its group, is signal_heads_node.hpp's.
    if (!g.dynamic)
      tile.small.box(at, p.heading, 0.25, 0.35, 1.0, rgba(0.12f, 0.12f, 0.12f),
                     rgba(0.12f, 0.12f, 0.12f));
    return;
  }
  const auto c = plate_colour(g);
  // The plate across the traffic's direction: thin along it, w wide.
  tile.small.box(at, p.heading, 0.04, w, h, rgba(c[0], c[1], c[2]), kPole);
}

}  // namespace

std::string shape_of(const map::odr::RoadObject& o) {
  const std::string t = lower(o.type);
  if (t == "building")
    return "building";
  if (t == "tree")
    return "tree";
  if (t == "vegetation")
    return (o.radius > 0.0 || (o.length <= 0.0 && o.width <= 0.0 && o.repeats.empty())) ? "tree"
                                                                                        : "hedge";
  if (t == "barrier" || t == "railing" || t == "soundbarrier" || t == "fence" || t == "wall" ||
      t == "guardrail" || t == "gantry")
    return "wall";
  if (t == "pole" || t == "streetlamp" || t == "trafficlight")
    return "pole";
  if (t == "crosswalk" || t == "roadmark" || t == "stopline" || t == "parkingspace" ||
      t == "patch" || t == "roadsurface" || t == "trafficisland")
    return "mark";
  return "box";
}

std::array<float, 3> wall_colour(const std::string& id, std::size_t copy) {
  // Plaster, brick, sandstone, grey, white.
  static const std::array<float, 3> kFacades[] = {{0.80f, 0.76f, 0.66f},
                                                  {0.62f, 0.36f, 0.28f},
                                                  {0.74f, 0.66f, 0.50f},
                                                  {0.66f, 0.67f, 0.68f},
                                                  {0.86f, 0.84f, 0.80f}};
  const std::size_t h = std::hash<std::string>{}(id) + copy * 7919u;
  return kFacades[h % std::size(kFacades)];
}

std::array<float, 3> roof_colour(const std::string& id, std::size_t copy) {
  const auto w = wall_colour(id, copy);
  return {w[0] * 0.55f, w[1] * 0.5f, w[2] * 0.5f};
}

std::array<float, 3> plate_colour(const map::odr::RoadSignal& g) {
  if (g.type == "206")
    return {0.80f, 0.10f, 0.10f};
  if (g.type == "250" || g.type == "267")  // no entry, no vehicles: red discs
    return {0.85f, 0.20f, 0.18f};
  if (g.type == "306" || g.type == "301")  // priority road: yellow
    return {0.95f, 0.80f, 0.15f};
  if (!g.type.empty() && g.type[0] == '4')  // direction signs: blue
    return {0.15f, 0.30f, 0.75f};
  return {0.93f, 0.93f, 0.93f};
}

osg::ref_ptr<osg::Node> make_road_objects_node(const map::odr::RoadNetwork& net,
                                               ObjectsNodeStats* stats) {
  std::map<std::pair<long, long>, Tile> tiles;
  std::size_t shapes = 0;
  auto tile_at = [&](double x, double y) -> Tile& {
    return tiles[{static_cast<long>(std::floor(x / kObjectTile)),
                  static_cast<long>(std::floor(y / kObjectTile))}];
  };
  for (const odr::Road& road : net.roads) {
    for (const odr::RoadObject& o : road.objects) {
      const std::string shape = shape_of(o);
      if (shape == "mark")
        continue;
      std::size_t copy = 0;
      for (const odr::PlacedObject& p : odr::place_object(road, o)) {
        add_object(p, shape, copy++, tile_at(p.pose.x, p.pose.y));
        ++shapes;
      }
    }
    for (const odr::RoadSignal& g : road.signals) {
      if (odr::is_stop_line(g))
        continue;
      const odr::ItemPose p = odr::signal_pose(road, g);
      add_signal(road, g, tile_at(p.x, p.y));
      ++shapes;
    }
  }
  osg::ref_ptr<osg::Group> group = new osg::Group;
  group->setName("road objects");
  // Every shape is closed and wound counter-clockwise from outside: back faces need no
  // rasterising (on llvmpipe the pixels are the cost).
  group->getOrCreateStateSet()->setMode(GL_CULL_FACE, osg::StateAttribute::ON);
  std::size_t triangles = 0;
  for (auto& [key, tile] : tiles) {
    osg::ref_ptr<osg::LOD> lod = new osg::LOD;
    if (!tile.big.empty()) {
      triangles += tile.big.triangles();
      lod->addChild(tile.big.build("big objects"), 0.0f, kBigRange);
    }
    if (!tile.small.empty()) {
      triangles += tile.small.triangles();
      lod->addChild(tile.small.build("small objects"), 0.0f, kSmallRange);
    }
    group->addChild(lod);
  }
  if (stats != nullptr)
    *stats = {shapes, triangles, tiles.size()};
  return group;
}

}  // namespace tb::client::view3d
