#include "sim-client/view3d/road_node.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <osg/BlendFunc>
#include <osg/Depth>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Group>
#include <osg/PolygonOffset>

#include "common/map/opendrive/mesh.hpp"
#include "common/map/opendrive/terrain.hpp"
#include "sim-client/view3d/shapes.hpp"

namespace tb::client::view3d {
namespace {

namespace odr = map::odr;

struct Line {
  double offset;  ///< lateral, m, along +t from the lane border
  bool broken;
};

/// The lines of a road-mark type (OpenDRIVE 1.7, 11.8); empty for none, curb, grass, edge.
std::vector<Line> lines_of(const std::string& type, double width) {
  const double d = width;  // double lines: the gap between them is one line's width
  if (type == "solid")
    return {{0, false}};
  if (type == "broken" || type == "botts dots")
    return {{0, true}};
  if (type == "solid solid")
    return {{-d, false}, {d, false}};
  if (type == "solid broken")
    return {{-d, false}, {d, true}};
  if (type == "broken solid")
    return {{-d, true}, {d, false}};
  if (type == "broken broken")
    return {{-d, true}, {d, true}};
  return {};
}

double reach_of(const odr::Road& road, std::size_t k) {
  const odr::LaneSection& ls = road.sections[k];
  double reach = 0.0;
  for (double s : {ls.s, (ls.s + ls.s_end) / 2, ls.s_end}) {
    const odr::LaneBorders b = road.borders(k, s);
    reach = std::max(reach, std::fabs(b.center));
    for (double v : b.left)
      reach = std::max(reach, std::fabs(v));
    for (double v : b.right)
      reach = std::max(reach, std::fabs(v));
  }
  return reach + 1.0;
}

void add_lane_marks(const odr::Road& road, std::size_t k, const odr::Lane& lane, double eps,
                    std::vector<MarkStrip>& out) {
  const odr::LaneSection& ls = road.sections[k];
  const double reach = reach_of(road, k);
  for (std::size_t i = 0; i < lane.marks.size(); ++i) {
    const odr::RoadMark& m = lane.marks[i];
    const double s_a = std::clamp(ls.s + m.s_offset, ls.s, ls.s_end);
    const double s_b = i + 1 < lane.marks.size()
                           ? std::clamp(ls.s + lane.marks[i + 1].s_offset, s_a, ls.s_end)
                           : ls.s_end;
    if (s_b - s_a < 1e-3)
      continue;
    const double w = std::clamp(m.width, 0.05, 0.5);
    // Botts' dots: squares a line width across, a metre apart.
    const bool dots = m.type == "botts dots";
    const double dash = dots ? w : std::max(0.1, m.line_length);
    const double gap = dots ? 1.0 : std::max(0.0, m.space);
    for (const Line& l : lines_of(m.type, w)) {
      std::vector<std::pair<double, double>> spans;
      if (!l.broken || gap <= 0.0) {
        spans.emplace_back(s_a, s_b);
      } else {
        for (double x = s_a; x < s_b - 1e-3; x += dash + gap)
          spans.emplace_back(x, std::min(x + dash, s_b));
      }
      for (const auto& [a, b] : spans) {
        MarkStrip strip;
        strip.colour = mark_colour(m.color);
        for (double s : odr::sample_s(road, a, b, eps, reach)) {
          const odr::LaneBorders bd = road.borders(k, s);
          const double t = (lane.id == 0 ? bd.center : bd.outer(lane.id)) + l.offset;
          const odr::SurfacePose p0 = road.surface(s, t + w / 2);
          const odr::SurfacePose p1 = road.surface(s, t - w / 2);
          strip.left.push_back({p0.x, p0.y, p0.z + kMarkLift});
          strip.right.push_back({p1.x, p1.y, p1.z + kMarkLift});
        }
        if (strip.left.size() >= 2)
          out.push_back(std::move(strip));
      }
    }
  }
}

osg::ref_ptr<osg::Geometry> new_geometry() {
  osg::ref_ptr<osg::Geometry> g = new osg::Geometry;
  g->setUseDisplayList(false);
  g->setUseVertexBufferObjects(true);
  return g;
}

/// The road surface, coloured by lane type. The connecting roads of a junction overlap at the
/// same height (several cover the same asphalt, a turning road's sidewalk or border lies over
/// another's lanes) and would fight for the depth buffer, striping. Overlapping carriageway
/// lanes have the same colour, so any of them may win; the other lanes of junction roads lie
/// kJunctionVergeDrop lower (all but their end rows, so that they still meet the roads they
/// continue without a crack), so that the carriageway wins over them: the junction surface
/// is drawn once, as asphalt. A polygon offset would not do: its unit is the depth buffer's
/// resolution, which differs by a factor of 256 between 24-bit and llvmpipe's 32-bit buffers,
/// and on the latter is far below the depth error of two coplanar surfaces.
osg::ref_ptr<osg::Geode> surface_geode(const odr::RoadNetwork& net, RoadNodeStats* stats) {
  const odr::RoadMesh mesh = odr::road_mesh(net, kRoadTolerance);
  osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array(mesh.vertices.size());
  osg::ref_ptr<osg::Vec3Array> n = filled<osg::Vec3Array>(mesh.vertices.size(), osg::Vec3(0, 0, 0));
  osg::ref_ptr<osg::Vec4Array> c =
      filled<osg::Vec4Array>(mesh.vertices.size(), osg::Vec4(0.3f, 0.3f, 0.3f, 1.0f));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const auto& p = mesh.vertices[i];
    (*v)[i].set(static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
  }
  const auto carriageway = lane_colour("driving");
  const auto colour_of = [&](std::size_t t) {
    const odr::LaneRef ref = mesh.lanes[t];
    const odr::Lane* lane =
        net.roads[static_cast<std::size_t>(ref.road)].sections[mesh.sections[t]].lane(ref.lane);
    return lane_colour(lane != nullptr ? lane->type : std::string("none"));
  };
  // Each lane strip's triangles come one after the other over vertices of their own (inner and
  // outer border per s sample): lower the inner rows of the junction roads' other lanes.
  for (std::size_t t = 0; t < mesh.triangles();) {
    std::size_t end = t;
    std::uint32_t lo = mesh.indices[3 * t], hi = lo;
    while (end < mesh.triangles() && mesh.lanes[end] == mesh.lanes[t] &&
           mesh.sections[end] == mesh.sections[t]) {
      for (int k = 0; k < 3; ++k) {
        lo = std::min(lo, mesh.indices[3 * end + k]);
        hi = std::max(hi, mesh.indices[3 * end + k]);
      }
      ++end;
    }
    const bool in_junction =
        net.roads[static_cast<std::size_t>(mesh.lanes[t].road)].junction_index >= 0;
    if (in_junction && colour_of(t) != carriageway) {
      for (std::uint32_t i = lo + 2; i + 2 <= hi; ++i)
        (*v)[i].z() -= static_cast<float>(kJunctionVergeDrop);
    }
    t = end;
  }
  osg::ref_ptr<osg::DrawElementsUInt> tris = new osg::DrawElementsUInt(GL_TRIANGLES);
  tris->reserve(mesh.indices.size());
  for (std::size_t t = 0; t < mesh.triangles(); ++t) {
    const std::uint32_t a = mesh.indices[3 * t], b = mesh.indices[3 * t + 1],
                        cc = mesh.indices[3 * t + 2];
    tris->push_back(a);
    tris->push_back(b);
    tris->push_back(cc);
    // Area-weighted normals, summed per vertex (a lane's strip shares its vertices).
    const osg::Vec3 face = ((*v)[b] - (*v)[a]) ^ ((*v)[cc] - (*v)[a]);
    for (auto idx : {a, b, cc})
      (*n)[idx] += face;
    const auto rgb = colour_of(t);
    for (auto idx : {a, b, cc})
      (*c)[idx].set(rgb[0], rgb[1], rgb[2], 1.0f);
  }
  for (auto& nn : *n) {
    if (nn.length2() < 1e-12f)
      nn.set(0, 0, 1);
    nn.normalize();
  }
  osg::ref_ptr<osg::Geometry> g = new_geometry();
  g->setVertexArray(v);
  g->setNormalArray(n, osg::Array::BIND_PER_VERTEX);
  g->setColorArray(c, osg::Array::BIND_PER_VERTEX);
  g->addPrimitiveSet(tris);
  if (stats != nullptr)
    stats->surface_triangles = mesh.triangles();
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(g);
  return geode;
}

osg::ref_ptr<osg::Geode> marks_geode(const odr::RoadNetwork& net, RoadNodeStats* stats) {
  osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array;
  osg::ref_ptr<osg::Vec4Array> c = new osg::Vec4Array;
  osg::ref_ptr<osg::DrawElementsUInt> tris = new osg::DrawElementsUInt(GL_TRIANGLES);
  // The centre of every strip as a line as well: a mark narrower than a pixel (far away, or
  // from the top camera at 8 px/m) falls between the pixel centres as triangles and vanishes;
  // a line always lights at least one pixel across.
  osg::ref_ptr<osg::DrawElementsUInt> lines = new osg::DrawElementsUInt(GL_LINES);
  for (const MarkStrip& s : lane_mark_strips(net, kRoadTolerance)) {
    const auto base = static_cast<std::uint32_t>(v->size());
    const osg::Vec4 colour(s.colour[0], s.colour[1], s.colour[2], 1.0f);
    auto vec = [](const std::array<double, 3>& p) {
      return osg::Vec3(static_cast<float>(p[0]), static_cast<float>(p[1]),
                       static_cast<float>(p[2]));
    };
    for (std::size_t i = 0; i < s.left.size(); ++i) {
      v->push_back(vec(s.left[i]));
      v->push_back(vec(s.right[i]));
      v->push_back((vec(s.left[i]) + vec(s.right[i])) * 0.5f);
      for (int k = 0; k < 3; ++k)
        c->push_back(colour);
    }
    for (std::uint32_t i = 0; i + 1 < s.left.size(); ++i) {
      const std::uint32_t l0 = base + 3 * i, r0 = l0 + 1, m0 = l0 + 2, l1 = l0 + 3, r1 = l0 + 4,
                          m1 = l0 + 5;
      for (auto idx : {r0, r1, l1, r0, l1, l0})
        tris->push_back(idx);
      lines->push_back(m0);
      lines->push_back(m1);
    }
  }
  osg::ref_ptr<osg::Geometry> g = new_geometry();
  g->setVertexArray(v);
  g->setColorArray(c, osg::Array::BIND_PER_VERTEX);
  g->setNormalArray(filled<osg::Vec3Array>(1, osg::Vec3(0, 0, 1)), osg::Array::BIND_OVERALL);
  g->addPrimitiveSet(tris);
  g->addPrimitiveSet(lines);
  if (stats != nullptr)
    stats->mark_triangles = tris->size() / 3;
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(g);
  osg::StateSet* ss = geode->getOrCreateStateSet();
  ss->setAttributeAndModes(new osg::PolygonOffset(-2.0f, -4.0f), osg::StateAttribute::ON);
  ss->setMode(GL_POLYGON_OFFSET_LINE, osg::StateAttribute::ON);
  ss->setRenderBinDetails(1, "RenderBin");
  return geode;
}

/// Grass, darker where the ground is steep, with patches of ~100 m so that motion over level
/// ground shows.
osg::Vec4 grass(double x, double y, double nz) {
  const double slope = std::sqrt(std::max(0.0, 1.0 / (nz * nz) - 1.0));
  const double shade = (1.0 - 0.35 * std::min(1.0, slope / 0.6)) *
                       (1.0 + 0.04 * std::sin(x / 37.0) * std::sin(y / 53.0));
  return {static_cast<float>(0.33 * shade), static_cast<float>(0.45 * shade),
          static_cast<float>(0.24 * shade), 1.0f};
}

/// Vertices, normals and colours of one drawable of the ground.
struct GroundPiece {
  osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array;
  osg::ref_ptr<osg::Vec3Array> n = new osg::Vec3Array;
  osg::ref_ptr<osg::Vec4Array> c = new osg::Vec4Array;
  osg::ref_ptr<osg::DrawElementsUInt> tris = new osg::DrawElementsUInt(GL_TRIANGLES);
  void add(double x, double y, double z, const odr::Vertex& normal) {
    v->push_back(osg::Vec3(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)));
    n->push_back(osg::Vec3(static_cast<float>(normal.x), static_cast<float>(normal.y),
                           static_cast<float>(normal.z)));
    c->push_back(grass(x, y, normal.z));
  }
  osg::ref_ptr<osg::Geometry> build() const {
    osg::ref_ptr<osg::Geometry> g = new_geometry();
    g->setVertexArray(v);
    g->setNormalArray(n, osg::Array::BIND_PER_VERTEX);
    g->setColorArray(c, osg::Array::BIND_PER_VERTEX);
    g->addPrimitiveSet(tris);
    return g;
  }
};

/// Rings around the terrain's border, out to beyond the fog's end, each at the height of the
/// border node it continues (the ground goes on level, as Terrain::height_at() does): the
/// horizon. Every border node is a vertex of the first ring, so no crack opens between the
/// terrain and the skirt. In pieces of kSkirtRun border nodes, so that those behind the camera
/// are culled.
void add_skirt(const odr::Terrain& t, osg::Geode& geode, std::size_t& triangles) {
  struct Edge {
    std::size_t i, j;
    double dx, dy;  ///< outwards (corners: diagonally)
  };
  const std::size_t nx = t.columns(), ny = t.rows();
  std::vector<Edge> loop;
  // Counter-clockwise round the border seen from above: south row, east column, north row,
  // west column.
  for (std::size_t i = 0; i + 1 < nx; ++i)
    loop.push_back({i, 0, i == 0 ? -1.0 : 0.0, -1.0});
  for (std::size_t j = 0; j + 1 < ny; ++j)
    loop.push_back({nx - 1, j, 1.0, j == 0 ? -1.0 : 0.0});
  for (std::size_t i = nx - 1; i > 0; --i)
    loop.push_back({i, ny - 1, i == nx - 1 ? 1.0 : 0.0, 1.0});
  for (std::size_t j = ny - 1; j > 0; --j)
    loop.push_back({0, j, -1.0, j == ny - 1 ? 1.0 : 0.0});
  // The fog (250 m to 2 km from the eye) interpolates well over these steps.
  constexpr double kRings[] = {0.0, 25.0, 80.0, 200.0, 500.0, 1000.0, 2000.0, 3500.0};
  constexpr std::size_t kSkirtRun = 32;
  const odr::Vertex up{0, 0, 1};
  for (std::size_t first = 0; first < loop.size(); first += kSkirtRun) {
    GroundPiece piece;
    const std::size_t m = std::min(kSkirtRun, loop.size() - first) + 1;  // closing the loop
    for (double d : kRings) {
      for (std::size_t k = 0; k < m; ++k) {
        const Edge& e = loop[(first + k) % loop.size()];
        piece.add(t.min_x() + t.cell() * static_cast<double>(e.i) + e.dx * d,
                  t.min_y() + t.cell() * static_cast<double>(e.j) + e.dy * d, t.node(e.i, e.j), up);
      }
    }
    for (std::size_t r = 0; r + 1 < std::size(kRings); ++r) {
      for (std::size_t k = 0; k + 1 < m; ++k) {
        const auto a = static_cast<std::uint32_t>(r * m + k);
        const auto b = a + 1;
        const auto a1 = static_cast<std::uint32_t>(a + m), b1 = a1 + 1;
        // The loop runs counter-clockwise, outwards is to its right: a, a1, b1 and a, b1, b are
        // counter-clockwise seen from above.
        for (auto idx : {a, a1, b1, a, b1, b})
          piece.tris->push_back(idx);
      }
    }
    triangles += piece.tris->size() / 3;
    geode.addDrawable(piece.build());
  }
}

/// One tile of the terrain: nodes [i0, i1] x [j0, j1], split along the (i, j)-(i + 1, j + 1)
/// diagonal as Terrain::height_at() interpolates. Neighbouring tiles repeat their common
/// border's vertices exactly, so no crack opens between them. @p whole: only the tile's corners
/// (a level terrain, where every tile is drawn so and the cells in between add nothing).
osg::ref_ptr<osg::Geode> terrain_tile(const odr::Terrain& terrain, const odr::TerrainMesh& mesh,
                                      std::size_t i0, std::size_t i1, std::size_t j0,
                                      std::size_t j1, bool whole, std::size_t& triangles) {
  const std::size_t nx = terrain.columns();
  std::vector<std::size_t> is, js;
  for (std::size_t i = i0; i <= i1; i += whole ? i1 - i0 : 1)
    is.push_back(i);
  for (std::size_t j = j0; j <= j1; j += whole ? j1 - j0 : 1)
    js.push_back(j);
  const auto w = static_cast<std::uint32_t>(is.size());
  GroundPiece piece;
  for (std::size_t j : js) {
    for (std::size_t i : is) {
      const odr::Vertex& p = mesh.vertices[j * nx + i];
      piece.add(p.x, p.y, p.z, mesh.normals[j * nx + i]);
    }
  }
  for (std::uint32_t j = 0; j + 1 < js.size(); ++j) {
    for (std::uint32_t i = 0; i + 1 < w; ++i) {
      const std::uint32_t v00 = j * w + i, v10 = v00 + 1, v01 = v00 + w, v11 = v01 + 1;
      for (auto idx : {v00, v10, v11, v00, v11, v01})
        piece.tris->push_back(idx);
    }
  }
  triangles += piece.tris->size() / 3;
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(piece.build());
  return geode;
}

/// The terrain in tiles of kTile x kTile cells, each a node of its own, so that the cull
/// traversal drops those outside the view (the chase camera sees about a third of them). (A
/// coarser grid for distant tiles saved nothing measurable on llvmpipe and opened pixel cracks
/// where a coarse tile met a fine one: not done.)
osg::ref_ptr<osg::Group> terrain_node(const odr::RoadNetwork& net, RoadNodeStats* stats) {
  constexpr std::size_t kTile = 16;
  const odr::Terrain terrain(net);
  const odr::TerrainMesh mesh = terrain.mesh();
  osg::ref_ptr<osg::Group> group = new osg::Group;
  group->setName("terrain");
  std::size_t triangles = 0;
  const std::size_t nx = terrain.columns(), ny = terrain.rows();
  // A level map (every road at one height) has a level terrain: drawn in 4 m cells it cost
  // llvmpipe half its frame rate on a 3 km straight road (60 -> 30 fps, view3d_latency_bench),
  // for nothing, so each tile is then one quad.
  double lowest = terrain.node(0, 0), highest = lowest;
  for (std::size_t j = 0; j < ny; ++j) {
    for (std::size_t i = 0; i < nx; ++i) {
      lowest = std::min(lowest, terrain.node(i, j));
      highest = std::max(highest, terrain.node(i, j));
    }
  }
  const bool level = highest - lowest < 1e-3;
  for (std::size_t j0 = 0; j0 + 1 < ny; j0 += kTile) {
    for (std::size_t i0 = 0; i0 + 1 < nx; i0 += kTile) {
      const std::size_t i1 = std::min(i0 + kTile, nx - 1), j1 = std::min(j0 + kTile, ny - 1);
      group->addChild(terrain_tile(terrain, mesh, i0, i1, j0, j1, level, triangles));
    }
  }
  osg::ref_ptr<osg::Geode> skirt = new osg::Geode;
  add_skirt(terrain, *skirt, triangles);
  group->addChild(skirt);
  if (stats != nullptr)
    stats->terrain_triangles = triangles;
  // The ground writes depth: on hills a near slope must hide what lies behind it (drawn without
  // depth writes, as the flat ground was, a far hill would paint over a near one and roads
  // behind a crest would show through it). The road wins over it by the kerb drop, 5 cm, which
  // the depth buffer resolves to a few hundred metres (beyond, the fog has most of it); the
  // polygon offset adds a little on 24-bit depth buffers (on llvmpipe's 32-bit one its unit
  // is too small to count).
  osg::StateSet* ss = group->getOrCreateStateSet();
  ss->setAttributeAndModes(new osg::PolygonOffset(1.0f, 2.0f), osg::StateAttribute::ON);
  return group;
}

}  // namespace

std::array<float, 3> lane_colour(const std::string& type) {
  if (type == "shoulder" || type == "stop" || type == "parking")
    return {0.42f, 0.42f, 0.41f};
  if (type == "border" || type == "curb" || type == "median" || type == "restricted")
    return {0.62f, 0.61f, 0.58f};
  if (type == "sidewalk" || type == "walking")
    return {0.70f, 0.67f, 0.62f};
  if (type == "biking")
    return {0.55f, 0.30f, 0.26f};
  if (type == "none")
    return {0.36f, 0.40f, 0.30f};
  return {0.27f, 0.27f, 0.28f};  // driving, entry, exit, ramps, bidirectional, bus, taxi, HOV
}

std::array<float, 3> mark_colour(const std::string& colour) {
  if (colour == "yellow")
    return {0.95f, 0.78f, 0.10f};
  if (colour == "blue")
    return {0.15f, 0.35f, 0.90f};
  if (colour == "green")
    return {0.15f, 0.70f, 0.25f};
  if (colour == "red")
    return {0.85f, 0.10f, 0.10f};
  if (colour == "orange")
    return {0.95f, 0.50f, 0.10f};
  return {0.95f, 0.95f, 0.95f};  // standard, white
}

std::vector<MarkStrip> lane_mark_strips(const map::odr::RoadNetwork& net, double eps) {
  std::vector<MarkStrip> out;
  for (const odr::Road& road : net.roads) {
    if (road.junction_index >= 0)
      continue;
    for (std::size_t k = 0; k < road.sections.size(); ++k) {
      const odr::LaneSection& ls = road.sections[k];
      add_lane_marks(road, k, ls.center, eps, out);
      for (const auto* side : {&ls.left, &ls.right})
        for (const odr::Lane& lane : *side)
          add_lane_marks(road, k, lane, eps, out);
    }
  }
  return out;
}

osg::ref_ptr<osg::Node> make_road_node(const map::odr::RoadNetwork& net, RoadNodeStats* stats) {
  osg::ref_ptr<osg::Group> g = new osg::Group;
  g->setName("roads");
  g->addChild(surface_geode(net, stats));
  g->addChild(terrain_node(net, stats));
  g->addChild(marks_geode(net, stats));
  return g;
}

}  // namespace tb::client::view3d
