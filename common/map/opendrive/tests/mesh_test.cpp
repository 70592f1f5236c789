// The road-surface mesh and the sampled lane lines on the shared maps.

#include "common/map/opendrive/mesh.hpp"
#include "common/map/opendrive/tests/shared_maps.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <map>
#include <set>
#include <tuple>
#include <vector>

#include "common/map/opendrive/reader.hpp"

namespace tb::map::odr {
namespace {

namespace fs = std::filesystem;

using test::shared_maps;

/// Lane area by quadrature of the width (fine steps, independent of the mesh's sampling).
double lane_area(const Road& r) {
  double area = 0.0;
  for (std::size_t k = 0; k < r.sections.size(); ++k) {
    const LaneSection& ls = r.sections[k];
    const int n = 2000;
    const double h = (ls.s_end - ls.s) / n;
    for (int i = 0; i < n; ++i) {
      const double s = ls.s + (i + 0.5) * h;
      const LaneBorders b = r.borders(k, s);
      const double kappa = r.curvature(s);
      // On a curve a strip between t0 and t1 has area h * (t1 - t0) * (1 - k (t0 + t1) / 2).
      auto strip = [&](double t0, double t1) {
        return std::fabs(t1 - t0) * (1 - kappa * (t0 + t1) / 2);
      };
      for (std::size_t j = 0; j < b.left.size(); ++j) {
        area += h * strip(b.inner(static_cast<int>(j) + 1), b.left[j]);
      }
      for (std::size_t j = 0; j < b.right.size(); ++j) {
        area += h * strip(b.inner(-static_cast<int>(j) - 1), b.right[j]);
      }
    }
  }
  return area;
}

TEST(RoadMesh, CoversEveryLaneCounterClockwiseWithTheLanesArea) {
  for (const auto& e : fs::directory_iterator(shared_maps())) {
    if (e.path().extension() != ".xodr")
      continue;
    SCOPED_TRACE(e.path().filename().string());
    const RoadNetwork net = load_opendrive(e.path().string());
    const RoadMesh mesh = road_mesh(net, 0.02);
    ASSERT_EQ(mesh.lanes.size(), mesh.triangles());
    ASSERT_EQ(mesh.sections.size(), mesh.triangles());
    const LaneLocator loc(net);
    double mesh_area = 0.0;
    std::size_t located = 0;
    for (std::size_t i = 0; i < mesh.triangles(); ++i) {
      const Vertex& a = mesh.vertices[mesh.indices[3 * i]];
      const Vertex& b = mesh.vertices[mesh.indices[3 * i + 1]];
      const Vertex& c = mesh.vertices[mesh.indices[3 * i + 2]];
      const double cross = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
      EXPECT_GE(cross, -1e-9) << "triangle " << i << " is clockwise";
      mesh_area += cross / 2;
      if (cross < 1e-6) {  // degenerate where a lane starts or ends with zero width
        ++located;
        continue;
      }
      // The centroid of a triangle lies on its road (on its lane, or a neighbour where the
      // lane starts or ends with zero width).
      const LaneRef want = mesh.lanes[i];
      const auto at = loc.locate((a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3,
                                 (a.z + b.z + c.z) / 3, std::span<const LaneRef>(&want, 1));
      if (at && at->ref.road == want.road) {
        ++located;
        // The triangle's section is the one its centroid lies in.
        const LaneSection& ls = net.roads[want.road].sections.at(mesh.sections[i]);
        EXPECT_GE(at->s, ls.s - 1e-6) << "triangle " << i;
        EXPECT_LE(at->s, ls.s_end + 1e-6) << "triangle " << i;
      }
    }
    double area = 0.0;
    for (const Road& r : net.roads)
      area += lane_area(r);
    EXPECT_NEAR(mesh_area, area, 0.002 * area);
    EXPECT_GT(static_cast<double>(located), 0.99 * static_cast<double>(mesh.triangles()));
  }
}

/// The first and the last (inner, outer) vertex pair of each lane strip of @p mesh, keyed by
/// road, then section: a strip's vertices run along s, two (inner, outer) per sample.
struct StripEnds {
  std::vector<Vertex> first, last;
};
std::map<int, std::map<std::uint32_t, StripEnds>> strip_ends(const RoadMesh& mesh) {
  std::map<std::tuple<int, std::uint32_t, int>, std::set<std::uint32_t>> strips;
  for (std::size_t i = 0; i < mesh.triangles(); ++i) {
    auto& v = strips[{mesh.lanes[i].road, mesh.sections[i], mesh.lanes[i].lane}];
    v.insert(mesh.indices.begin() + static_cast<std::ptrdiff_t>(3 * i),
             mesh.indices.begin() + static_cast<std::ptrdiff_t>(3 * i + 3));
  }
  std::map<int, std::map<std::uint32_t, StripEnds>> out;
  for (const auto& [key, idx] : strips) {
    StripEnds& e = out[std::get<0>(key)][std::get<1>(key)];
    const auto lo = idx.begin();
    const auto hi = idx.rbegin();
    e.first.push_back(mesh.vertices[*lo]);
    e.first.push_back(mesh.vertices[*std::next(lo)]);
    e.last.push_back(mesh.vertices[*hi]);
    e.last.push_back(mesh.vertices[*std::next(hi)]);
  }
  return out;
}

double nearest(const Vertex& v, const std::vector<Vertex>& others) {
  double best = 1e300;
  for (const Vertex& o : others)
    best = std::min(best, std::hypot(v.x - o.x, v.y - o.y, v.z - o.z));
  return best;
}

TEST(RoadMesh, VerticesLieOnTheSurfaceAndSectionsMeet) {
  {
    const RoadNetwork net = load_opendrive((shared_maps() / "crest-curve.xodr").string());
    const RoadMesh mesh = road_mesh(net, 0.02);
    const LaneLocator loc(net);
    std::size_t checked = 0;
    for (const Vertex& v : mesh.vertices) {
      const auto at = loc.locate(v.x, v.y, v.z);
      if (!at)
        continue;  // the outermost border: on no lane's inside
      EXPECT_NEAR(at->z, v.z, 1e-6);
      ++checked;
    }
    EXPECT_GT(checked, mesh.vertices.size() / 2);
  }
  // Where one lane section ends, the next begins: every border vertex of the last row of one
  // section has a vertex of the next section's first row within 1 mm, and the other way round
  // (mesh vertices against mesh vertices; the files' lane widths are continuous there, e.g.
  // multi_lanesections' lane 2 widens 0.0009*100^2 - 6e-6*100^3 = 3 m to meet the next 3 m).
  std::size_t boundaries = 0;
  for (const char* file : {"multi_lanesections.xodr", "highway_merge.xodr", "highway_exit.xodr"}) {
    SCOPED_TRACE(file);
    const RoadNetwork net = load_opendrive((shared_maps() / file).string());
    const RoadMesh mesh = road_mesh(net, 0.02);
    for (const auto& [road, sections] : strip_ends(mesh)) {
      for (auto it = sections.begin(); std::next(it) != sections.end(); ++it) {
        const auto next = std::next(it);
        if (next->first != it->first + 1)
          continue;  // a section without a strip in between
        SCOPED_TRACE("road index " + std::to_string(road) + ", section " +
                     std::to_string(it->first));
        for (const Vertex& v : it->second.last)
          EXPECT_LT(nearest(v, next->second.first), 1e-3);
        for (const Vertex& v : next->second.first)
          EXPECT_LT(nearest(v, it->second.last), 1e-3);
        ++boundaries;
      }
    }
  }
  EXPECT_GE(boundaries, 4u);  // multi_lanesections alone has five sections on road 0
}

TEST(LaneLines, FollowTheTolerance) {
  const RoadNetwork net = load_opendrive((shared_maps() / "circular_road.xodr").string());
  const Road& r = net.roads[1];  // the loop's arc
  ASSERT_GT(std::fabs(r.curvature(10)), 0.005);
  const auto coarse = lane_centre(r, 0, -1, 0.1);
  const auto fine = lane_centre(r, 0, -1, 0.001);
  EXPECT_GT(fine.size(), 3 * coarse.size());
  // Every chord midpoint of the coarse line lies within 0.1 m of the lane centre.
  const LaneLocator loc(net);
  for (std::size_t i = 0; i + 1 < coarse.size(); ++i) {
    const double mx = (coarse[i].x + coarse[i + 1].x) / 2;
    const double my = (coarse[i].y + coarse[i + 1].y) / 2;
    const auto at = loc.locate(mx, my);
    ASSERT_TRUE(at);
    EXPECT_LT(std::fabs(at->t - lane_centre_t(net.roads[static_cast<std::size_t>(at->ref.road)], -1,
                                              at->s)),
              0.1);
  }
  const auto border = lane_border(r, 0, -1, 0.02);
  const auto p = r.surface(0, r.borders(0, 0).outer(-1));
  EXPECT_NEAR(border.front().x, p.x, 1e-9);
  EXPECT_NEAR(border.front().y, p.y, 1e-9);
}

}  // namespace
}  // namespace tb::map::odr
