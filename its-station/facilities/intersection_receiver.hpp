#pragma once
/// @file The receiving side of TS 103 301's RLT service (MAPEM, BTP-B port 2003) and TLM
/// service (SPATEM, BTP-B port 2004): decodes each message into the LDM's IntersectionStore and
/// tells listeners; counts what it could not decode.

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "its-station/facilities/intersection_store.hpp"
#include "its-station/facilities/transport.hpp"
#include "its-station/messages/mapem.hpp"
#include "its-station/messages/spatem.hpp"

namespace tb::its::facilities {

struct IntersectionRxCounters {
  std::uint64_t mapem_received = 0;  ///< decoded
  std::uint64_t spatem_received = 0;
  std::uint64_t mapem_decode_errors = 0;
  std::uint64_t spatem_decode_errors = 0;
  std::uint64_t mapem_without_intersections = 0;  ///< MapData with no IntersectionGeometry
};

class IntersectionReceiver {
 public:
  using MapListener = std::function<void(const IntersectionEntry&, MapOutcome)>;
  using SpatListener = std::function<void(const IntersectionEntry&)>;

  explicit IntersectionReceiver(IntersectionStore& store);
  ~IntersectionReceiver();

  /// A MAPEM's payload (BTP-B 2003): each IntersectionGeometry into the store. Never reads
  /// outside @p bytes; a message that does not decode is counted, its first error logged.
  void receive_mapem(std::span<const std::uint8_t> bytes);
  /// A SPATEM's payload (BTP-B 2004): each IntersectionState into the store.
  void receive_spatem(std::span<const std::uint8_t> bytes);

  /// After each intersection a MAPEM brought (new, another revision or refreshed).
  void on_map(MapListener l) { map_listeners_.push_back(std::move(l)); }
  /// After each intersection state a SPATEM brought.
  void on_spat(SpatListener l) { spat_listeners_.push_back(std::move(l)); }

  const IntersectionRxCounters& counters() const { return counters_; }

 private:
  IntersectionStore& store_;
  // Decoded into, reused: a Mapem is 1.8 MB and a Spatem 0.5 MB (messages/README.md), made at
  // the first reception so that a station that never hears one pays nothing.
  std::unique_ptr<messages::Mapem> mapem_;
  std::unique_ptr<messages::Spatem> spatem_;
  IntersectionRxCounters counters_;
  bool mapem_error_said_ = false;
  bool spatem_error_said_ = false;
  std::vector<MapListener> map_listeners_;
  std::vector<SpatListener> spat_listeners_;
};

}  // namespace tb::its::facilities
