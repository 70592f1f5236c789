#include "network-emulator/radio/spatial_grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>
#include <vector>

#include "network-emulator/radio/channel.hpp"

namespace tb::emu::radio {
namespace {

std::vector<SpatialGrid::Id> within(const SpatialGrid& g, SpatialGrid::Position p, double r) {
  std::vector<SpatialGrid::Id> out;
  g.within(p, r, out);
  std::sort(out.begin(), out.end());
  return out;
}

TEST(SpatialGrid, FindsJustInsideAndNotJustOutside) {
  SpatialGrid g(100);
  g.place(1, {0, 0, 0});
  g.place(2, {99.999, 0, 0});   // same cell
  g.place(3, {100.0, 0, 0});    // next cell, exactly at the radius: heard
  g.place(4, {100.001, 0, 0});  // next cell, just beyond
  g.place(5, {-60, -80, 0});    // 100 m diagonally, in cell (-1, -1)
  g.place(6, {0, 0, 100.5});    // above: the height counts
  EXPECT_EQ(within(g, {0, 0, 0}, 100), (std::vector<SpatialGrid::Id>{1, 2, 3, 5}));
  EXPECT_EQ(g.size(), 6u);
}

TEST(SpatialGrid, StationsMoveBetweenCells) {
  SpatialGrid g(50);
  g.place(7, {10, 10, 0});
  g.place(8, {20, 10, 0});
  EXPECT_EQ(g.cells(), 1u);
  g.place(7, {500, 500, 0});  // far away now
  EXPECT_EQ(within(g, {0, 0, 0}, 50), (std::vector<SpatialGrid::Id>{8}));
  EXPECT_EQ(within(g, {510, 500, 0}, 50), (std::vector<SpatialGrid::Id>{7}));
  EXPECT_EQ(g.cells(), 2u);
  g.place(7, {501, 500, 0});  // within its cell
  g.place(8, {-1, -1, 0});    // across a cell border at the origin (floor, not truncation)
  EXPECT_EQ(within(g, {-30, -30, 0}, 50), (std::vector<SpatialGrid::Id>{8}));
  g.remove(8);
  g.remove(8);  // twice: nothing
  EXPECT_TRUE(within(g, {0, 0, 0}, 50).empty());
  EXPECT_EQ(g.size(), 1u);
  EXPECT_EQ(g.cells(), 1u);
}

TEST(SpatialGrid, AgreesWithAllPairsUnderRandomMoves) {
  // Against the plain definition, with stations that keep moving between cells and a radius
  // larger than a cell (more than one ring of cells).
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> coord(-400, 400);
  SpatialGrid g(60);
  std::vector<SpatialGrid::Position> where(200);
  for (int round = 0; round < 20; ++round) {
    for (std::uint32_t id = 0; id < where.size(); ++id) {
      if (round > 0 && id % 3 == 0)
        continue;  // some stay
      where[id] = {coord(rng), coord(rng), coord(rng) / 100};
      g.place(id, where[id]);
    }
    for (double r : {30.0, 60.0, 130.0}) {
      const SpatialGrid::Position p{coord(rng), coord(rng), 0};
      std::vector<SpatialGrid::Id> want;
      for (std::uint32_t id = 0; id < where.size(); ++id) {
        const double dx = where[id][0] - p[0], dy = where[id][1] - p[1], dz = where[id][2] - p[2];
        if (dx * dx + dy * dy + dz * dz <= r * r)
          want.push_back(id);
      }
      EXPECT_EQ(within(g, p, r), want) << "round " << round << " r " << r;
    }
  }
}

TEST(SpatialGrid, RefusesACellThatIsNotPositive) {
  EXPECT_THROW(SpatialGrid(0), std::invalid_argument);
  EXPECT_THROW(SpatialGrid(-5), std::invalid_argument);
}

TEST(PositionTableGrid, FollowsUpdatesAndCanBeStartedLate) {
  PositionTable t;
  std::vector<StationId> out;
  t.set(1, {{0, 0, 0}, 0});
  EXPECT_FALSE(t.stations_within({0, 0, 0}, 10, out));  // no index: cannot tell
  t.index_cells(100);                                   // built from what it holds
  ASSERT_TRUE(t.stations_within({0, 0, 0}, 10, out));
  EXPECT_EQ(out, std::vector<StationId>{1});
  wire::VehicleState s;
  s.station_id = 1;
  s.sim_time_ns = 5;
  s.position = {300, 0, 0};
  ASSERT_TRUE(t.update(s));
  out.clear();
  t.stations_within({0, 0, 0}, 100, out);
  EXPECT_TRUE(out.empty());
  s.sim_time_ns = 4;  // older: not taken, not moved either
  s.position = {0, 0, 0};
  EXPECT_FALSE(t.update(s));
  t.stations_within({0, 0, 0}, 100, out);
  EXPECT_TRUE(out.empty());
}

}  // namespace
}  // namespace tb::emu::radio
