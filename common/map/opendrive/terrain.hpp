#pragma once
/// @file The ground under, beside and between the roads: one height field that the 3D view
/// draws and the physics drives on off the lanes.
///
/// A regular grid of nodes over the roads' extent plus a margin, each cell cut into two
/// triangles along the diagonal from its (i, j) corner to its (i + 1, j + 1) corner; heights
/// in between are linear on those triangles. The heights follow the roads:
/// - every node of a cell that a road triangle's box touches is *pinned* to the lowest of the
///   planes of those road triangles at the node, less the kerb drop (5 cm). Linear
///   interpolation of nodes that each lie the drop below a plane lies the drop below that plane,
///   so the ground is at least the drop below every road triangle at every point under it
///   (the lowest road where roads cross at different heights) and, where one road alone covers
///   it, exactly the drop below it: no gap under a road, no ground through it. A road triangle
///   too thin for its plane to be extrapolated (a lane tapering to nothing) pins the nodes to
///   its lowest corner instead, which keeps the first guarantee;
/// - the other nodes are the discrete harmonic interpolation of the pinned ones (each the mean
///   of its neighbours; no slope across the grid's border): smooth, and never above the highest
///   pinned node nor below the lowest. Solved coarse to fine (each level starts from the
///   coarser one's solution, then Gauss–Seidel sweeps), so building takes time linear in the
///   nodes and is deterministic.
/// Renderer-free and physics-free: the view draws `mesh()`, the physics tests rays against the
/// same triangles.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/map/opendrive/mesh.hpp"

namespace tb::map::odr {

struct TerrainOptions {
  /// Grid spacing, m (made coarser when the extent would need more than max_nodes). 4 m: the
  /// 3D view draws the shipped junction's ground (49 k triangles with the margin) in a few
  /// milliseconds on llvmpipe; at 2 m (194 k) it took 50 ms a frame.
  double cell_m = 4.0;
  /// How far the ground reaches beyond the roads' extent, m.
  double margin_m = 200.0;
  /// How far the ground lies below the road surface at the road's edge (a kerb), m.
  double drop_m = 0.05;
  /// Chord tolerance of the road mesh the ground is fitted to when built from a network, m (the
  /// physics' road mesh: the same triangles, the same ground).
  double road_eps = 0.02;
  std::size_t max_nodes = 1u << 20;
};

/// The ground's triangles, counter-clockwise seen from above, with a unit normal per vertex.
struct TerrainMesh {
  std::vector<Vertex> vertices;
  std::vector<Vertex> normals;
  std::vector<std::uint32_t> indices;
  std::size_t triangles() const { return indices.size() / 3; }
};

class Terrain {
 public:
  /// The ground under @p roads (the surface as odr::road_mesh gives it).
  explicit Terrain(const RoadMesh& roads, const TerrainOptions& options = {});
  /// The ground under the network's road mesh at options.road_eps.
  explicit Terrain(const RoadNetwork& net, const TerrainOptions& options = {});

  /// Height of the ground at (x, y) on the triangles; outside the grid, the height at the
  /// nearest point of its border (the ground goes on level); for a non-finite x or y, the
  /// height of node (0, 0).
  double height_at(double x, double y) const;
  /// Whether (x, y) lies on the grid.
  bool covers(double x, double y) const;

  double min_x() const { return x0_; }
  double min_y() const { return y0_; }
  double max_x() const { return x0_ + cell_ * static_cast<double>(nx_ - 1); }
  double max_y() const { return y0_ + cell_ * static_cast<double>(ny_ - 1); }
  double cell() const { return cell_; }
  /// Nodes along x and y.
  std::size_t columns() const { return nx_; }
  std::size_t rows() const { return ny_; }
  /// Height of node (i, j) at (min_x + i cell, min_y + j cell).
  double node(std::size_t i, std::size_t j) const { return h_[j * nx_ + i]; }
  /// Whether node (i, j) was pinned by a road (else interpolated between them).
  bool pinned(std::size_t i, std::size_t j) const { return pinned_[j * nx_ + i] != 0; }
  double drop() const { return drop_; }

  /// Node (i, j) is vertex j * columns() + i; two triangles per cell, split as height_at() does.
  TerrainMesh mesh() const;

 private:
  void pin(const RoadMesh& roads);
  void solve();

  double x0_ = 0, y0_ = 0, cell_ = 4.0, drop_ = 0.05;
  std::size_t nx_ = 2, ny_ = 2;
  std::vector<double> h_;
  std::vector<std::uint8_t> pinned_;
};

}  // namespace tb::map::odr
