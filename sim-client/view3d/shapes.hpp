#pragma once
/// @file Geometry made in code: boxes with face normals collected into one osg::Geometry, and
/// a wheel (tyre with a two-spoke hub that shows the rolling).

#include <algorithm>
#include <cstddef>

#include <osg/Geometry>
#include <osg/Node>
#include <osg/ref_ptr>

namespace tb::client::view3d {

/// An OpenSceneGraph array of @p n copies of @p value.
template <class ArrayT, class ValueT>
osg::ref_ptr<ArrayT> filled(std::size_t n, const ValueT& value) {
  osg::ref_ptr<ArrayT> a = new ArrayT(static_cast<unsigned int>(n));
  std::fill(a->begin(), a->end(), value);
  return a;
}

/// Per-vertex positions, normals and colours drawn as @p mode primitives (GL_TRIANGLES,
/// GL_QUADS) in one geometry: vertex buffer objects, no display list.
osg::ref_ptr<osg::Geometry> lit_geometry(osg::Vec3Array* vertices, osg::Vec3Array* normals,
                                         osg::Vec4Array* colours, GLenum mode);

/// Collects axis-aligned boxes (and quads) into one geometry: one draw call per builder.
class MeshBuilder {
 public:
  MeshBuilder();
  /// A box between @p lo and @p hi in this geometry's frame, in @p colour.
  void box(const osg::Vec3& lo, const osg::Vec3& hi, const osg::Vec4& colour);
  /// A quad, corners counter-clockwise seen from where its normal points.
  void quad(const osg::Vec3& a, const osg::Vec3& b, const osg::Vec3& c, const osg::Vec3& d,
            const osg::Vec4& colour);
  /// The geometry with per-vertex colours (vertex buffer objects, no display list).
  osg::ref_ptr<osg::Geometry> build();
  /// The geometry with one colour array for all vertices, returned in @p colour (lamps switch
  /// it); the per-vertex colours given above are ignored.
  osg::ref_ptr<osg::Geometry> build_overall(osg::ref_ptr<osg::Vec4Array>& colour,
                                            const osg::Vec4& initial);

 private:
  osg::ref_ptr<osg::Vec3Array> v_;
  osg::ref_ptr<osg::Vec3Array> n_;
  osg::ref_ptr<osg::Vec4Array> c_;
};

/// A wheel of radius @p r and width @p w, axle along y, centred on the origin.
osg::ref_ptr<osg::Node> make_wheel(float r, float w);

}  // namespace tb::client::view3d
