#include <gtest/gtest.h>

#include "its-station/geonet/location_table.hpp"

namespace tb::its::geonet {
namespace {

using namespace std::chrono_literals;

GnAddress addr(std::uint8_t last) {
  return {false, StationType::kPassengerCar, {0x02, 0, 0, 0, 0, last}};
}

LongPositionVector pv(std::uint8_t last, Timestamp tst) {
  LongPositionVector p;
  p.address = addr(last);
  p.timestamp = tst;
  p.latitude = 481'500'000;
  return p;
}

TEST(LocationTable, EntriesExpireAfterTheirLifetimeSinceTheLastUpdate) {
  LocationTable table{20s};
  const clock::SteadyTime t0{};
  bool created = false;
  auto& e = table.find_or_create(addr(1), t0, created);
  EXPECT_TRUE(created);
  EXPECT_TRUE(table.update_position(e, pv(1, 1000), t0));
  EXPECT_NE(table.find(addr(1).mid_key(), t0 + 19s), nullptr);
  // A newer position at 10 s restarts the lifetime.
  EXPECT_TRUE(
      table.update_position(*table.find(addr(1).mid_key(), t0 + 10s), pv(1, 2000), t0 + 10s));
  EXPECT_NE(table.find(addr(1).mid_key(), t0 + 29s), nullptr);
  EXPECT_EQ(table.find(addr(1).mid_key(), t0 + 30s), nullptr);
  EXPECT_EQ(table.size(), 1u);
  EXPECT_EQ(table.purge(t0 + 30s), 1u);
  EXPECT_EQ(table.size(), 0u);
}

// Purge skips the walk until the earliest expiry, which refreshes only move later; an entry
// made after the table emptied is purged in its turn.
TEST(LocationTable, PurgeRemovesEachEntryOnceItsLifetimeEnds) {
  LocationTable table{20s};
  const clock::SteadyTime t0{};
  bool created = false;
  table.update_position(table.find_or_create(addr(1), t0, created), pv(1, 1000), t0);
  table.update_position(table.find_or_create(addr(2), t0 + 5s, created), pv(2, 1000), t0 + 5s);
  // 1 heard again at 10 s: it now outlives 2.
  table.refresh(*table.find(addr(1).mid_key(), t0 + 10s), t0 + 10s);
  EXPECT_EQ(table.purge(t0 + 20s), 0u);
  EXPECT_EQ(table.purge(t0 + 25s), 1u);
  EXPECT_EQ(table.find(addr(2).mid_key(), t0 + 25s), nullptr);
  EXPECT_NE(table.find(addr(1).mid_key(), t0 + 25s), nullptr);
  EXPECT_EQ(table.purge(t0 + 29s), 0u);
  EXPECT_EQ(table.purge(t0 + 30s), 1u);
  EXPECT_EQ(table.size(), 0u);
  table.find_or_create(addr(3), t0 + 40s, created);
  EXPECT_EQ(table.purge(t0 + 59s), 0u);
  EXPECT_EQ(table.size(), 1u);
  EXPECT_EQ(table.purge(t0 + 60s), 1u);
  EXPECT_EQ(table.size(), 0u);
}

TEST(LocationTable, AnExpiredEntryIsRecreatedEmpty) {
  LocationTable table{20s};
  bool created = false;
  auto& e = table.find_or_create(addr(1), {}, created);
  table.update_position(e, pv(1, 1000), {});
  e.is_neighbour = true;
  EXPECT_FALSE(LocationTable::is_duplicate_sequence_number(e, 7));
  auto& again = table.find_or_create(addr(1), clock::SteadyTime{} + 21s, created);
  EXPECT_TRUE(created);
  EXPECT_FALSE(again.is_neighbour);
  EXPECT_FALSE(again.has_position);
  EXPECT_FALSE(LocationTable::is_duplicate_sequence_number(again, 7));
}

// Two tables sharing a SenderIndex (station-host's stations) find their entries through it,
// each its own; a purged entry leaves its cell, and a wrong row is not trusted.
TEST(LocationTable, ASharedSenderIndexFindsEachTablesOwnEntry) {
  SenderIndex index;
  LocationTable a{20s};
  LocationTable b{20s};
  a.share_sender_index(index);
  b.share_sender_index(index);
  const clock::SteadyTime t0{};
  const auto row1 = index.row(addr(1).mid_key());
  const auto row2 = index.row(addr(2).mid_key());
  bool created = false;
  auto& a1 = a.find_or_create(addr(1), t0, created, row1);
  EXPECT_TRUE(created);
  auto& b1 = b.find_or_create(addr(1), t0, created, row1);
  EXPECT_TRUE(created);
  EXPECT_NE(&a1, &b1);
  EXPECT_TRUE(a.update_position(a1, pv(1, 1000), t0));
  EXPECT_EQ(&a.find_or_create(addr(1), t0 + 1s, created, row1), &a1);
  EXPECT_FALSE(created);
  EXPECT_EQ(&b.find_or_create(addr(1), t0 + 1s, created, row1), &b1);
  // Address 2 said to be from row 1: looked up by its key, 1's entry untouched.
  auto& a2 = a.find_or_create(addr(2), t0 + 1s, created, row1);
  EXPECT_TRUE(created);
  EXPECT_NE(&a2, &a1);
  EXPECT_EQ(a1.position.timestamp, Timestamp{1000});
  EXPECT_EQ(&a.find_or_create(addr(2), t0 + 2s, created, row2), &a2);
  EXPECT_EQ(a.size(), 2u);
  // Purged, then heard again through its row: a new entry, created empty.
  EXPECT_EQ(a.purge(t0 + 30s), 2u);
  auto& again = a.find_or_create(addr(1), t0 + 30s, created, row1);
  EXPECT_TRUE(created);
  EXPECT_FALSE(again.has_position);
  EXPECT_EQ(a.size(), 1u);
  EXPECT_EQ(a.find(addr(1).mid_key(), t0 + 30s), &again);
}

TEST(LocationTable, OnlyNewerPositionsReplaceTheHeldOne) {
  LocationTable table{20s};
  bool created = false;
  auto& e = table.find_or_create(addr(1), {}, created);
  EXPECT_TRUE(table.update_position(e, pv(1, 0xffff'ff00u), {}));
  EXPECT_FALSE(table.update_position(e, pv(1, 0xffff'ff00u), {}));  // equal
  EXPECT_FALSE(table.update_position(e, pv(1, 0xffff'fe00u), {}));  // older
  EXPECT_TRUE(table.update_position(e, pv(1, 0x10), {}));           // newer across the wrap
  EXPECT_EQ(e.position.timestamp, 0x10u);
}

TEST(LocationTable, DuplicateListRemembersTheLastEightSequenceNumbers) {
  LocationTable table{20s};
  bool created = false;
  auto& e = table.find_or_create(addr(1), {}, created);
  for (std::uint16_t sn = 100; sn < 108; ++sn)
    EXPECT_FALSE(LocationTable::is_duplicate_sequence_number(e, sn));
  for (std::uint16_t sn = 100; sn < 108; ++sn)
    EXPECT_TRUE(LocationTable::is_duplicate_sequence_number(e, sn));
  EXPECT_FALSE(LocationTable::is_duplicate_sequence_number(e, 108));  // evicts 100
  EXPECT_FALSE(LocationTable::is_duplicate_sequence_number(e, 100));
  EXPECT_TRUE(LocationTable::is_duplicate_sequence_number(e, 108));
}

TEST(LocationTable, NeighboursAreTheLiveEntriesMarkedSo) {
  LocationTable table{20s};
  bool created = false;
  table.find_or_create(addr(1), {}, created).is_neighbour = true;
  table.find_or_create(addr(2), {}, created);
  table.find_or_create(addr(3), clock::SteadyTime{} + 5s, created).is_neighbour = true;
  int n = 0;
  table.for_each_neighbour(clock::SteadyTime{} + 21s, [&](const LocationTableEntry& e) {
    ++n;
    EXPECT_EQ(e.address, addr(3));
  });
  EXPECT_EQ(n, 1);
}

}  // namespace
}  // namespace tb::its::geonet
