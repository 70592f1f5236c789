#include "its-station/facilities/den_service.hpp"

#include <algorithm>
#include <array>
#include <cmath>

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

DenService::DenService(clock::Runtime& runtime, MessageSender& sender, Ldm& ldm, DenConfig config)
    : runtime_(runtime), sender_(sender), ldm_(ldm), config_(config) {}

DenService::~DenService() {
  for (auto& [_, own] : own_)
    runtime_.cancel(own.timer);
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
  return d;
}

bool DenService::transmit(const messages::Denm& denm, const GeoArea& area) {
  std::array<std::uint8_t, messages::kDenmMaxEncodedSize> buf;
  auto n = messages::encode(denm, buf);
  if (!n) {
    spdlog::error("DEN service: cannot encode DENM: {}", asn1::to_string(n.error()));
    ++counters_.send_errors;
    return false;
  }
  const auto r = sender_.send_geobroadcast(kBtpPortDenm, area, std::span(buf.data(), *n),
                                           gn_lifetime_ms(denm.denm.management.validityDuration));
  if (r != SendResult::kSent) {
    ++counters_.send_errors;
    spdlog::warn("DEN service: DENM not sent: {}", to_string(r));
    return false;
  }
  ++counters_.sent;
  const auto& mc = denm.denm.management;
  trace::global().record("its.denm_tx", {{"station", config_.station_id},
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
  transmit(own.denm, own.area);
  start_repetition(own, own.interval, own.repeat_until - runtime_.steady_now());
}

Expected<messages::ActionID, DenError> DenService::trigger(const DenRequest& request) {
  const messages::ActionID id{config_.station_id, next_sequence_};
  auto denm = make(id, request, timestamp_its(runtime_.wall_now()));
  if (!denm)
    return Unexpected{denm.error()};
  // Sequence numbers wrap (clause 8.1.1 uses them modulo 2^16).
  ++next_sequence_;
  auto [it, _] =
      own_.insert_or_assign(Key{id.originatingStationID, id.sequenceNumber},
                            Own{*denm, request.destination_area, {}, {}, 0, false, false});
  if (!transmit(it->second.denm, it->second.area)) {
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
  if (!transmit(it->second.denm, it->second.area))
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
    if (!transmit(own.denm, own.area))
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
  GeoArea area;
  area.latitude_deg = cdd::latitude_deg(mc.eventPosition.latitude).value_or(0.0);
  area.longitude_deg = cdd::longitude_deg(mc.eventPosition.longitude).value_or(0.0);
  area.distance_a_m = config_.negation_radius_m;
  area.distance_b_m = config_.negation_radius_m;
  if (!transmit(neg, area))
    return Unexpected{DenError::kSendFailed};
  // Our own LDM applies the negation too, so the event stops being active here at once.
  ldm_.add_denm(neg);
  return id;
}

void DenService::receive(std::span<const std::uint8_t> payload,
                         std::optional<std::span<const std::uint8_t>> ssp) {
  auto denm = messages::decode_denm(payload);
  if (!denm) {
    ++counters_.decode_errors;
    spdlog::debug("DEN service: dropped undecodable DENM: {}", asn1::to_string(denm.error()));
    return;
  }
  const auto& mc = denm->denm.management;
  if (denm->header.stationID == config_.station_id)
    return;  // our own, heard back
  if (ssp) {
    if (const auto missing = denm_not_permitted(*denm, *ssp)) {
      ++counters_.not_permitted;
      spdlog::debug("DEN service: dropped DENM of {}: its AT does not permit {}",
                    denm->header.stationID, missing->name);
      return;
    }
  }
  ++counters_.received;
  // Another station negated one of our events: stop repeating it.
  if (mc.actionID.originatingStationID == config_.station_id && mc.termination) {
    auto it = own_.find({mc.actionID.originatingStationID, mc.actionID.sequenceNumber});
    if (it != own_.end()) {
      runtime_.cancel(it->second.timer);
      own_.erase(it);
      spdlog::info("DEN service: station {} negated our event {}", denm->header.stationID,
                   mc.actionID.sequenceNumber);
    }
    return;
  }
  const auto outcome = ldm_.add_denm(*denm);
  if (outcome != DenmOutcome::kNew && outcome != DenmOutcome::kUpdate &&
      outcome != DenmOutcome::kTerminated)
    ++counters_.dropped;
  trace::global().record("its.denm_rx", {{"station", config_.station_id},
                                         {"origin", mc.actionID.originatingStationID},
                                         {"seq", unsigned{mc.actionID.sequenceNumber}},
                                         {"outcome", to_string(outcome)}});
}

}  // namespace tb::its::facilities
