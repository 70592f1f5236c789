#include "network-emulator/radio/spatial_grid.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace tb::emu::radio {

SpatialGrid::SpatialGrid(double cell_m) : cell_m_(cell_m) {
  if (!(cell_m > 0.0) || !std::isfinite(cell_m))
    throw std::invalid_argument("spatial grid: cell width " + std::to_string(cell_m) +
                                " m must be positive and finite");
}

SpatialGrid::Cell SpatialGrid::cell_of(const Position& p) const {
  return {static_cast<std::int64_t>(std::floor(p[0] / cell_m_)),
          static_cast<std::int64_t>(std::floor(p[1] / cell_m_))};
}

void SpatialGrid::erase_from_cell(const Where& w) {
  auto it = cells_.find(w.cell);
  auto& v = it->second;
  if (w.index + 1 != v.size()) {
    v[w.index] = v.back();
    where_[v[w.index].id].index = w.index;
  }
  v.pop_back();
  if (v.empty())
    cells_.erase(it);
}

void SpatialGrid::place(Id id, const Position& p) {
  const Cell cell = cell_of(p);
  auto it = where_.find(id);
  if (it != where_.end()) {
    if (it->second.cell == cell) {
      cells_[cell][it->second.index].p = p;
      return;
    }
    erase_from_cell(it->second);
  }
  auto& v = cells_[cell];
  v.push_back({id, p});
  where_[id] = {cell, v.size() - 1};
}

void SpatialGrid::remove(Id id) {
  auto it = where_.find(id);
  if (it == where_.end())
    return;
  const Where w = it->second;
  where_.erase(it);
  erase_from_cell(w);  // the entry it moves into the hole is another station's
}

void SpatialGrid::within(const Position& p, double radius_m, std::vector<Id>& out) const {
  if (!(radius_m >= 0.0))
    return;
  const Cell c = cell_of(p);
  const auto reach = static_cast<std::int64_t>(std::ceil(radius_m / cell_m_));
  const double r2 = radius_m * radius_m;
  for (std::int64_t dx = -reach; dx <= reach; ++dx) {
    for (std::int64_t dy = -reach; dy <= reach; ++dy) {
      const auto it = cells_.find({c.first + dx, c.second + dy});
      if (it == cells_.end())
        continue;
      for (const Entry& e : it->second) {
        const double ex = e.p[0] - p[0], ey = e.p[1] - p[1], ez = e.p[2] - p[2];
        if (ex * ex + ey * ey + ez * ez <= r2)
          out.push_back(e.id);
      }
    }
  }
}

}  // namespace tb::emu::radio
