#pragma once
/// @file Local dynamic map (EN 302 895, in the small): what the station knows of its
/// neighbours (from CAMs), of active events (from DENMs) and of signalised intersections (from
/// MAPEM and SPATEM: intersection_store.hpp), with expiry, for applications.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <queue>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "common/clock/runtime.hpp"
#include "common/util/sender_index.hpp"
#include "its-station/facilities/intersection_store.hpp"
#include "its-station/messages/cam.hpp"
#include "its-station/messages/denm.hpp"

namespace tb::its::facilities {

/// One state of a neighbour, decoded from a CAM into SI units.
struct NeighbourSample {
  clock::SteadyTime received{};
  clock::WallTime received_wall{};
  std::uint16_t generation_delta_time = 0;
  clock::WallTime generation_time{};  ///< the fix time the CAM names, reconstructed from gdt
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  std::optional<double> heading_deg;
  std::optional<double> speed_mps;  ///< signed: negative when driving backward
};

class Ldm;

/// A neighbour's newest samples, newest first, in a ring allocated once: a CAM overwrites the
/// oldest sample in place (issue 33: std::deque allocated and freed a block every few CAMs, a
/// tenth of a pooled station's reception cost at 300 in range).
class SampleHistory {
 public:
  explicit SampleHistory(std::size_t capacity = 1) : capacity_(capacity == 0 ? 1 : capacity) {
    samples_.reserve(capacity_);
  }
  void push_front(const NeighbourSample& s) {
    if (samples_.size() < capacity_) {
      samples_.push_back(s);
      newest_ = samples_.size() - 1;
    } else {
      newest_ = (newest_ + 1) % capacity_;
      samples_[newest_] = s;
    }
  }
  std::size_t size() const { return samples_.size(); }
  bool empty() const { return samples_.empty(); }
  /// @p i = 0 is the newest.
  const NeighbourSample& operator[](std::size_t i) const {
    return samples_[(newest_ + samples_.size() - i) % samples_.size()];
  }
  const NeighbourSample& front() const { return samples_[newest_]; }

 private:
  std::size_t capacity_;
  std::size_t newest_ = 0;
  std::vector<NeighbourSample> samples_;
};

struct Neighbour {
  messages::StationID station_id = 0;
  messages::StationType station_type = 0;
  /// The newest CAM, as received and decoded: shared and immutable, so that a station keeps it
  /// without copying its 1.6 kB (issue 33: the copy was a third of a pooled station's reception
  /// cost). Set for every neighbour the LDM holds.
  std::shared_ptr<const messages::Cam> last_cam;
  SampleHistory history;  ///< newest first
  const NeighbourSample& latest() const { return history.front(); }
};

/// An event from a DENM, keyed by its action ID.
struct Event {
  messages::Denm denm;  ///< the newest version received
  clock::SteadyTime received{};
  /// TimestampIts after which the event is no longer valid (detection + validity duration).
  std::int64_t expires_its = 0;
  bool terminated = false;  ///< kept as a tombstone until expiry, so late repeats stay dropped
};

/// What the LDM did with a received DENM: the receiving ITS-S rules of EN 302 637-3 V1.3.1 as
/// the DEN conformance tests check them (TS 102 869-2 TP/DEN/MSRV), see Ldm::add_denm.
enum class DenmOutcome : std::uint8_t {
  kNew,                 ///< a new event (action ID not held, not a termination)
  kUpdate,              ///< a newer (referenceTime, detectionTime) of a known event
  kRepetition,          ///< the same referenceTime and detectionTime again: dropped
  kOutdated,            ///< older than the version held, or about a cancelled event: dropped
  kCancelled,           ///< isCancellation (the originator ended it): the event ends
  kNegated,             ///< isNegation (another station found it gone): the event ends
  kUnknownTermination,  ///< terminates nothing we hold: dropped
  kExpired,             ///< its validity had already ended: dropped
};
/// Whether @p o put the DENM's content into the LDM (the ones applications hear of).
inline bool accepted(DenmOutcome o) {
  return o == DenmOutcome::kNew || o == DenmOutcome::kUpdate || o == DenmOutcome::kCancelled ||
         o == DenmOutcome::kNegated;
}
std::string_view to_string(DenmOutcome o);

struct LdmConfig {
  /// A neighbour unheard for this long is forgotten (CAMs come at least every T_GenCamMax,
  /// 1 s; three lost in a row mean the station is out of range).
  clock::Duration neighbour_timeout = std::chrono::milliseconds{3000};
  std::size_t history_length = 10;
  /// Period of the expiry sweep.
  clock::Duration sweep_interval = std::chrono::milliseconds{200};
};

class Ldm {
 public:
  using NeighbourListener = std::function<void(const Neighbour&)>;
  using NeighbourGoneListener = std::function<void(messages::StationID)>;
  using EventListener = std::function<void(const Event&, DenmOutcome)>;

  Ldm(clock::Runtime& runtime, LdmConfig config = {});
  ~Ldm();
  Ldm(const Ldm&) = delete;
  Ldm& operator=(const Ldm&) = delete;

  /// A CAM from another station arrived (decoded); the neighbour keeps @p cam (not a copy).
  /// Ignores CAMs without a position.
  /// @p sender_row: the sender's row in the SenderIndex shared with share_sender_index(),
  /// which finds the neighbour without a hash lookup.
  void add_cam(std::shared_ptr<const messages::Cam> cam, clock::WallTime rx_wall,
               std::uint32_t sender_row = SenderIndex::kNoRow);
  /// Caches the neighbours in a column of @p index (keyed by StationID), shared by the LDMs of
  /// one thread that hear the same CAMs (common/util/sender_index.hpp). Before the first CAM.
  void share_sender_index(SenderIndex& index) { by_row_ = SenderColumn<Neighbour>(index); }
  /// A DENM arrived; applies the receiving rules and says what became of it:
  /// - validity over (detectionTime + validityDuration ≤ now): kExpired;
  /// - unknown action ID: kNew, or kUnknownTermination for a termination;
  /// - known action ID: versions are ordered by referenceTime, then detectionTime (a negation
  ///   keeps the event's referenceTime and brings a later detectionTime): an older one is
  ///   kOutdated, the same one kRepetition, a newer one an update or, with a termination,
  ///   kCancelled / kNegated;
  /// - after a cancellation nothing but newer repetitions of it is taken (the originator ended
  ///   the event and does not reuse its action ID); after a negation a newer DENM from the
  ///   originator brings the event back (it still sees it, and its referenceTime is newer than
  ///   the one the negation named).
  DenmOutcome add_denm(const messages::Denm& denm);

  /// Removes expired neighbours and events now (also done by the periodic sweep). Costs the
  /// neighbours it removes, not the ones it keeps.
  void expire();

  // Queries for applications.
  const std::map<messages::StationID, Neighbour>& neighbours() const { return neighbours_; }
  const Neighbour* neighbour(messages::StationID id) const;
  /// Active (not terminated, not expired) events.
  std::vector<const Event*> active_events() const;
  /// The active event of @p id, or null.
  const Event* event(const messages::ActionID& id) const;
  /// The newest version held of @p id, terminated events included (until their validity ends).
  const Event* any_event(const messages::ActionID& id) const;

  /// Signalised intersections (MAPEM/SPATEM), filled by the IntersectionReceiver; swept with
  /// the rest.
  IntersectionStore& intersections() { return intersections_; }
  const IntersectionStore& intersections() const { return intersections_; }

  void on_neighbour(NeighbourListener l) { neighbour_listeners_.push_back(std::move(l)); }
  void on_neighbour_gone(NeighbourGoneListener l) { gone_listeners_.push_back(std::move(l)); }
  void on_event(EventListener l) { event_listeners_.push_back(std::move(l)); }

 private:
  using ActionKey = std::pair<messages::StationID, messages::SequenceNumber>;
  void schedule_sweep();
  std::int64_t now_its() const;

  clock::Runtime& runtime_;
  LdmConfig config_;
  std::map<messages::StationID, Neighbour> neighbours_;
  /// neighbours_ by hash: a CAM finds its sender in one or two cache lines, not down a tree of
  /// hundreds of neighbours (issue 33: the tree walk was most of a pooled station's add_cam).
  std::unordered_map<messages::StationID, Neighbour*> by_id_;
  /// by_id_ without the lookup, for the hosts that share a SenderIndex.
  SenderColumn<Neighbour> by_row_;
  /// One expiry check per neighbour, soonest first: when it falls due the neighbour is forgotten
  /// if it has been unheard since, else checked again at its latest CAM + timeout. A CAM itself
  /// touches nothing here (issue 33: keeping a reception order moved a list node per CAM, and
  /// walking all neighbours at every sweep was a fifth of a pooled station's reception cost);
  /// each neighbour is looked at about once per timeout. A check names its neighbour directly:
  /// a neighbour has exactly one check waiting, and is only forgotten when that check is taken
  /// out, so the pointer (stable in neighbours_) is live whenever the check falls due.
  struct ExpiryCheck {
    clock::SteadyTime due;
    Neighbour* neighbour;
    bool operator>(const ExpiryCheck& o) const { return due > o.due; }
  };
  std::priority_queue<ExpiryCheck, std::vector<ExpiryCheck>, std::greater<>> expiry_checks_;
  std::map<ActionKey, Event> events_;
  IntersectionStore intersections_;
  std::vector<NeighbourListener> neighbour_listeners_;
  std::vector<NeighbourGoneListener> gone_listeners_;
  std::vector<EventListener> event_listeners_;
  clock::TimerId sweep_timer_ = 0;
};

}  // namespace tb::its::facilities
