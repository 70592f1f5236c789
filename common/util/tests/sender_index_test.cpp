#include <gtest/gtest.h>

#include "common/util/sender_index.hpp"

namespace tb {
namespace {

TEST(SenderIndex, RowsAreMadeOnFirstSightAndKeptPerKey) {
  SenderIndex index;
  index.add_column();
  EXPECT_EQ(index.find_row(7), SenderIndex::kNoRow);
  const auto a = index.row(7);
  const auto b = index.row(9);
  EXPECT_NE(a, b);
  EXPECT_EQ(index.row(7), a);
  EXPECT_EQ(index.find_row(9), b);
  EXPECT_EQ(index.key(a), 7u);
  EXPECT_EQ(index.key(b), 9u);
  EXPECT_EQ(index.rows(), 2u);
}

TEST(SenderIndex, EachColumnHoldsItsOwnEntryForASender) {
  SenderIndex index;
  SenderColumn<int> first(index);
  SenderColumn<int> second(index);
  int x = 1, y = 2;
  const auto r = index.row(42);
  EXPECT_EQ(first.get(r), nullptr);
  first.set(r, 42, &x);
  second.set(r, 42, &y);
  EXPECT_EQ(first.get(r), &x);
  EXPECT_EQ(second.get(r), &y);
  first.forget(42);
  EXPECT_EQ(first.get(r), nullptr);
  EXPECT_EQ(second.get(r), &y);
}

TEST(SenderIndex, ACellOnlyTakesTheEntryOfItsRowsKey) {
  SenderIndex index;
  SenderColumn<int> column(index);
  int x = 1;
  const auto r = index.row(42);
  column.set(r, 43, &x);  // a caller naming the wrong row for key 43
  EXPECT_EQ(column.get(r), nullptr);
  column.set(SenderIndex::kNoRow, 42, &x);
  column.forget(1000);  // never seen: nothing to clear, no row made
  EXPECT_EQ(index.find_row(1000), SenderIndex::kNoRow);
}

TEST(SenderIndex, AColumnAddedLaterKeepsTheOthersCells) {
  SenderIndex index;
  SenderColumn<int> first(index);
  int x = 1, y = 2;
  const auto r1 = index.row(1);
  const auto r2 = index.row(2);
  first.set(r1, 1, &x);
  first.set(r2, 2, &y);
  SenderColumn<int> second(index);
  EXPECT_EQ(first.get(r1), &x);
  EXPECT_EQ(first.get(r2), &y);
  EXPECT_EQ(second.get(r1), nullptr);
  EXPECT_EQ(second.get(r2), nullptr);
}

TEST(SenderIndex, SendersBeyondTheLimitGetNoRow) {
  SenderIndex index(2);
  SenderColumn<int> column(index);
  EXPECT_NE(index.row(1), SenderIndex::kNoRow);
  EXPECT_NE(index.row(2), SenderIndex::kNoRow);
  EXPECT_EQ(index.row(3), SenderIndex::kNoRow);
  EXPECT_EQ(column.get(SenderIndex::kNoRow), nullptr);
  EXPECT_EQ(index.rows(), 2u);
}

TEST(SenderIndex, AnEmptyColumnFindsNothing) {
  SenderColumn<int> none;
  int x = 1;
  EXPECT_FALSE(none);
  none.set(0, 0, &x);
  EXPECT_EQ(none.get(0), nullptr);
  none.forget(0);
}

}  // namespace
}  // namespace tb
