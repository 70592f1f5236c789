#include "sim-server/physics/ground.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/map/opendrive/mesh.hpp"

namespace tb::server::physics {

namespace {

/// Chord tolerance of the road surface, m.
constexpr double kRoadEps = 0.02;
/// The flat maps' plane, in cells of this size for Bullet.
constexpr double kPlaneCell = 50.0;
/// Maps within this distance of their frame's origin are computed unshifted (float keeps
/// better than a millimetre there), so the built-in layouts compute exactly as before.
constexpr double kUnshiftedExtent = 10000.0;
/// A hit this far outside a triangle (barycentric, of its size) still counts: seams between
/// lane sections and between roads leave no crack a ray falls through.
constexpr double kSeamTolerance = 1e-4;

}  // namespace

Ground::Ground(const map::ScenarioMap& map, double margin_m, bool mesh) : flat_(!mesh) {
  const auto& net = map.network();
  // The roads' extent, from their surface (coarse where it only gives the bounds).
  const map::odr::RoadMesh roads = map::odr::road_mesh(net, flat_ ? 0.5 : kRoadEps);
  const map::odr::Extent e = map::odr::extent(roads);
  double x0 = e.min_x, y0 = e.min_y, x1 = e.max_x, y1 = e.max_y;
  if (std::max({std::fabs(x0), std::fabs(x1), std::fabs(y0), std::fabs(y1)}) > kUnshiftedExtent) {
    origin_ = {std::round((x0 + x1) / 2000.0) * 1000.0, std::round((y0 + y1) / 2000.0) * 1000.0,
               0.0};
  }
  min_x_ = x0 - origin_.x - margin_m;
  min_y_ = y0 - origin_.y - margin_m;
  max_x_ = x1 - origin_.x + margin_m;
  max_y_ = y1 - origin_.y + margin_m;
  if (!flat_) {
    for (std::size_t t = 0; t < roads.triangles(); ++t) {
      const auto& a = roads.vertices[roads.indices[3 * t]];
      const auto& b = roads.vertices[roads.indices[3 * t + 1]];
      const auto& c = roads.vertices[roads.indices[3 * t + 2]];
      add_triangle({a.x, a.y, a.z}, {b.x, b.y, b.z}, {c.x, c.y, c.z});
    }
    terrain_.emplace(roads, map::odr::TerrainOptions{.margin_m = margin_m});
    min_x_ = terrain_->min_x() - origin_.x;
    min_y_ = terrain_->min_y() - origin_.y;
    max_x_ = terrain_->max_x() - origin_.x;
    max_y_ = terrain_->max_y() - origin_.y;
  }
  indexed_ = triangles();
  build_index();
  if (terrain_)
    add_terrain();
  else
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

void Ground::add_terrain() {
  const map::odr::Terrain& t = *terrain_;
  terrain_base_ = vertices_.size();
  const map::odr::TerrainMesh m = t.mesh();
  for (const auto& v : m.vertices) {
    vertices_.push_back({static_cast<float>(v.x - origin_.x), static_cast<float>(v.y - origin_.y),
                         static_cast<float>(v.z - origin_.z)});
  }
  const auto base = static_cast<std::uint32_t>(terrain_base_);
  for (std::uint32_t i : m.indices)
    indices_.push_back(base + i);
}

void Ground::add_plane() {
  const int nx = std::max(1, static_cast<int>(std::ceil((max_x_ - min_x_) / kPlaneCell)));
  const int ny = std::max(1, static_cast<int>(std::ceil((max_y_ - min_y_) / kPlaneCell)));
  const double dx = (max_x_ - min_x_) / nx, dy = (max_y_ - min_y_) / ny;
  // Vertices are given in the map frame to add_triangle(), which shifts them.
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      const double xa = min_x_ + i * dx + origin_.x, ya = min_y_ + j * dy + origin_.y;
      const Vec3 p00{xa, ya, 0.0}, p10{xa + dx, ya, 0.0}, p01{xa, ya + dy, 0.0},
          p11{xa + dx, ya + dy, 0.0};
      add_triangle(p00, p10, p11);
      add_triangle(p00, p11, p01);
    }
  }
}

void Ground::build_index() {
  if (indexed_ == 0)
    return;
  // Cells of 2 m: a wheel's ray spans a few decimetres, so a query reads one or two cells.
  cell_ = std::max(2.0, std::sqrt((max_x_ - min_x_) * (max_y_ - min_y_) / 4e6));
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

void Ground::hit_triangle(std::size_t t, const Vec3& from, const Vec3& d,
                          std::optional<GroundHit>& best) const {
  const auto& A = vertices_[indices_[3 * t]];
  const auto& B = vertices_[indices_[3 * t + 1]];
  const auto& C = vertices_[indices_[3 * t + 2]];
  const double e1[3] = {B[0] - A[0], B[1] - A[1], B[2] - A[2]};
  const double e2[3] = {C[0] - A[0], C[1] - A[1], C[2] - A[2]};
  const double p[3] = {d.y * e2[2] - d.z * e2[1], d.z * e2[0] - d.x * e2[2],
                       d.x * e2[1] - d.y * e2[0]};
  const double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
  if (std::fabs(det) < 1e-12)
    return;
  const double inv = 1.0 / det;
  const double s[3] = {from.x - A[0], from.y - A[1], from.z - A[2]};
  const double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * inv;
  if (u < -kSeamTolerance || u > 1.0 + kSeamTolerance)
    return;
  const double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2],
                       s[0] * e1[1] - s[1] * e1[0]};
  const double v = (d.x * q[0] + d.y * q[1] + d.z * q[2]) * inv;
  if (v < -kSeamTolerance || u + v > 1.0 + kSeamTolerance)
    return;
  const double f = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv;
  if (f < 0.0 || f > 1.0 || (best && f >= best->fraction))
    return;
  Vec3 n{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
         e1[0] * e2[1] - e1[1] * e2[0]};
  const double len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  const double flip = n.x * d.x + n.y * d.y + n.z * d.z > 0 ? -1.0 : 1.0;
  n = {flip * n.x / len, flip * n.y / len, flip * n.z / len};
  best = GroundHit{{from.x + f * d.x, from.y + f * d.y, from.z + f * d.z}, n, f};
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
        for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k)
          hit_triangle(items_[k], from, d, best);
      }
    }
  }
  if (terrain_) {
    // The terrain's cells under the ray (its grid starts at the ground's min corner); a ray
    // that leaves the grid finds nothing there.
    const map::odr::Terrain& t = *terrain_;
    const double lo_x = std::min(from.x, to.x), hi_x = std::max(from.x, to.x);
    const double lo_y = std::min(from.y, to.y), hi_y = std::max(from.y, to.y);
    if (hi_x < min_x_ || lo_x > max_x_ || hi_y < min_y_ || lo_y > max_y_)
      return best;
    const auto cell = [&](double v, double lo, std::size_t n) {
      return static_cast<std::size_t>(
          std::clamp(std::floor((v - lo) / t.cell()), 0.0, static_cast<double>(n - 2)));
    };
    const std::size_t i0 = cell(lo_x, min_x_, t.columns()), i1 = cell(hi_x, min_x_, t.columns());
    const std::size_t j0 = cell(lo_y, min_y_, t.rows()), j1 = cell(hi_y, min_y_, t.rows());
    const std::size_t first = indexed_;
    for (std::size_t j = j0; j <= j1; ++j) {
      for (std::size_t i = i0; i <= i1; ++i) {
        const std::size_t tri = first + 2 * (j * (t.columns() - 1) + i);
        hit_triangle(tri, from, d, best);
        hit_triangle(tri + 1, from, d, best);
      }
    }
    return best;
  }
  if (best)
    return best;
  // The flat maps' plane z = 0, exactly, within the ground's extent.
  if (from.z < 0.0 || to.z > 0.0 || from.z == to.z)
    return std::nullopt;
  const double f = from.z / (from.z - to.z);
  const Vec3 hit{from.x + f * d.x, from.y + f * d.y, 0.0};
  if (hit.x < min_x_ || hit.x > max_x_ || hit.y < min_y_ || hit.y > max_y_)
    return std::nullopt;
  return GroundHit{hit, {0, 0, 1}, f};
}

}  // namespace tb::server::physics
