#pragma once
/// @file SpatialGrid: which stations are near a point, without looking at every station (issue
/// 33, range culling). Square cells of a fixed width over the ENU plane; a station sits in the
/// cell of its east/north position and moves when its position does. A query within a radius
/// looks only at the cells the radius can reach, so its cost grows with the stations nearby,
/// not with all of them. Height is left out of the cells (a 3-D distance is never shorter than
/// its horizontal part) but counts in the distance test.

#include <array>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

namespace tb::emu::radio {

class SpatialGrid {
 public:
  using Id = std::uint32_t;
  using Position = std::array<double, 3>;

  /// @p cell_m > 0: one channel's maximum range wide, so that a query for that range reads
  /// the 3×3 cells around the sender. @throws std::invalid_argument otherwise.
  explicit SpatialGrid(double cell_m);

  double cell_m() const { return cell_m_; }
  std::size_t size() const { return where_.size(); }
  std::size_t cells() const { return cells_.size(); }

  /// Puts @p id at @p p, moving it from its old cell if it had one.
  void place(Id id, const Position& p);
  void remove(Id id);
  bool contains(Id id) const { return where_.contains(id); }

  /// Appends to @p out (not cleared) every station within @p radius_m (3-D, inclusive) of @p p,
  /// in no particular order.
  void within(const Position& p, double radius_m, std::vector<Id>& out) const;

 private:
  using Cell = std::pair<std::int64_t, std::int64_t>;
  struct CellHash {
    std::size_t operator()(const Cell& c) const {
      return std::hash<std::int64_t>()(c.first * 0x9E3779B97F4A7C15ull ^ c.second);
    }
  };
  struct Entry {
    Id id;
    Position p;
  };
  struct Where {
    Cell cell;
    std::size_t index;  ///< in cells_[cell]
  };

  Cell cell_of(const Position& p) const;
  void erase_from_cell(const Where& w);

  double cell_m_;
  std::unordered_map<Cell, std::vector<Entry>, CellHash> cells_;
  std::unordered_map<Id, Where> where_;
};

}  // namespace tb::emu::radio
