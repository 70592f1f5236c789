#include "its-station/geonet/location_table.hpp"

#include <algorithm>

namespace tb::its::geonet {

LocationTableEntry* LocationTable::find(std::uint64_t mid_key, clock::SteadyTime now) {
  auto it = entries_.find(mid_key);
  if (it == entries_.end() || it->second.expires <= now)
    return nullptr;
  return &it->second;
}

const LocationTableEntry* LocationTable::find(std::uint64_t mid_key, clock::SteadyTime now) const {
  auto it = entries_.find(mid_key);
  if (it == entries_.end() || it->second.expires <= now)
    return nullptr;
  return &it->second;
}

LocationTableEntry& LocationTable::find_or_create(const GnAddress& address, clock::SteadyTime now,
                                                  bool& created, std::uint32_t sender_row) {
  const std::uint64_t key = address.mid_key();
  LocationTableEntry* cached = by_row_.get(sender_row);
  bool inserted = false;
  // The row is the caller's word for the key; an entry under another key is not trusted.
  if (cached == nullptr || cached->address.mid_key() != key) {
    auto [it, added] = entries_.try_emplace(key);
    cached = &it->second;
    inserted = added;
    by_row_.set(sender_row, key, cached);
  }
  LocationTableEntry& e = *cached;
  created = inserted || e.expires <= now;
  if (created) {
    // An expired entry is as good as absent: its position and DPL are stale (clause 8.1.3).
    e = LocationTableEntry{};
    e.address = address;
    e.expires = now + lifetime_;
    earliest_expiry_ = std::min(earliest_expiry_, e.expires);
  }
  return e;
}

bool LocationTable::update_position(LocationTableEntry& entry, const LongPositionVector& pv,
                                    clock::SteadyTime now) {
  if (entry.has_position && !is_newer(pv.timestamp, entry.position.timestamp))
    return false;
  entry.position = pv;
  entry.has_position = true;
  entry.address = pv.address;
  entry.expires = now + lifetime_;
  return true;
}

bool LocationTable::is_duplicate_sequence_number(LocationTableEntry& entry, std::uint16_t sn) {
  const auto end = entry.dpl.begin() + entry.dpl_size;
  if (std::find(entry.dpl.begin(), end, sn) != end)
    return true;
  entry.dpl[entry.dpl_next] = sn;
  entry.dpl_next = static_cast<std::uint8_t>((entry.dpl_next + 1) % kDuplicatePacketListLength);
  if (entry.dpl_size < kDuplicatePacketListLength)
    ++entry.dpl_size;
  return false;
}

std::size_t LocationTable::purge(clock::SteadyTime now) {
  if (now < earliest_expiry_)
    return 0;
  clock::SteadyTime earliest = clock::SteadyTime::max();
  const auto removed = std::erase_if(entries_, [&](const auto& kv) {
    if (kv.second.expires <= now) {
      by_row_.forget(kv.first);
      return true;
    }
    earliest = std::min(earliest, kv.second.expires);
    return false;
  });
  earliest_expiry_ = earliest;
  return removed;
}

}  // namespace tb::its::geonet
