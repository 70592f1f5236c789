#include "common/util/sender_index.hpp"

namespace tb {

std::uint32_t SenderIndex::add_column() {
  const std::uint32_t old_columns = columns_;
  ++columns_;
  if (!rows_.empty()) {
    std::vector<void*> relaid(rows_.size() * columns_, nullptr);
    for (std::size_t r = 0; r < rows_.size(); ++r)
      for (std::uint32_t c = 0; c < old_columns; ++c)
        relaid[r * columns_ + c] = cells_[r * old_columns + c];
    cells_ = std::move(relaid);
  }
  return old_columns;
}

std::uint32_t SenderIndex::row(std::uint64_t key) {
  if (const auto it = rows_.find(key); it != rows_.end())
    return it->second;
  if (rows_.size() >= max_rows_)
    return kNoRow;
  const auto r = static_cast<std::uint32_t>(rows_.size());
  rows_.emplace(key, r);
  keys_.push_back(key);
  cells_.resize(cells_.size() + columns_, nullptr);
  return r;
}

std::uint32_t SenderIndex::find_row(std::uint64_t key) const {
  const auto it = rows_.find(key);
  return it == rows_.end() ? kNoRow : it->second;
}

}  // namespace tb
