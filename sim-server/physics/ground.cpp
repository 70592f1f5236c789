#include "sim-server/physics/ground.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/map/opendrive/mesh.hpp"

namespace tb::server::physics {

namespace {

/// Chord tolerance of the road surface, m.
constexpr double kRoadEps = 0.02;
/// The verge: drop at the road's edge, width and fall.
constexpr double kVergeDrop = 0.05;
constexpr double kVergeWidth = 40.0;
constexpr double kVergeFall = 0.04;
/// The plane under everything, below the lowest triangle.
constexpr double kPlaneBelow = 1.0;
constexpr double kPlaneCell = 50.0;
/// Maps within this distance of their frame's origin are computed unshifted (float keeps
/// better than a millimetre there), so the built-in layouts compute exactly as before.
constexpr double kUnshiftedExtent = 10000.0;
/// A hit this far outside a triangle (barycentric, of its size) still counts: seams between
/// lane sections and between roads leave no crack a ray falls through.
constexpr double kSeamTolerance = 1e-4;

double outer_left(const map::odr::LaneBorders& b) {
  return b.left.empty() ? b.center : b.left.back();
}
double outer_right(const map::odr::LaneBorders& b) {
  return b.right.empty() ? b.center : b.right.back();
}

}  // namespace

Ground::Ground(const map::ScenarioMap& map, double margin_m, bool mesh) : flat_(!mesh) {
  const auto& net = map.network();
  // The roads' extent, from their surface (coarse where it only gives the bounds).
  const map::odr::RoadMesh roads = map::odr::road_mesh(net, flat_ ? 0.5 : kRoadEps);
  double x0 = std::numeric_limits<double>::max(), y0 = x0, z0 = x0;
  double x1 = std::numeric_limits<double>::lowest(), y1 = x1;
  for (const auto& v : roads.vertices) {
    x0 = std::min(x0, v.x);
    y0 = std::min(y0, v.y);
    z0 = std::min(z0, v.z);
    x1 = std::max(x1, v.x);
    y1 = std::max(y1, v.y);
  }
  if (roads.vertices.empty())
    x0 = y0 = z0 = x1 = y1 = 0.0;
  if (std::max({std::fabs(x0), std::fabs(x1), std::fabs(y0), std::fabs(y1)}) > kUnshiftedExtent) {
    origin_ = {std::round((x0 + x1) / 2000.0) * 1000.0, std::round((y0 + y1) / 2000.0) * 1000.0,
               0.0};
  }
  const double reach = flat_ ? 0.0 : kVergeWidth;
  min_x_ = x0 - origin_.x - reach - margin_m;
  min_y_ = y0 - origin_.y - reach - margin_m;
  max_x_ = x1 - origin_.x + reach + margin_m;
  max_y_ = y1 - origin_.y + reach + margin_m;
  if (!flat_) {
    for (std::size_t t = 0; t < roads.triangles(); ++t) {
      const auto& a = roads.vertices[roads.indices[3 * t]];
      const auto& b = roads.vertices[roads.indices[3 * t + 1]];
      const auto& c = roads.vertices[roads.indices[3 * t + 2]];
      add_triangle({a.x, a.y, a.z}, {b.x, b.y, b.z}, {c.x, c.y, c.z});
    }
    add_verges(net);
    plane_z_ = z0 - kVergeDrop - kVergeFall * kVergeWidth - kPlaneBelow;
  }
  indexed_ = triangles();
  build_index();
  add_plane();
}

void Ground::add_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const auto base = static_cast<std::uint32_t>(vertices_.size());
  for (const Vec3& v : {a, b, c}) {
    vertices_.push_back({static_cast<float>(v.x - origin_.x), static_cast<float>(v.y - origin_.y),
                         static_cast<float>(v.z - origin_.z)});
  }
  indices_.insert(indices_.end(), {base, base + 1, base + 2});
}

void Ground::add_verges(const map::odr::RoadNetwork& net) {
  for (const auto& road : net.roads) {
    for (std::size_t k = 0; k < road.sections.size(); ++k) {
      const auto& ls = road.sections[k];
      double reach = 0.0;
      for (double s : {ls.s, ls.s_end}) {
        const auto b = road.borders(k, s);
        reach = std::max({reach, std::fabs(outer_left(b)), std::fabs(outer_right(b))});
      }
      const std::vector<double> ss =
          map::odr::sample_s(road, ls.s, ls.s_end, kRoadEps, reach + kVergeWidth);
      // Per sample and side: the road's edge (dropped) and the verge's outer edge.
      std::vector<Vec3> edge[2], outer[2];
      for (double s : ss) {
        const auto b = road.borders(k, s);
        const double hdg = road.reference(s).hdg;
        for (int side = 0; side < 2; ++side) {
          const double t = side == 0 ? outer_left(b) : outer_right(b);
          const double sign = side == 0 ? 1.0 : -1.0;
          const auto p = road.surface(s, t);
          const double z = p.z - kVergeDrop;
          edge[side].push_back({p.x, p.y, z});
          outer[side].push_back({p.x - sign * kVergeWidth * std::sin(hdg),
                                 p.y + sign * kVergeWidth * std::cos(hdg),
                                 z - kVergeFall * kVergeWidth});
        }
      }
      for (std::size_t i = 0; i + 1 < ss.size(); ++i) {
        // Left verge: edge, outer, next edge is clockwise from above for a left side; order so
        // that every triangle is counter-clockwise seen from above.
        add_triangle(edge[0][i], edge[0][i + 1], outer[0][i]);
        add_triangle(outer[0][i], edge[0][i + 1], outer[0][i + 1]);
        add_triangle(edge[1][i], outer[1][i], edge[1][i + 1]);
        add_triangle(outer[1][i], outer[1][i + 1], edge[1][i + 1]);
      }
    }
  }
}

void Ground::add_plane() {
  const int nx = std::max(1, static_cast<int>(std::ceil((max_x_ - min_x_) / kPlaneCell)));
  const int ny = std::max(1, static_cast<int>(std::ceil((max_y_ - min_y_) / kPlaneCell)));
  const double dx = (max_x_ - min_x_) / nx, dy = (max_y_ - min_y_) / ny;
  // Vertices are given in the map frame to add_triangle(), which shifts them.
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      const double xa = min_x_ + i * dx + origin_.x, ya = min_y_ + j * dy + origin_.y;
      const Vec3 p00{xa, ya, plane_z_}, p10{xa + dx, ya, plane_z_}, p01{xa, ya + dy, plane_z_},
          p11{xa + dx, ya + dy, plane_z_};
      add_triangle(p00, p10, p11);
      add_triangle(p00, p11, p01);
    }
  }
}

void Ground::build_index() {
  if (indexed_ == 0)
    return;
  // Cells of 4 m: a wheel's ray spans a few decimetres, so a query reads one or two cells.
  cell_ = std::max(4.0, std::sqrt((max_x_ - min_x_) * (max_y_ - min_y_) / 4e6));
  nx_ = static_cast<std::size_t>((max_x_ - min_x_) / cell_) + 1;
  ny_ = static_cast<std::size_t>((max_y_ - min_y_) / cell_) + 1;
  auto cells = [&](std::size_t t, auto&& fn) {
    float bx0 = std::numeric_limits<float>::max(), by0 = bx0;
    float bx1 = std::numeric_limits<float>::lowest(), by1 = bx1;
    for (int k = 0; k < 3; ++k) {
      const auto& v = vertices_[indices_[3 * t + k]];
      bx0 = std::min(bx0, v[0]);
      by0 = std::min(by0, v[1]);
      bx1 = std::max(bx1, v[0]);
      by1 = std::max(by1, v[1]);
    }
    const auto clampc = [](double v, std::size_t n) {
      return static_cast<std::size_t>(std::clamp(v, 0.0, static_cast<double>(n - 1)));
    };
    const std::size_t cx0 = clampc((bx0 - min_x_) / cell_, nx_);
    const std::size_t cx1 = clampc((bx1 - min_x_) / cell_, nx_);
    const std::size_t cy0 = clampc((by0 - min_y_) / cell_, ny_);
    const std::size_t cy1 = clampc((by1 - min_y_) / cell_, ny_);
    for (std::size_t cy = cy0; cy <= cy1; ++cy) {
      for (std::size_t cx = cx0; cx <= cx1; ++cx)
        fn(cy * nx_ + cx);
    }
  };
  cell_start_.assign(nx_ * ny_ + 1, 0);
  for (std::size_t t = 0; t < indexed_; ++t)
    cells(t, [&](std::size_t c) { ++cell_start_[c + 1]; });
  for (std::size_t i = 1; i < cell_start_.size(); ++i)
    cell_start_[i] += cell_start_[i - 1];
  items_.resize(cell_start_.back());
  std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t t = 0; t < indexed_; ++t)
    cells(t, [&](std::size_t c) { items_[fill[c]++] = static_cast<std::uint32_t>(t); });
}

std::optional<GroundHit> Ground::cast(const Vec3& from, const Vec3& to) const {
  // A car whose state blew up (NaN, infinity) finds no ground rather than an index out of range.
  for (double v : {from.x, from.y, from.z, to.x, to.y, to.z}) {
    if (!std::isfinite(v))
      return std::nullopt;
  }
  const Vec3 d{to.x - from.x, to.y - from.y, to.z - from.z};
  std::optional<GroundHit> best;
  if (indexed_ > 0) {
    const auto cell = [&](double v, double lo, std::size_t n) {
      return static_cast<std::size_t>(
          std::clamp((v - lo) / cell_, 0.0, static_cast<double>(n - 1)));
    };
    const std::size_t cx0 = cell(std::min(from.x, to.x), min_x_, nx_);
    const std::size_t cx1 = cell(std::max(from.x, to.x), min_x_, nx_);
    const std::size_t cy0 = cell(std::min(from.y, to.y), min_y_, ny_);
    const std::size_t cy1 = cell(std::max(from.y, to.y), min_y_, ny_);
    for (std::size_t cy = cy0; cy <= cy1; ++cy) {
      for (std::size_t cx = cx0; cx <= cx1; ++cx) {
        const std::size_t c = cy * nx_ + cx;
        for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
          const std::uint32_t t = items_[k];
          const auto& A = vertices_[indices_[3 * t]];
          const auto& B = vertices_[indices_[3 * t + 1]];
          const auto& C = vertices_[indices_[3 * t + 2]];
          // Möller–Trumbore.
          const double e1[3] = {B[0] - A[0], B[1] - A[1], B[2] - A[2]};
          const double e2[3] = {C[0] - A[0], C[1] - A[1], C[2] - A[2]};
          const double p[3] = {d.y * e2[2] - d.z * e2[1], d.z * e2[0] - d.x * e2[2],
                               d.x * e2[1] - d.y * e2[0]};
          const double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
          if (std::fabs(det) < 1e-12)
            continue;
          const double inv = 1.0 / det;
          const double s[3] = {from.x - A[0], from.y - A[1], from.z - A[2]};
          const double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * inv;
          if (u < -kSeamTolerance || u > 1.0 + kSeamTolerance)
            continue;
          const double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2],
                               s[0] * e1[1] - s[1] * e1[0]};
          const double v = (d.x * q[0] + d.y * q[1] + d.z * q[2]) * inv;
          if (v < -kSeamTolerance || u + v > 1.0 + kSeamTolerance)
            continue;
          const double f = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv;
          if (f < 0.0 || f > 1.0 || (best && f >= best->fraction))
            continue;
          Vec3 n{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                 e1[0] * e2[1] - e1[1] * e2[0]};
          const double len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
          const double flip = n.x * d.x + n.y * d.y + n.z * d.z > 0 ? -1.0 : 1.0;
          n = {flip * n.x / len, flip * n.y / len, flip * n.z / len};
          best = GroundHit{{from.x + f * d.x, from.y + f * d.y, from.z + f * d.z}, n, f};
        }
      }
    }
  }
  if (best)
    return best;
  // The plane, exactly, within the ground's extent.
  if (from.z < plane_z_ || to.z > plane_z_ || from.z == to.z)
    return std::nullopt;
  const double f = (from.z - plane_z_) / (from.z - to.z);
  const Vec3 hit{from.x + f * d.x, from.y + f * d.y, plane_z_};
  if (hit.x < min_x_ || hit.x > max_x_ || hit.y < min_y_ || hit.y > max_y_)
    return std::nullopt;
  return GroundHit{hit, {0, 0, 1}, f};
}

}  // namespace tb::server::physics
