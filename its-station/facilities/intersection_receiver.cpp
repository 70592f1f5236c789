#include "its-station/facilities/intersection_receiver.hpp"

#include <spdlog/spdlog.h>

namespace tb::its::facilities {

IntersectionReceiver::IntersectionReceiver(IntersectionStore& store) : store_(store) {}

IntersectionReceiver::~IntersectionReceiver() = default;

void IntersectionReceiver::receive_mapem(std::span<const std::uint8_t> bytes) {
  if (!mapem_)
    mapem_ = std::make_unique<messages::Mapem>();
  const auto r = messages::decode(bytes, *mapem_);
  if (!r) {
    ++counters_.mapem_decode_errors;
    if (!mapem_error_said_) {
      mapem_error_said_ = true;
      spdlog::warn("MAPEM of {} bytes dropped: {} (further ones only counted)", bytes.size(),
                   asn1::to_string(r.error()));
    }
    return;
  }
  ++counters_.mapem_received;
  if (!mapem_->map.intersections || mapem_->map.intersections->empty()) {
    ++counters_.mapem_without_intersections;
    return;
  }
  for (const messages::IntersectionGeometry& g : *mapem_->map.intersections) {
    const MapOutcome o = store_.add_map(g);
    if (const IntersectionEntry* e = store_.find(g.id.id))
      for (const auto& l : map_listeners_)
        l(*e, o);
  }
}

void IntersectionReceiver::receive_spatem(std::span<const std::uint8_t> bytes) {
  if (!spatem_)
    spatem_ = std::make_unique<messages::Spatem>();
  const auto r = messages::decode(bytes, *spatem_);
  if (!r) {
    ++counters_.spatem_decode_errors;
    if (!spatem_error_said_) {
      spatem_error_said_ = true;
      spdlog::warn("SPATEM of {} bytes dropped: {} (further ones only counted)", bytes.size(),
                   asn1::to_string(r.error()));
    }
    return;
  }
  ++counters_.spatem_received;
  for (const messages::IntersectionState& s : spatem_->spat.intersections) {
    store_.add_spat(s);
    if (const IntersectionEntry* e = store_.find(s.id.id))
      for (const auto& l : spat_listeners_)
        l(*e);
  }
}

}  // namespace tb::its::facilities
