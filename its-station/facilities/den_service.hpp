#pragma once
/// @file Decentralized Environmental Notification basic service, EN 302 637-3 V1.3.1:
/// applications trigger, update and terminate events; the service builds, repeats and
/// GeoBroadcasts their DENMs, and passes received DENMs through the LDM's receiving rules.

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string_view>

#include "common/clock/runtime.hpp"
#include "common/util/expected.hpp"
#include "its-station/facilities/ldm.hpp"
#include "its-station/facilities/transport.hpp"
#include "its-station/messages/denm.hpp"

namespace tb::its::facilities {

/// What an application asks for (AppDENM_trigger / AppDENM_update parameters, clause 7.2).
struct DenRequest {
  messages::CauseCode event_type;
  messages::InformationQuality information_quality = 0;
  double event_latitude_deg = 0.0;
  double event_longitude_deg = 0.0;
  std::optional<double> event_altitude_m;
  std::optional<clock::WallTime> detection_time;  ///< default: now
  std::optional<messages::RelevanceDistance> relevance_distance;
  std::optional<messages::RelevanceTrafficDirection> relevance_traffic_direction;
  messages::ValidityDuration validity_s = messages::kDefaultValidity;
  /// T_Repetition; empty: the DENM is sent once.
  std::optional<clock::Duration> repetition_interval;
  /// T_RepetitionDuration; repetitions stop after it (and at the end of validity at the latest).
  clock::Duration repetition_duration{};
  GeoArea destination_area;  ///< where the DENM is GeoBroadcast (the relevance area)
  std::optional<messages::SituationContainer> situation_extra;  ///< linkedCause, eventHistory
  std::optional<messages::LocationContainer> location;
};

enum class DenError : std::uint8_t {
  kUnknownAction,  ///< no such event (own, or received and active)
  kAlreadyTerminated,
  kBadRequest,  ///< a parameter outside what the DENM can carry (named in the log)
  kSendFailed,  ///< encoding failed or the network did not take it (no position, link...)
};

/// itsGnMaxPacketLifetime (EN 302 636-4-1 Annex H): the GN lifetime of a DENM is capped at it.
inline constexpr std::uint32_t kMaxGnLifetimeMs = 600'000;
std::string_view to_string(DenError e);

struct DenConfig {
  messages::StationID station_id = 0;
  messages::StationType station_type = messages::station_type::kPassengerCar;
  /// Destination area for negations, whose request names no area: a circle this wide around
  /// the event position.
  double negation_radius_m = 1000.0;
};

class DenService {
 public:
  struct Counters {
    std::uint64_t sent = 0;
    std::uint64_t send_errors = 0;
    std::uint64_t received = 0;
    std::uint64_t decode_errors = 0;
    std::uint64_t dropped = 0;  ///< repetitions, outdated, expired, unknown terminations
    /// Signed DENMs whose cause code their signer's SSP does not permit (ssp_permissions.hpp).
    std::uint64_t not_permitted = 0;
  };
  using SentListener = std::function<void(const messages::Denm&)>;

  DenService(clock::Runtime& runtime, MessageSender& sender, Ldm& ldm, DenConfig config);
  ~DenService();
  DenService(const DenService&) = delete;
  DenService& operator=(const DenService&) = delete;

  /// A new event: a new action ID, sent now and repeated as requested.
  Expected<messages::ActionID, DenError> trigger(const DenRequest& request);
  /// New information about one of our events: same action ID, new referenceTime.
  Expected<messages::ActionID, DenError> update(const messages::ActionID& id,
                                                const DenRequest& request);
  /// Ends an event: our own with isCancellation, another station's (as held in the LDM) with
  /// isNegation (clause 8.1). The termination DENM is repeated like the event was.
  Expected<messages::ActionID, DenError> terminate(const messages::ActionID& id);

  /// A BTP-B packet for port 2002 arrived.
  /// @p ssp: the signer AT's DENM SSP of a DENM that came signed and verified, checked against
  /// its cause code; none for an unsecured DENM.
  void receive(std::span<const std::uint8_t> payload,
               std::optional<std::span<const std::uint8_t>> ssp = std::nullopt);

  void on_sent(SentListener l) { sent_listeners_.push_back(std::move(l)); }
  const Counters& counters() const { return counters_; }
  /// Our own events still being repeated or valid.
  std::size_t originated() const { return own_.size(); }

 private:
  struct Own {
    messages::Denm denm;
    GeoArea area;
    std::optional<clock::Duration> interval;
    clock::SteadyTime repeat_until{};
    clock::TimerId timer = 0;
    bool terminated = false;
    bool repeating = false;  ///< the pending timer is a repetition (else: the end of the entry)
  };
  using Key = std::pair<messages::StationID, messages::SequenceNumber>;

  Expected<messages::Denm, DenError> make(const messages::ActionID& id, const DenRequest& r,
                                          std::int64_t reference_its) const;
  bool transmit(const messages::Denm& denm, const GeoArea& area);
  void start_repetition(Own& own, const std::optional<clock::Duration>& interval,
                        clock::Duration duration);
  void repeat(Key key);

  clock::Runtime& runtime_;
  MessageSender& sender_;
  Ldm& ldm_;
  DenConfig config_;
  messages::SequenceNumber next_sequence_ = 0;
  std::map<Key, Own> own_;
  Counters counters_;
  std::vector<SentListener> sent_listeners_;
};

}  // namespace tb::its::facilities
