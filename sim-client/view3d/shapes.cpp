#include "sim-client/view3d/shapes.hpp"

#include <cmath>
#include <numbers>

#include <osg/Geode>

namespace tb::client::view3d {

MeshBuilder::MeshBuilder()
    : v_(new osg::Vec3Array), n_(new osg::Vec3Array), c_(new osg::Vec4Array) {}

void MeshBuilder::quad(const osg::Vec3& a, const osg::Vec3& b, const osg::Vec3& c,
                       const osg::Vec3& d, const osg::Vec4& colour) {
  osg::Vec3 n = (b - a) ^ (c - a);
  n.normalize();
  for (const auto& p : {a, b, c, d}) {
    v_->push_back(p);
    n_->push_back(n);
    c_->push_back(colour);
  }
}

void MeshBuilder::box(const osg::Vec3& lo, const osg::Vec3& hi, const osg::Vec4& colour) {
  const float x0 = lo.x(), y0 = lo.y(), z0 = lo.z(), x1 = hi.x(), y1 = hi.y(), z1 = hi.z();
  quad({x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1}, colour);  // top
  quad({x0, y0, z0}, {x0, y1, z0}, {x1, y1, z0}, {x1, y0, z0}, colour);  // bottom
  quad({x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x1, y0, z1}, colour);  // front (+x)
  quad({x0, y0, z0}, {x0, y0, z1}, {x0, y1, z1}, {x0, y1, z0}, colour);  // back
  quad({x0, y1, z0}, {x0, y1, z1}, {x1, y1, z1}, {x1, y1, z0}, colour);  // left (+y)
  quad({x0, y0, z0}, {x1, y0, z0}, {x1, y0, z1}, {x0, y0, z1}, colour);  // right
}

osg::ref_ptr<osg::Geometry> lit_geometry(osg::Vec3Array* vertices, osg::Vec3Array* normals,
                                         osg::Vec4Array* colours, GLenum mode) {
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  g->setUseDisplayList(false);
  g->setUseVertexBufferObjects(true);
  g->setVertexArray(vertices);
  g->setNormalArray(normals, osg::Array::BIND_PER_VERTEX);
  g->setColorArray(colours, osg::Array::BIND_PER_VERTEX);
  g->addPrimitiveSet(new osg::DrawArrays(mode, 0, static_cast<GLsizei>(vertices->size())));
  return g;
}

osg::ref_ptr<osg::Geometry> MeshBuilder::build() {
  return lit_geometry(v_, n_, c_, GL_QUADS);
}

osg::ref_ptr<osg::Geometry> MeshBuilder::build_overall(osg::ref_ptr<osg::Vec4Array>& colour,
                                                       const osg::Vec4& initial) {
  osg::ref_ptr<osg::Geometry> g = build();
  colour = filled<osg::Vec4Array>(1, initial);
  g->setColorArray(colour, osg::Array::BIND_OVERALL);
  return g;
}

osg::ref_ptr<osg::Node> make_wheel(float r, float w) {
  constexpr int kSides = 16;
  const osg::Vec4 tyre(0.08f, 0.08f, 0.08f, 1.0f);
  const osg::Vec4 rim(0.55f, 0.56f, 0.58f, 1.0f);
  MeshBuilder m;
  const float h = w / 2;
  for (int i = 0; i < kSides; ++i) {
    const double a0 = 2.0 * std::numbers::pi * i / kSides;
    const double a1 = 2.0 * std::numbers::pi * (i + 1) / kSides;
    const osg::Vec3 p0(static_cast<float>(r * std::cos(a0)), 0,
                       static_cast<float>(r * std::sin(a0)));
    const osg::Vec3 p1(static_cast<float>(r * std::cos(a1)), 0,
                       static_cast<float>(r * std::sin(a1)));
    const osg::Vec3 dy(0, h, 0);
    m.quad(p0 - dy, p1 - dy, p1 + dy, p0 + dy, tyre);  // tread
    // Side walls as thin quads to the hub: the rim colour inside 60 % of the radius.
    const osg::Vec3 q0 = p0 * 0.6f, q1 = p1 * 0.6f;
    m.quad(p0 + dy, p1 + dy, q1 + dy, q0 + dy, tyre);
    m.quad(p1 - dy, p0 - dy, q0 - dy, q1 - dy, tyre);
    m.quad(q0 + dy, q1 + dy, osg::Vec3() + dy, osg::Vec3() + dy, rim);
    m.quad(q1 - dy, q0 - dy, osg::Vec3() - dy, osg::Vec3() - dy, rim);
  }
  // Two dark spokes across the rim, slightly proud of it, so that the rolling shows.
  const float s = 0.55f * r, t = 0.09f * r, o = h + 0.005f;
  const osg::Vec4 spoke(0.2f, 0.2f, 0.22f, 1.0f);
  m.box({-s, o - 0.004f, -t}, {s, o, t}, spoke);
  m.box({-t, o - 0.004f, -s}, {t, o, s}, spoke);
  m.box({-s, -o, -t}, {s, -o + 0.004f, t}, spoke);
  m.box({-t, -o, -s}, {t, -o + 0.004f, s}, spoke);
  osg::ref_ptr<osg::Geode> g = new osg::Geode;
  g->addDrawable(m.build());
  return g;
}

}  // namespace tb::client::view3d
