#include "sim-client/view3d/junction_marks.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

#include <osg/Geode>
#include <osg/Geometry>
#include <osg/PolygonOffset>

#include "common/map/opendrive/queries.hpp"
#include "common/map/opendrive/road_objects.hpp"
#include "sim-client/view3d/road_node.hpp"
#include "sim-client/view3d/shapes.hpp"

namespace tb::client::view3d {
namespace {

namespace odr = map::odr;

constexpr double kStopLineDepth = 0.5;  // m along the road
constexpr double kStripe = 0.5;         // m, zebra stripes and their gaps

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool says(const odr::RoadObject& o, const char* word) {
  return lower(o.subtype).find(word) != std::string::npos ||
         lower(o.name).find(word) != std::string::npos;
}

/// An object's local frame (u along its heading, v to its left) on the road's surface: road
/// coordinates turned by hdg, so that the patch follows the surface's height and banking.
struct LocalFrame {
  const odr::Road& road;
  double s, t, ch, sh;
  LocalFrame(const odr::Road& r, double s0, double t0, double hdg)
      : road(r), s(s0), t(t0), ch(std::cos(hdg)), sh(std::sin(hdg)) {}
  std::array<double, 3> at(double u, double v) const {
    const double ss = std::clamp(s + u * ch - v * sh, 0.0, road.length);
    const odr::SurfacePose p = road.surface(ss, t + u * sh + v * ch);
    return {p.x, p.y, p.z + kMarkLift};
  }
  /// The rectangle u in [u0, u1], v in [v0, v1].
  MarkQuad rect(MarkQuad::Kind kind, double u0, double u1, double v0, double v1) const {
    MarkQuad q;
    q.kind = kind;
    q.corners = {at(u0, v0), at(u1, v0), at(u1, v1), at(u0, v1)};
    return q;
  }
};

/// The extent of an object in its local frame: its outline's bounding box, else its size.
struct Extent {
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
};
Extent extent(const odr::RoadObject& o) {
  if (o.outline.size() >= 3) {
    Extent e{1e300, -1e300, 1e300, -1e300};
    for (const odr::OutlineCorner& c : o.outline) {
      e.u0 = std::min(e.u0, c.u);
      e.u1 = std::max(e.u1, c.u);
      e.v0 = std::min(e.v0, c.v);
      e.v1 = std::max(e.v1, c.v);
    }
    return e;
  }
  return {-o.length / 2, o.length / 2, -o.width / 2, o.width / 2};
}

void stop_line(const odr::Road& road, const odr::RoadSignal& g, std::vector<MarkQuad>& out) {
  double w = g.width;
  if (w <= 0.0) {  // the lane's width where the file gives none
    const std::size_t k = road.section_index(g.s);
    const int lane = odr::lane_of(road, k, g.s, g.t);
    if (lane == 0)
      return;
    const odr::LaneBorders b = road.borders(k, g.s);
    w = std::fabs(b.outer(lane) - b.inner(lane));
  }
  const LocalFrame f(road, g.s, g.t, g.h_offset);
  out.push_back(
      f.rect(MarkQuad::Kind::kStopLine, -kStopLineDepth / 2, kStopLineDepth / 2, -w / 2, w / 2));
}

void crosswalk(const odr::Road& road, const odr::RoadObject& o, std::vector<MarkQuad>& out) {
  const Extent e = extent(o);
  const double across = e.v1 - e.v0;
  if (e.u1 - e.u0 <= 0.0 || across < kStripe)
    return;
  const LocalFrame f(road, o.s, o.t, o.hdg);
  const int n = static_cast<int>(std::floor((across + kStripe) / (2 * kStripe)));
  const double first = (e.v0 + e.v1) / 2 - (n - 1) * kStripe;  // centred
  for (int i = 0; i < n; ++i) {
    const double v = first + 2 * kStripe * i;
    out.push_back(f.rect(MarkQuad::Kind::kCrosswalk, e.u0, e.u1, v - kStripe / 2, v + kStripe / 2));
  }
}

/// A straight arrow along +u: a shaft over 60 % of the length, a head (a quad with two
/// corners at the tip) over the rest.
void arrow(const odr::Road& road, const odr::RoadObject& o, std::vector<MarkQuad>& out) {
  const Extent e = extent(o);
  const double len = e.u1 - e.u0, wid = e.v1 - e.v0;
  if (len <= 0.0 || wid <= 0.0)
    return;
  const LocalFrame f(road, o.s, o.t, o.hdg);
  const double vc = (e.v0 + e.v1) / 2, neck = e.u0 + 0.6 * len;
  out.push_back(f.rect(MarkQuad::Kind::kArrow, e.u0, neck, vc - wid * 0.15, vc + wid * 0.15));
  MarkQuad head;
  head.kind = MarkQuad::Kind::kArrow;
  head.corners = {f.at(neck, e.v0), f.at(e.u1, vc), f.at(e.u1, vc), f.at(neck, e.v1)};
  out.push_back(head);
}

}  // namespace

std::vector<MarkQuad> junction_mark_quads(const map::odr::RoadNetwork& net) {
  std::vector<MarkQuad> out;
  for (const odr::Road& road : net.roads) {
    for (const odr::RoadSignal& g : road.signals)
      if (odr::is_stop_line(g))
        stop_line(road, g, out);
    for (const odr::RoadObject& o : road.objects) {
      const std::string type = lower(o.type);
      if (type == "crosswalk") {
        crosswalk(road, o, out);
      } else if (type == "stopline" || (type == "roadmark" && says(o, "stop"))) {
        const Extent e = extent(o);
        out.push_back(LocalFrame(road, o.s, o.t, o.hdg)
                          .rect(MarkQuad::Kind::kStopLine, e.u0, e.u1, e.v0, e.v1));
      } else if (type == "roadmark" && says(o, "arrow")) {
        arrow(road, o, out);
      }
    }
  }
  return out;
}

osg::ref_ptr<osg::Node> make_junction_marks_node(const map::odr::RoadNetwork& net,
                                                 std::size_t* count) {
  const std::vector<MarkQuad> quads = junction_mark_quads(net);
  if (count != nullptr)
    *count = quads.size();
  osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array;
  osg::ref_ptr<osg::Vec4Array> c = new osg::Vec4Array;
  for (const MarkQuad& q : quads) {
    const osg::Vec4 colour(q.colour[0], q.colour[1], q.colour[2], 1.0f);
    for (int i : {0, 1, 2, 0, 2, 3}) {
      const auto& p = q.corners[static_cast<std::size_t>(i)];
      v->push_back(
          osg::Vec3(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])));
      c->push_back(colour);
    }
  }
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  g->setUseDisplayList(false);
  g->setUseVertexBufferObjects(true);
  g->setVertexArray(v);
  g->setColorArray(c, osg::Array::BIND_PER_VERTEX);
  g->setNormalArray(filled<osg::Vec3Array>(1, osg::Vec3(0, 0, 1)), osg::Array::BIND_OVERALL);
  g->addPrimitiveSet(new osg::DrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(v->size())));
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->setName("junction marks");
  geode->addDrawable(g);
  osg::StateSet* ss = geode->getOrCreateStateSet();
  ss->setAttributeAndModes(new osg::PolygonOffset(-2.0f, -4.0f), osg::StateAttribute::ON);
  ss->setRenderBinDetails(1, "RenderBin");
  return geode;
}

}  // namespace tb::client::view3d
