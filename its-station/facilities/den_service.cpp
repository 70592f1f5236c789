#include "its-station/facilities/den_service.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include <spdlog/spdlog.h>

#include "common/trace/tracer.hpp"
#include "its-station/facilities/cdd_convert.hpp"
#include "its-station/facilities/its_time.hpp"
#include "its-station/facilities/ssp_permissions.hpp"

namespace tb::its::facilities {

std::string_view to_string(DenError e) {
  switch (e) {
    case DenError::kUnknownAction:
      return "unknown action ID";
    case DenError::kAlreadyTerminated:
      return "event already terminated";
    case DenError::kBadRequest:
      return "bad request";
    case DenError::kSendFailed:
      return "DENM not sent (encoding or the network refused it; see the log)";
  }
  return "?";
}

namespace {

// The GN packet lifetime follows the validity (no forwarding after it ends) but is capped at
// itsGnMaxPacketLifetime, 600 s (EN 302 636-4-1 Annex H), which the router enforces: a DENM valid
// for longer is still sent, repetitions carry it on.
std::uint32_t gn_lifetime_ms(messages::ValidityDuration validity_s) {
  return std::min<std::uint32_t>(validity_s * 1000u, kMaxGnLifetimeMs);
}

}  // namespace

DenService::DenService(clock::Runtime& runtime, MessageSender& sender, Ldm& ldm, DenConfig config,
                       const AreaLocator* locator)
    : runtime_(runtime),
      sender_(sender),
      ldm_(ldm),
      config_(std::move(config)),
      locator_(locator),
      rng_(config_.station_id) {}

DenService::~DenService() {
  for (auto& [_, own] : own_)
    runtime_.cancel(own.timer);
  for (auto& [_, f] : forwarding_)
    runtime_.cancel(f.timer);
}

Expected<messages::Denm, DenError> DenService::make(const messages::ActionID& id,
                                                    const DenRequest& r,
                                                    std::int64_t reference_its) const {
  if (r.validity_s > 86400 || !std::isfinite(r.event_latitude_deg) ||
      !std::isfinite(r.event_longitude_deg) || std::abs(r.event_latitude_deg) > 90.0 ||
      std::abs(r.event_longitude_deg) > 180.0) {
    spdlog::warn("DEN service: request rejected: validity {} s, event at {}, {}", r.validity_s,
                 r.event_latitude_deg, r.event_longitude_deg);
    return Unexpected{DenError::kBadRequest};
  }
  if (r.repetition_interval && (*r.repetition_interval < std::chrono::milliseconds{1} ||
                                *r.repetition_interval > std::chrono::milliseconds{10000})) {
    spdlog::warn("DEN service: request rejected: repetition interval outside 1..10000 ms");
    return Unexpected{DenError::kBadRequest};
  }
  messages::Denm d;
  d.header.stationID = config_.station_id;
  auto& mc = d.denm.management;
  mc.actionID = id;
  const auto detection = timestamp_its(r.detection_time.value_or(runtime_.wall_now()));
  mc.detectionTime = static_cast<messages::TimestampIts>(std::max<std::int64_t>(0, detection));
  mc.referenceTime = static_cast<messages::TimestampIts>(std::max<std::int64_t>(0, reference_its));
  mc.eventPosition.latitude = cdd::latitude(r.event_latitude_deg);
  mc.eventPosition.longitude = cdd::longitude(r.event_longitude_deg);
  mc.eventPosition.altitude = cdd::altitude(r.event_altitude_m, std::nullopt);
  mc.relevanceDistance = r.relevance_distance;
  mc.relevanceTrafficDirection = r.relevance_traffic_direction;
  mc.validityDuration = r.validity_s;
  if (r.repetition_interval)
    mc.transmissionInterval = static_cast<messages::TransmissionInterval>(
        std::chrono::duration_cast<std::chrono::milliseconds>(*r.repetition_interval).count());
  mc.stationType = config_.station_type;
  messages::SituationContainer sc = r.situation_extra.value_or(messages::SituationContainer{});
  sc.informationQuality = r.information_quality;
  sc.eventType = r.event_type;
  d.denm.situation = sc;
  if (r.location)
    d.denm.location = r.location;
  if (r.alacarte)
    d.denm.alacarte = r.alacarte;
  return d;
}

bool DenService::transmit(const messages::Denm& denm, const GeoArea& area,
                          std::uint8_t traffic_class, bool forwarded) {
  std::array<std::uint8_t, messages::kDenmMaxEncodedSize> buf;
  auto n = messages::encode(denm, buf);
  if (!n) {
    spdlog::error("DEN service: cannot encode DENM: {}", asn1::to_string(n.error()));
    ++counters_.send_errors;
    return false;
  }
  // Stamped before the send, as its.cam_tx: on a veth or hwsim radio the send already carries
  // the frame to the medium, and a neighbour may take it in before the send returns.
  const std::int64_t handed_ns = trace::Tracer::now_ns();
  const auto r = sender_.send_geobroadcast(kBtpPortDenm, area, std::span(buf.data(), *n),
                                           gn_lifetime_ms(denm.denm.management.validityDuration),
                                           traffic_class);
  if (r != SendResult::kSent) {
    ++counters_.send_errors;
    spdlog::warn("DEN service: DENM not sent: {}", to_string(r));
    return false;
  }
  const auto& mc = denm.denm.management;
  if (forwarded) {
    ++counters_.forwarded;
    trace::global().record_at(handed_ns, "its.denm_fwd",
                              {{"station", config_.station_id},
                               {"origin", mc.actionID.originatingStationID},
                               {"seq", unsigned{mc.actionID.sequenceNumber}},
                               {"ref", static_cast<std::uint64_t>(mc.referenceTime)}});
    return true;
  }
  ++counters_.sent;
  trace::global().record_at(handed_ns, "its.denm_tx",
                            {{"station", config_.station_id},
                             {"origin", mc.actionID.originatingStationID},
                             {"seq", unsigned{mc.actionID.sequenceNumber}},
                             {"ref", static_cast<std::uint64_t>(mc.referenceTime)},
                             {"term", mc.termination.has_value()}});
  for (auto& l : sent_listeners_)
    l(denm);
  return true;
}

void DenService::start_repetition(Own& own, const std::optional<clock::Duration>& interval,
                                  clock::Duration duration) {
  runtime_.cancel(own.timer);
  const auto now = runtime_.steady_now();
  own.interval = interval;
  own.repeat_until = now + duration;
  const auto& mc = own.denm.denm.management;
  const Key key{mc.actionID.originatingStationID, mc.actionID.sequenceNumber};
  // Clause 8.1.2: repetition at T_Repetition while T_RepetitionDuration lasts. Afterwards an
  // event stays until its validity ends, so that it can still be updated or cancelled; a
  // terminated one is forgotten at once.
  own.repeating = interval && now + *interval <= own.repeat_until;
  clock::SteadyTime next;
  if (own.repeating) {
    next = now + *interval;
  } else if (own.terminated) {
    next = now;
  } else {
    const std::int64_t end_its =
        static_cast<std::int64_t>(mc.detectionTime) + std::int64_t{mc.validityDuration} * 1000;
    next = now + std::chrono::milliseconds{
                     std::max<std::int64_t>(0, end_its - timestamp_its(runtime_.wall_now()))};
  }
  own.timer = runtime_.schedule_at(next, [this, key] { repeat(key); });
}

void DenService::repeat(Key key) {
  auto it = own_.find(key);
  if (it == own_.end())
    return;
  Own& own = it->second;
  if (!own.repeating) {
    own_.erase(it);  // validity over, or termination repeated: the event is forgotten
    return;
  }
  const auto& mc = own.denm.denm.management;
  const std::int64_t end_its =
      static_cast<std::int64_t>(mc.detectionTime) + std::int64_t{mc.validityDuration} * 1000;
  if (timestamp_its(runtime_.wall_now()) >= end_its) {
    own_.erase(it);  // no repetition beyond the validity (clause 8.1.2)
    return;
  }
  transmit(own.denm, own.area, own.traffic_class);
  start_repetition(own, own.interval, own.repeat_until - runtime_.steady_now());
}

Expected<messages::ActionID, DenError> DenService::trigger(const DenRequest& request) {
  const messages::ActionID id{config_.station_id, next_sequence_};
  auto denm = make(id, request, timestamp_its(runtime_.wall_now()));
  if (!denm)
    return Unexpected{denm.error()};
  // Sequence numbers wrap (clause 8.1.1 uses them modulo 2^16).
  ++next_sequence_;
  auto [it, _] = own_.insert_or_assign(
      Key{id.originatingStationID, id.sequenceNumber},
      Own{*denm, request.destination_area, request.traffic_class, {}, {}, 0, false, false});
  if (!transmit(it->second.denm, it->second.area, it->second.traffic_class)) {
    own_.erase(it);
    return Unexpected{DenError::kSendFailed};
  }
  start_repetition(it->second, request.repetition_interval, request.repetition_duration);
  return id;
}

Expected<messages::ActionID, DenError> DenService::update(const messages::ActionID& id,
                                                          const DenRequest& request) {
  auto it = own_.find({id.originatingStationID, id.sequenceNumber});
  if (it == own_.end())
    return Unexpected{DenError::kUnknownAction};
  if (it->second.terminated)
    return Unexpected{DenError::kAlreadyTerminated};
  auto denm = make(id, request, timestamp_its(runtime_.wall_now()));
  if (!denm)
    return Unexpected{denm.error()};
  // The detection time of the event stays unless the application saw it anew.
  if (!request.detection_time)
    denm->denm.management.detectionTime = it->second.denm.denm.management.detectionTime;
  it->second.denm = *denm;
  it->second.area = request.destination_area;
  it->second.traffic_class = request.traffic_class;
  if (!transmit(it->second.denm, it->second.area, it->second.traffic_class))
    return Unexpected{DenError::kSendFailed};
  start_repetition(it->second, request.repetition_interval, request.repetition_duration);
  return id;
}

Expected<messages::ActionID, DenError> DenService::terminate(const messages::ActionID& id) {
  const auto now_its = timestamp_its(runtime_.wall_now());
  auto it = own_.find({id.originatingStationID, id.sequenceNumber});
  if (it != own_.end()) {
    Own& own = it->second;
    if (own.terminated)
      return Unexpected{DenError::kAlreadyTerminated};
    own.terminated = true;
    own.denm.denm.management.termination = messages::Termination::isCancellation;
    own.denm.denm.management.referenceTime = static_cast<messages::TimestampIts>(now_its);
    if (!transmit(own.denm, own.area, own.traffic_class))
      return Unexpected{DenError::kSendFailed};
    // Repeat the cancellation as the event was repeated, over the remaining duration.
    const auto remaining =
        std::max<clock::Duration>(own.repeat_until - runtime_.steady_now(), clock::Duration{});
    start_repetition(own, own.interval, remaining);
    return id;
  }
  // Another station's event, as we hold it: negation (clause 8.1, isNegation).
  const Event* e = ldm_.event(id);
  if (!e)
    return Unexpected{DenError::kUnknownAction};
  messages::Denm neg = e->denm;
  neg.header.stationID = config_.station_id;
  auto& mc = neg.denm.management;
  // EN 302 637-3 clause 8.1: a negation keeps the event's referenceTime (receivers match it
  // to the event they hold) and carries the time the event was found gone as detectionTime.
  mc.termination = messages::Termination::isNegation;
  mc.detectionTime = static_cast<messages::TimestampIts>(std::max<std::int64_t>(0, now_its));
  mc.stationType = config_.station_type;
  if (!transmit(neg, relevance_area(neg), kDenmTrafficClassDefault))
    return Unexpected{DenError::kSendFailed};
  // Our own LDM applies the negation too, so the event stops being active here at once.
  ldm_.add_denm(neg);
  return id;
}

void DenService::receive(std::span<const std::uint8_t> payload, const DenmReception& rx) {
  auto denm = messages::decode_denm(payload);
  if (!denm) {
    ++counters_.decode_errors;
    spdlog::debug("DEN service: dropped undecodable DENM: {}", asn1::to_string(denm.error()));
    return;
  }
  const auto& mc = denm->denm.management;
  if (denm->header.stationID == config_.station_id)
    return;  // our own, heard back
  if (rx.ssp) {
    if (const auto missing = denm_not_permitted(*denm, *rx.ssp)) {
      ++counters_.not_permitted;
      spdlog::debug("DEN service: dropped DENM of {}: its AT does not permit {}",
                    denm->header.stationID, missing->name);
      return;
    }
  }
  ++counters_.received;
  if (mc.actionID.originatingStationID == config_.station_id) {
    // Another station negated one of our events: stop repeating it.
    if (mc.termination == messages::Termination::isNegation) {
      auto it = own_.find({mc.actionID.originatingStationID, mc.actionID.sequenceNumber});
      if (it != own_.end()) {
        runtime_.cancel(it->second.timer);
        own_.erase(it);
        spdlog::info("DEN service: station {} negated our event {}", denm->header.stationID,
                     mc.actionID.sequenceNumber);
      }
      return;
    }
    // One of our own events (or its cancellation), kept alive by another station: we know it
    // better.
    ++counters_.own_heard;
    return;
  }
  // Stamped when the LDM takes the DENM, before its listeners publish it to MQTT (which can
  // take longer than the decision itself).
  const std::int64_t taken_ns = trace::Tracer::now_ns();
  const auto outcome = ldm_.add_denm(*denm);
  if (!accepted(outcome))
    ++counters_.dropped;
  trace::global().record_at(taken_ns, "its.denm_rx",
                            {{"station", config_.station_id},
                             {"origin", mc.actionID.originatingStationID},
                             {"seq", unsigned{mc.actionID.sequenceNumber}},
                             {"outcome", to_string(outcome)}});
  if (config_.keep_alive_forwarding)
    keep_alive(*denm, outcome, rx);
}

GeoArea DenService::relevance_area(const messages::Denm& denm) const {
  const auto& mc = denm.denm.management;
  const double radius = mc.relevanceDistance ? cdd::relevance_radius_m(*mc.relevanceDistance)
                                             : config_.negation_radius_m;
  return GeoArea{GeoArea::Shape::kCircle,
                 cdd::latitude_deg(mc.eventPosition.latitude).value_or(0.0),
                 cdd::longitude_deg(mc.eventPosition.longitude).value_or(0.0),
                 radius,
                 radius,
                 0.0};
}

// Keep-alive forwarding, EN 302 637-3 V1.3.1 clause 8.2.2, as the DEN conformance tests check
// it (TS 102 869-2 TP/DEN/KAFW/BV-01…11, TI-03):
// - only DENMs with a transmissionInterval are kept alive (BV-11);
// - every DENM of the event that is not older than the version held restarts T_Forwarding
//   (BV-01, BV-02): someone else is keeping it alive;
// - T_Forwarding = min(2 × transmissionInterval + rnd(0, 150 ms), remaining validity) (TI-03);
// - when it expires, the station re-sends the DENM held, its own station ID in the header and
//   every container unchanged: action ID, referenceTime, termination (BV-04…BV-08), into the
//   area it came for, and starts T_Forwarding again;
// - it stops when the validity ends (BV-09) or the station is outside the relevance area
//   (BV-10).
void DenService::keep_alive(const messages::Denm& denm, DenmOutcome outcome,
                            const DenmReception& rx) {
  const auto& mc = denm.denm.management;
  const Key key{mc.actionID.originatingStationID, mc.actionID.sequenceNumber};
  auto it = forwarding_.find(key);
  switch (outcome) {
    case DenmOutcome::kOutdated:
    case DenmOutcome::kExpired:
    case DenmOutcome::kUnknownTermination:
      return;  // says nothing newer about an event we keep alive
    case DenmOutcome::kRepetition:
      if (it != forwarding_.end()) {
        // It is alive without us, for now. (A newer repetition of a termination, which the
        // LDM files as a repetition, becomes the version we would forward.)
        const auto& held = it->second.denm.denm.management;
        if (std::make_pair(mc.referenceTime, mc.detectionTime) >
            std::make_pair(held.referenceTime, held.detectionTime))
          it->second.denm = denm;
        start_forwarding_timer(key, it->second);
      }
      return;
    default:
      break;
  }
  if (!mc.transmissionInterval) {
    // The newest version asks for no keep-alive forwarding.
    if (it != forwarding_.end()) {
      runtime_.cancel(it->second.timer);
      forwarding_.erase(it);
    }
    return;
  }
  // The version the LDM now holds is this one: forward that.
  if (it == forwarding_.end())
    it = forwarding_.emplace(key, Forwarding{}).first;
  Forwarding& f = it->second;
  f.denm = denm;
  f.area = rx.destination_area.value_or(relevance_area(denm));
  f.traffic_class = rx.traffic_class;
  start_forwarding_timer(key, f);
}

void DenService::start_forwarding_timer(Key key, Forwarding& f) {
  runtime_.cancel(f.timer);
  const auto& mc = f.denm.denm.management;
  const clock::Duration jitter =
      config_.kaf_jitter
          ? config_.kaf_jitter()
          : std::chrono::duration_cast<clock::Duration>(
                std::chrono::duration<double>(std::uniform_real_distribution<double>(
                    0.0, std::chrono::duration<double>(config_.kaf_jitter_max).count())(rng_)));
  const clock::Duration interval = std::chrono::milliseconds{*mc.transmissionInterval};
  const std::int64_t end_its =
      static_cast<std::int64_t>(mc.detectionTime) + std::int64_t{mc.validityDuration} * 1000;
  const clock::Duration remaining = std::chrono::milliseconds{
      std::max<std::int64_t>(0, end_its - timestamp_its(runtime_.wall_now()))};
  const clock::Duration delay = std::min(2 * interval + jitter, remaining);
  f.timer = runtime_.schedule_in(delay, [this, key] { forward(key); });
}

void DenService::forward(Key key) {
  auto it = forwarding_.find(key);
  if (it == forwarding_.end())
    return;
  Forwarding& f = it->second;
  const auto& mc = f.denm.denm.management;
  const std::int64_t end_its =
      static_cast<std::int64_t>(mc.detectionTime) + std::int64_t{mc.validityDuration} * 1000;
  if (timestamp_its(runtime_.wall_now()) >= end_its) {
    forwarding_.erase(it);  // BV-09: the event's validity is over
    return;
  }
  if (locator_ != nullptr && !locator_->inside(f.area)) {
    spdlog::debug("DEN service: outside the relevance area of {}/{}: no longer kept alive",
                  key.first, key.second);
    forwarding_.erase(it);  // BV-10
    return;
  }
  messages::Denm copy = f.denm;
  copy.header.stationID = config_.station_id;  // BV-04: the forwarder's header
  transmit(copy, f.area, f.traffic_class, true);
  start_forwarding_timer(key, f);
}

}  // namespace tb::its::facilities
