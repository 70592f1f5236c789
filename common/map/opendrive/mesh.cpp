#include "common/map/opendrive/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tb::map::odr {

namespace {

void add_record_starts(const CubicProfile& p, double offset, std::vector<double>& out) {
  for (const CubicRecord& r : p.records())
    out.push_back(r.s + offset);
}

double reach_of(const Road& road, std::size_t section) {
  const LaneSection& ls = road.sections[section];
  double reach = 0.0;
  for (double s : {ls.s, (ls.s + ls.s_end) / 2, ls.s_end}) {
    const LaneBorders b = road.borders(section, s);
    reach = std::max(reach, std::fabs(b.center));
    for (double v : b.left)
      reach = std::max(reach, std::fabs(v));
    for (double v : b.right)
      reach = std::max(reach, std::fabs(v));
  }
  return reach;
}

}  // namespace

std::vector<double> sample_s(const Road& road, double s0, double s1, double eps, double reach,
                             double max_step) {
  std::vector<double> breaks{s0, s1};
  for (const auto& g : road.geometries)
    breaks.push_back(g->s0());
  add_record_starts(road.elevation, 0, breaks);
  add_record_starts(road.superelevation, 0, breaks);
  add_record_starts(road.lane_offset, 0, breaks);
  const LaneSection& ls = road.sections[road.section_index(s0)];
  for (const auto* side : {&ls.left, &ls.right}) {
    for (const Lane& l : *side) {
      add_record_starts(l.width, ls.s, breaks);
      add_record_starts(l.border, ls.s, breaks);
    }
  }
  std::sort(breaks.begin(), breaks.end());
  std::vector<double> out;
  eps = std::max(eps, 1e-4);
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
    const double a = std::max(breaks[i], s0);
    const double b = std::min(breaks[i + 1], s1);
    if (b - a <= 1e-9)
      continue;
    out.push_back(a);
    // A chord of length h on a curve of curvature k deviates by k h^2 / 8; at lateral distance
    // `reach` the curvature seen is k / (1 - k reach). Elevation and superelevation bend z
    // like a curvature of |z''| and |roll'| * reach.
    double s = a;
    while (s < b) {
      const double mid = std::min(b, s + 0.5);
      double k = 0.0;
      for (double q : {s, mid}) {
        const double kc = std::fabs(road.curvature(q));
        const double kr = kc / std::max(0.1, 1.0 - kc * reach);
        const double h = 0.01;
        const double z2 =
            std::fabs(road.elevation.derivative(q + h) - road.elevation.derivative(q)) / h;
        const double r2 = std::fabs(road.superelevation.derivative(q)) * reach;
        k = std::max(k, kr + z2 + r2);
      }
      double step = k > 0 ? std::sqrt(8.0 * eps / k) : max_step;
      step = std::clamp(step, 0.05, max_step);
      s = std::min(b, s + step);
      if (b - s < 1e-6)
        break;
      out.push_back(s);
    }
  }
  out.push_back(s1);
  out.erase(std::unique(out.begin(), out.end(), [](double x, double y) { return y - x < 1e-9; }),
            out.end());
  return out;
}

namespace {
std::vector<Vertex> lane_line(const Road& road, std::size_t section, int lane, double eps,
                              double where) {
  const LaneSection& ls = road.sections[section];
  std::vector<Vertex> out;
  for (double s : sample_s(road, ls.s, ls.s_end, eps, reach_of(road, section))) {
    const LaneBorders b = road.borders(section, s);
    const double t = b.inner(lane) + where * (b.outer(lane) - b.inner(lane));
    const SurfacePose p = road.surface(s, t);
    out.push_back({p.x, p.y, p.z});
  }
  return out;
}
}  // namespace

std::vector<Vertex> lane_border(const Road& road, std::size_t section, int lane, double eps) {
  return lane_line(road, section, lane, eps, 1.0);
}

std::vector<Vertex> lane_centre(const Road& road, std::size_t section, int lane, double eps) {
  return lane_line(road, section, lane, eps, 0.5);
}

RoadMesh road_mesh(const RoadNetwork& net, double eps) {
  RoadMesh mesh;
  for (std::size_t ri = 0; ri < net.roads.size(); ++ri) {
    const Road& road = net.roads[ri];
    for (std::size_t k = 0; k < road.sections.size(); ++k) {
      const LaneSection& ls = road.sections[k];
      const std::vector<double> ss = sample_s(road, ls.s, ls.s_end, eps, reach_of(road, k));
      std::vector<LaneBorders> borders;
      borders.reserve(ss.size());
      for (double s : ss)
        borders.push_back(road.borders(k, s));
      for (const auto* side : {&ls.left, &ls.right}) {
        for (const Lane& lane : *side) {
          const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
          for (std::size_t i = 0; i < ss.size(); ++i) {
            for (double t : {borders[i].inner(lane.id), borders[i].outer(lane.id)}) {
              const SurfacePose p = road.surface(ss[i], t);
              mesh.vertices.push_back({p.x, p.y, p.z});
            }
          }
          for (std::size_t i = 0; i + 1 < ss.size(); ++i) {
            const double w0 = std::fabs(borders[i].outer(lane.id) - borders[i].inner(lane.id));
            const double w1 =
                std::fabs(borders[i + 1].outer(lane.id) - borders[i + 1].inner(lane.id));
            if (w0 < 1e-6 && w1 < 1e-6)
              continue;
            const auto in0 = base + static_cast<std::uint32_t>(2 * i);
            const std::uint32_t out0 = in0 + 1, in1 = in0 + 2, out1 = in0 + 3;
            // Left lanes lie at +t: inner, outer, next inner is counter-clockwise from above;
            // right lanes mirror it.
            const std::uint32_t tri[2][3] = {{in0, out0, in1}, {out0, out1, in1}};
            for (const auto& t3 : tri) {
              if (lane.id > 0) {
                mesh.indices.insert(mesh.indices.end(), {t3[0], t3[2], t3[1]});
              } else {
                mesh.indices.insert(mesh.indices.end(), {t3[0], t3[1], t3[2]});
              }
              mesh.lanes.push_back({static_cast<int>(ri), lane.id});
              mesh.sections.push_back(static_cast<std::uint32_t>(k));
            }
          }
        }
      }
    }
  }
  return mesh;
}

Extent extent(const RoadMesh& mesh) {
  if (mesh.vertices.empty())
    return {};
  Extent e{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
           std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest()};
  for (const Vertex& v : mesh.vertices) {
    e.min_x = std::min(e.min_x, v.x);
    e.min_y = std::min(e.min_y, v.y);
    e.max_x = std::max(e.max_x, v.x);
    e.max_y = std::max(e.max_y, v.y);
  }
  return e;
}

}  // namespace tb::map::odr
