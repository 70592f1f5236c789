#pragma once
/// @file The LDM's part about signalised intersections (issue 34): the latest MapData
/// IntersectionGeometry (MAPEM) and the latest SPAT IntersectionState (SPATEM) of each
/// intersection heard, with their validity.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>

#include "common/clock/clock.hpp"
#include "its-station/messages/dsrc.hpp"

namespace tb::its::facilities {

struct IntersectionStoreConfig {
  /// A MapData not heard again for this long is dropped. RSUs send MAPEM about once a second
  /// (C-Roads), so 30 s is many lost in a row: the vehicle has left the RSU's range.
  clock::Duration map_validity = std::chrono::seconds{30};
  /// A SPAT older than this is dropped: SPATEM comes at up to 10 Hz and on every change, and a
  /// light's state a few seconds old is wrong more often than right.
  clock::Duration spat_validity = std::chrono::seconds{2};
};

/// What the store did with a MapData intersection.
enum class MapOutcome : std::uint8_t {
  kNew,          ///< an intersection not held
  kNewRevision,  ///< another revision (MsgCount) than the one held: replaces it
  kRefreshed,    ///< the revision held: only its validity is extended
};

/// One intersection as last heard. Shared and immutable: the frames are large (dsrc.hpp bounds),
/// so listeners and applications keep a pointer instead of a copy.
struct IntersectionEntry {
  messages::IntersectionID id = 0;
  std::shared_ptr<const messages::IntersectionGeometry> map;  ///< null: no MAPEM held
  clock::SteadyTime map_received{};
  std::shared_ptr<const messages::IntersectionState> spat;  ///< null: no SPATEM held
  clock::SteadyTime spat_received{};
};

/// Keyed by IntersectionReferenceID.id: the region (RoadRegulatorID) is not part of the key, as a
/// testbed has one road operator (the contract's intersection id is the junction id).
/// Expiry runs on the steady clock (validity is a duration since reception), on expire() and
/// on every add.
class IntersectionStore {
 public:
  explicit IntersectionStore(const clock::Clock& clock, IntersectionStoreConfig config = {});

  /// A MAPEM's intersection: copied in only when new or of another revision.
  MapOutcome add_map(const messages::IntersectionGeometry& g);
  /// A SPATEM's intersection state: the latest one replaces what was held.
  void add_spat(const messages::IntersectionState& s);
  /// Drops what is past its validity; an intersection with neither part left goes.
  void expire();

  const IntersectionEntry* find(messages::IntersectionID id) const;
  const std::map<messages::IntersectionID, IntersectionEntry>& entries() const { return entries_; }
  /// Intersections with a MapData held.
  std::size_t maps() const;

 private:
  const clock::Clock& clock_;
  IntersectionStoreConfig config_;
  std::map<messages::IntersectionID, IntersectionEntry> entries_;
};

}  // namespace tb::its::facilities
