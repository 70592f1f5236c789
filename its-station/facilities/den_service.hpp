#pragma once
/// @file Decentralized Environmental Notification basic service, EN 302 637-3 V1.3.1:
/// applications trigger, update and terminate events; the service builds, repeats and
/// GeoBroadcasts their DENMs, passes received DENMs through the LDM's receiving rules and keeps
/// other stations' events alive by forwarding them when their originator falls silent
/// (keep-alive forwarding, clause 8.2.2).

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <random>
#include <span>
#include <string_view>

#include "common/clock/runtime.hpp"
#include "common/util/expected.hpp"
#include "its-station/facilities/ldm.hpp"
#include "its-station/facilities/transport.hpp"
#include "its-station/messages/denm.hpp"

namespace tb::its::facilities {

/// Traffic class of DENMs that are not time-critical (see DenRequest::traffic_class).
inline constexpr std::uint8_t kDenmTrafficClassDefault = 1;
/// Traffic class of time-critical collision warnings (emergency electronic brake light, LCRW).
inline constexpr std::uint8_t kDenmTrafficClassTimeCritical = 0;

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
  std::optional<messages::AlacarteContainer> alacarte;
  /// GN traffic class of the DENMs (EN 302 636-4-1 clause 9.7.5). EN 302 637-3 fixes no
  /// value; the deployed profiles do, per use case: the C-ITS service profiles of the
  /// Commission's C-ITS delegated act (C(2019) 1789, Annex I, after the C2C-CC triggering
  /// conditions) send DENMs with traffic class 1 and the time-critical emergency electronic
  /// brake light with 0, as Artery's C2C-CC use cases do (EmergencyBrakeLight tc_id 0;
  /// TrafficJam, TractionLoss, Fog … tc_id 1). Applications with a time-critical warning
  /// (LCRW) ask for 0.
  std::uint8_t traffic_class = kDenmTrafficClassDefault;
};

/// What the network said about a received DENM (GN-DATA.indication): the GeoBroadcast
/// destination area and the traffic class it came with, which keep-alive forwarding reuses.
struct DenmReception {
  std::optional<GeoArea> destination_area;
  std::uint8_t traffic_class = kDenmTrafficClassDefault;
  /// The signer AT's DENM SSP of a DENM that came signed and verified, checked against its
  /// cause code (ssp_permissions.hpp); none for an unsecured DENM.
  std::optional<std::span<const std::uint8_t>> ssp;
};

/// The station's place relative to an area: keep-alive forwarding stops outside the relevance
/// area (clause 8.2.2). The station program answers from its GNSS position (GeoNetworking's
/// geometric function); without one the station counts as inside.
class AreaLocator {
 public:
  virtual ~AreaLocator() = default;
  virtual bool inside(const GeoArea& area) const = 0;
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
  /// Destination area of negations, and of forwarded DENMs that came without one, when the
  /// DENM names no relevanceDistance: a circle this wide around the event position.
  double negation_radius_m = 1000.0;
  /// Keep-alive forwarding (KAF, clause 8.2.2; optional in the standard, PICS_KAF): on, as the
  /// testbed's stations are meant to exercise the whole DEN service.
  bool keep_alive_forwarding = true;
  /// The random part of T_Forwarding, uniform in [0, kaf_jitter_max] (clause 8.2.1.4: 150 ms).
  clock::Duration kaf_jitter_max = std::chrono::milliseconds{150};
  /// Draws that random part; empty: a generator seeded with the station ID. Tests inject one.
  std::function<clock::Duration()> kaf_jitter;
};

class DenService {
 public:
  struct Counters {
    std::uint64_t sent = 0;
    std::uint64_t send_errors = 0;
    std::uint64_t received = 0;
    std::uint64_t decode_errors = 0;
    std::uint64_t dropped = 0;    ///< repetitions, outdated, expired, unknown terminations
    std::uint64_t own_heard = 0;  ///< our own events forwarded back to us by others
    std::uint64_t forwarded = 0;  ///< keep-alive forwardings sent
    /// Signed DENMs whose cause code their signer's SSP does not permit (ssp_permissions.hpp).
    std::uint64_t not_permitted = 0;
  };
  using SentListener = std::function<void(const messages::Denm&)>;

  /// @p locator may be null (the station counts as inside every relevance area).
  DenService(clock::Runtime& runtime, MessageSender& sender, Ldm& ldm, DenConfig config,
             const AreaLocator* locator = nullptr);
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

  /// A BTP-B packet for port 2002 arrived, with what GeoNetworking said about it.
  void receive(std::span<const std::uint8_t> payload, const DenmReception& reception = {});

  void on_sent(SentListener l) { sent_listeners_.push_back(std::move(l)); }
  const Counters& counters() const { return counters_; }
  /// Our own events still being repeated or valid.
  std::size_t originated() const { return own_.size(); }
  /// Other stations' events this station keeps alive (T_Forwarding running).
  std::size_t keeping_alive() const { return forwarding_.size(); }

 private:
  struct Own {
    messages::Denm denm;
    GeoArea area;
    std::uint8_t traffic_class = kDenmTrafficClassDefault;
    std::optional<clock::Duration> interval;
    clock::SteadyTime repeat_until{};
    clock::TimerId timer = 0;
    bool terminated = false;
    bool repeating = false;  ///< the pending timer is a repetition (else: the end of the entry)
  };
  /// Another station's event kept alive here: the version to forward, where, how.
  struct Forwarding {
    messages::Denm denm;
    GeoArea area;
    std::uint8_t traffic_class = kDenmTrafficClassDefault;
    clock::TimerId timer = 0;
  };
  using Key = std::pair<messages::StationID, messages::SequenceNumber>;

  Expected<messages::Denm, DenError> make(const messages::ActionID& id, const DenRequest& r,
                                          std::int64_t reference_its) const;
  /// Sends @p denm; @p forwarded marks a keep-alive forwarding (not one of our DENMs: no
  /// sent-listener call, its own trace record).
  bool transmit(const messages::Denm& denm, const GeoArea& area, std::uint8_t traffic_class,
                bool forwarded = false);
  void start_repetition(Own& own, const std::optional<clock::Duration>& interval,
                        clock::Duration duration);
  void repeat(Key key);
  /// Clause 8.2.2 on a DENM the LDM judged @p outcome: (re)starts, moves or ends the keeping
  /// alive of its event.
  void keep_alive(const messages::Denm& denm, DenmOutcome outcome, const DenmReception& rx);
  void start_forwarding_timer(Key key, Forwarding& f);
  void forward(Key key);
  GeoArea relevance_area(const messages::Denm& denm) const;

  clock::Runtime& runtime_;
  MessageSender& sender_;
  Ldm& ldm_;
  DenConfig config_;
  messages::SequenceNumber next_sequence_ = 0;
  std::map<Key, Own> own_;
  std::map<Key, Forwarding> forwarding_;
  const AreaLocator* locator_;
  std::mt19937 rng_;
  Counters counters_;
  std::vector<SentListener> sent_listeners_;
};

}  // namespace tb::its::facilities
