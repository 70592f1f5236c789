#include "sim-client/view3d/overlay.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <set>
#include <vector>

#include <osg/Geometry>
#include <osg/NodeVisitor>

namespace tb::client::view3d {
namespace {

/// Every vertex the overlay's geometries hold (no GL needed: the scene graph only).
std::vector<osg::Vec3> vertices(osg::Node& n, GLenum mode) {
  struct Collect : osg::NodeVisitor {
    explicit Collect(GLenum m) : osg::NodeVisitor(TRAVERSE_ALL_CHILDREN), mode(m) {}
    void apply(osg::Drawable& d) override {
      auto* g = d.asGeometry();
      if (g == nullptr || g->getNumPrimitiveSets() == 0 || g->getPrimitiveSet(0)->getMode() != mode)
        return;
      const auto* v = dynamic_cast<const osg::Vec3Array*>(g->getVertexArray());
      const GLsizei count = static_cast<const osg::DrawArrays*>(g->getPrimitiveSet(0))->getCount();
      if (seen.insert(g).second)
        for (GLsizei i = 0; i < count; ++i)
          out.push_back((*v)[static_cast<std::size_t>(i)]);
    }
    GLenum mode;
    std::set<const osg::Geometry*> seen;
    std::vector<osg::Vec3> out;
  } c(mode);
  n.accept(c);
  return c.out;
}

VehicleLook car(std::uint32_t station) {
  VehicleLook l;
  l.id = std::to_string(station);
  l.station_id = station;
  return l;
}

wire::VehicleState state(double x, double y, double z) {
  wire::VehicleState s;
  s.position = {x, y, z};
  return s;
}

// On a hill: each station's ring lies at its own car's height (plus the lift), at the range
// from it; the DENM area at the height of the car nearest to the event, at its radius.
TEST(V2xOverlay, GroundShapesSitAtTheirCarsHeight) {
  auto w = std::make_shared<World>();
  w->vehicles = {car(1), car(2)};
  w->radio_range_m = 40.0;
  w->frame.emplace(geodesy::Geodetic{48.0, 11.0, 500.0});
  FrameInput in;
  in.world = w;
  in.vehicles = {state(0, 0, 6.0), state(100, 0, -2.0)};
  in.choice.overlay = true;
  const geodesy::Geodetic ev = w->frame->to_geodetic({90.0, 10.0, 0.0});
  v2x::DenmEvent d;
  d.originator = 2;
  d.sequence = 1;
  d.latitude_deg = ev.latitude_deg;
  d.longitude_deg = ev.longitude_deg;
  d.relevance_radius_m = 25.0;
  in.v2x.denms = {d};
  V2xOverlay overlay;
  overlay.update(in);
  EXPECT_EQ(overlay.range_rings(), 2u);
  EXPECT_EQ(overlay.denm_areas(), 1u);
  int around1 = 0, around2 = 0, area = 0, other = 0;
  for (const osg::Vec3& p : vertices(*overlay.node(), GL_LINES)) {
    // The event comes as WGS84 without altitude: placed on the ellipsoid under a frame whose
    // origin is 500 m up, its east/north shift by millimetres (the verticals converge).
    const auto at = [&](double x, double y, double z, double r) {
      return std::abs(std::hypot(p.x() - x, p.y() - y) - r) < 0.01 &&
             std::abs(p.z() - (z + V2xOverlay::kGroundLift)) < 1e-4;
    };
    if (at(0, 0, 6.0, 40.0))
      ++around1;
    else if (at(100, 0, -2.0, 40.0))
      ++around2;
    else if (at(90, 10, -2.0, 25.0))
      ++area;
    else
      ++other;
  }
  EXPECT_GE(around1, 96 * 2);  // line segments: two vertices each
  EXPECT_GE(around2, 96 * 2);
  EXPECT_GE(area, 96 * 2);
  EXPECT_EQ(other, 0);  // no links, no warnings
  // The disc fills the area: every vertex within the radius, at the same height.
  for (const osg::Vec3& p : vertices(*overlay.node(), GL_TRIANGLES)) {
    if (std::abs(p.z() - (-2.0f + V2xOverlay::kGroundLift)) > 1e-4f)
      continue;  // the pylon
    EXPECT_LE(std::hypot(p.x() - 90.0, p.y() - 10.0), 25.0 + 0.01);
  }
  // The ideal channel: no rings. Overlay off: nothing.
  auto ideal = std::make_shared<World>(*w);
  ideal->radio_range_m.reset();
  in.world = ideal;
  overlay.update(in);
  EXPECT_EQ(overlay.range_rings(), 0u);
  in.choice.overlay = false;
  overlay.update(in);
  EXPECT_EQ(overlay.denm_areas(), 0u);
  EXPECT_TRUE(vertices(*overlay.node(), GL_LINES).empty());
}

}  // namespace
}  // namespace tb::client::view3d
