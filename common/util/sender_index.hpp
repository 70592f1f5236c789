#pragma once
/// @file Per-sender rows of per-station pointers, for the stations of one thread that hear the
/// same frames one after the other (station-host's pooled stations, issue 33).
///
/// Each station keeps its entry for a sender (location table entry, LDM neighbour) in a hash
/// table of its own: at 300 stations in range a frame cost 300 lookups, each a miss on a bucket
/// array and a node of another sender, two fifths of the host's CPU. Here the sender is looked
/// up once per frame, by whoever parses the frame for all the stations; each station then finds
/// its entry in the sender's row at its own column. The rows are laid out station after station
/// in the order the host walks them, so a frame reads one contiguous row.
///
/// The index only caches pointers: each table still owns its entries, sets its cell when it
/// finds or makes an entry the slow way and clears it (forget) before the entry goes.

#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

namespace tb {

class SenderIndex {
 public:
  static constexpr std::uint32_t kNoRow = std::numeric_limits<std::uint32_t>::max();
  /// Senders beyond this many get no row (their frames take the tables' own lookup): a stream
  /// of made-up sender addresses cannot grow the index without bound.
  static constexpr std::size_t kDefaultMaxRows = 4096;

  explicit SenderIndex(std::size_t max_rows = kDefaultMaxRows) : max_rows_(max_rows) {}
  SenderIndex(const SenderIndex&) = delete;
  SenderIndex& operator=(const SenderIndex&) = delete;

  /// A column for one more station, its cells empty. Re-lays out the rows held (the host adds
  /// its stations before the first frame).
  std::uint32_t add_column();

  /// The row of @p key, made (its cells empty) on first sight; kNoRow when the index is full.
  std::uint32_t row(std::uint64_t key);
  /// The row of @p key if it has one, else kNoRow.
  std::uint32_t find_row(std::uint64_t key) const;

  /// The key @p row was made for.
  std::uint64_t key(std::uint32_t row) const { return keys_[row]; }

  void* get(std::uint32_t row, std::uint32_t column) const {
    return cells_[std::size_t{row} * columns_ + column];
  }
  void set(std::uint32_t row, std::uint32_t column, void* p) {
    cells_[std::size_t{row} * columns_ + column] = p;
  }

  std::size_t rows() const { return rows_.size(); }

 private:
  std::size_t max_rows_;
  std::uint32_t columns_ = 0;
  std::unordered_map<std::uint64_t, std::uint32_t> rows_;
  std::vector<std::uint64_t> keys_;  ///< by row
  std::vector<void*> cells_;         ///< row-major: rows_.size() × columns_
};

/// One station's column of a SenderIndex, typed: what a table holds. Empty (no index) by
/// default, and then every call finds nothing and changes nothing. A cell only ever holds the
/// entry of its row's key (set() checks), so a caller that names a wrong row gets an entry
/// whose key it can see is not its own, never a stale one.
template <typename T>
class SenderColumn {
 public:
  SenderColumn() = default;
  explicit SenderColumn(SenderIndex& index) : index_(&index), column_(index.add_column()) {}

  explicit operator bool() const { return index_ != nullptr; }

  /// The entry cached for @p row, or null (no index, no row, or none cached).
  T* get(std::uint32_t row) const {
    if (index_ == nullptr || row == SenderIndex::kNoRow)
      return nullptr;
    return static_cast<T*>(index_->get(row, column_));
  }
  /// Caches @p entry, the table's entry for @p key, in @p row if that is @p key's row.
  void set(std::uint32_t row, std::uint64_t key, T* entry) {
    if (index_ != nullptr && row != SenderIndex::kNoRow && index_->key(row) == key)
      index_->set(row, column_, entry);
  }
  /// Clears the cell of @p key: its entry is about to go.
  void forget(std::uint64_t key) {
    if (index_ == nullptr)
      return;
    if (const std::uint32_t row = index_->find_row(key); row != SenderIndex::kNoRow)
      index_->set(row, column_, nullptr);
  }

 private:
  SenderIndex* index_ = nullptr;
  std::uint32_t column_ = 0;
};

}  // namespace tb
