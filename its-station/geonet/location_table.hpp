#pragma once
/// @file The location table (EN 302 636-4-1 V1.4.1 clause 8.1) with duplicate packet detection
/// (Annex A).

#include <array>
#include <cstdint>
#include <unordered_map>

#include "common/clock/clock.hpp"
#include "common/util/sender_index.hpp"
#include "its-station/geonet/packet.hpp"

namespace tb::its::geonet {

/// itsGnDPLLength (Annex H): sequence numbers remembered per source.
inline constexpr std::size_t kDuplicatePacketListLength = 8;

struct LocationTableEntry {
  GnAddress address;
  link::MacAddress link_address{};  ///< who sent us the last frame from this source directly
  LongPositionVector position;
  bool has_position = false;
  bool is_neighbour = false;
  clock::SteadyTime expires{};

  // Duplicate packet list (Annex A.2): a ring of the last sequence numbers seen.
  std::array<std::uint16_t, kDuplicatePacketListLength> dpl{};
  std::uint8_t dpl_size = 0;
  std::uint8_t dpl_next = 0;
};

class LocationTable {
 public:
  /// @p lifetime is itsGnLifetimeLocTE (20 s by default); an entry lives that long after its
  /// last position update.
  explicit LocationTable(clock::Duration lifetime) : lifetime_(lifetime) {}

  /// The live entry for @p mid_key (GnAddress::mid_key()), or nullptr if absent or expired.
  LocationTableEntry* find(std::uint64_t mid_key, clock::SteadyTime now);
  const LocationTableEntry* find(std::uint64_t mid_key, clock::SteadyTime now) const;

  /// The entry of @p address, created (not a neighbour, empty DPL) if absent or expired.
  /// Sets @p created when a new entry was made. @p sender_row: the address's row in the
  /// shared SenderIndex (share_sender_index), which finds the entry without a hash lookup.
  LocationTableEntry& find_or_create(const GnAddress& address, clock::SteadyTime now, bool& created,
                                     std::uint32_t sender_row = SenderIndex::kNoRow);

  /// Caches this table's entries in a column of @p index, shared by the tables of one thread
  /// that hear the same frames (sender_index.hpp). Before the first entry is made.
  void share_sender_index(SenderIndex& index) { by_row_ = SenderColumn<LocationTableEntry>(index); }

  /// Clause C.2: takes @p pv into the entry if it is newer than the one held, and restarts the
  /// entry's lifetime. Returns false (and changes nothing) for an older or equal timestamp.
  bool update_position(LocationTableEntry& entry, const LongPositionVector& pv,
                       clock::SteadyTime now);

  /// Restarts the entry's lifetime without touching its position: its source was heard again.
  void refresh(LocationTableEntry& entry, clock::SteadyTime now) const {
    entry.expires = now + lifetime_;
  }

  /// Annex A.2: true if @p sn is in the entry's duplicate packet list; otherwise records it.
  static bool is_duplicate_sequence_number(LocationTableEntry& entry, std::uint16_t sn);

  /// Removes expired entries; returns how many. Walks the table only once its earliest expiry
  /// has come (issue 33: a pooled station walked its hundreds of entries every second).
  std::size_t purge(clock::SteadyTime now);
  /// Entries held, live or not yet purged.
  std::size_t size() const { return entries_.size(); }
  clock::Duration lifetime() const { return lifetime_; }

  template <typename F>
  void for_each_neighbour(clock::SteadyTime now, F&& f) const {
    for (const auto& [key, e] : entries_) {
      if (e.is_neighbour && e.expires > now)
        f(e);
    }
  }

 private:
  clock::Duration lifetime_;
  /// Node-based: the entries stay where they are, so by_row_ may point at them.
  std::unordered_map<std::uint64_t, LocationTableEntry> entries_;
  SenderColumn<LocationTableEntry> by_row_;
  /// No entry expires before this. Every expiry is set to the then steady now + lifetime_, so
  /// none moves earlier: the earliest one a purge left stays a bound, lowered by new entries.
  clock::SteadyTime earliest_expiry_ = clock::SteadyTime::max();
};

}  // namespace tb::its::geonet
