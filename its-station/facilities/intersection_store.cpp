#include "its-station/facilities/intersection_store.hpp"

namespace tb::its::facilities {

IntersectionStore::IntersectionStore(const clock::Clock& clock, IntersectionStoreConfig config)
    : clock_(clock), config_(config) {}

MapOutcome IntersectionStore::add_map(const messages::IntersectionGeometry& g) {
  expire();
  auto& e = entries_[g.id.id];
  e.id = g.id.id;
  e.map_received = clock_.steady_now();
  if (e.map && e.map->revision == g.revision)
    return MapOutcome::kRefreshed;
  // MsgCount wraps (0..127), so "newer" cannot be told from the number: another revision than
  // the one held is the RSU's current map (ISO TS 19091 msgIssueRevision / revision).
  const MapOutcome outcome = e.map ? MapOutcome::kNewRevision : MapOutcome::kNew;
  e.map = std::make_shared<const messages::IntersectionGeometry>(g);
  return outcome;
}

void IntersectionStore::add_spat(const messages::IntersectionState& s) {
  expire();
  auto& e = entries_[s.id.id];
  e.id = s.id.id;
  e.spat_received = clock_.steady_now();
  e.spat = std::make_shared<const messages::IntersectionState>(s);
}

void IntersectionStore::expire() {
  const auto now = clock_.steady_now();
  for (auto it = entries_.begin(); it != entries_.end();) {
    auto& e = it->second;
    if (e.map && now - e.map_received > config_.map_validity)
      e.map.reset();
    if (e.spat && now - e.spat_received > config_.spat_validity)
      e.spat.reset();
    it = (!e.map && !e.spat) ? entries_.erase(it) : std::next(it);
  }
}

const IntersectionEntry* IntersectionStore::find(messages::IntersectionID id) const {
  const auto it = entries_.find(id);
  return it == entries_.end() ? nullptr : &it->second;
}

std::size_t IntersectionStore::maps() const {
  std::size_t n = 0;
  for (const auto& [id, e] : entries_)
    n += e.map ? 1 : 0;
  return n;
}

}  // namespace tb::its::facilities
