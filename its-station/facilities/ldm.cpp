#include "its-station/facilities/ldm.hpp"

#include <utility>

#include "its-station/facilities/cdd_convert.hpp"
#include "its-station/facilities/its_time.hpp"

namespace tb::its::facilities {

std::string_view to_string(DenmOutcome o) {
  switch (o) {
    case DenmOutcome::kNew:
      return "new";
    case DenmOutcome::kUpdate:
      return "update";
    case DenmOutcome::kRepetition:
      return "repetition";
    case DenmOutcome::kOutdated:
      return "outdated";
    case DenmOutcome::kCancelled:
      return "cancelled";
    case DenmOutcome::kNegated:
      return "negated";
    case DenmOutcome::kUnknownTermination:
      return "unknown-termination";
    case DenmOutcome::kExpired:
      return "expired";
  }
  return "?";
}

Ldm::Ldm(clock::Runtime& runtime, LdmConfig config)
    : runtime_(runtime), config_(config), intersections_(runtime) {
  schedule_sweep();
}

Ldm::~Ldm() {
  runtime_.cancel(sweep_timer_);
}

void Ldm::schedule_sweep() {
  sweep_timer_ = runtime_.schedule_in(config_.sweep_interval, [this] {
    expire();
    schedule_sweep();
  });
}

std::int64_t Ldm::now_its() const {
  return timestamp_its(runtime_.wall_now());
}

void Ldm::add_cam(std::shared_ptr<const messages::Cam> shared, clock::WallTime rx_wall,
                  std::uint32_t sender_row) {
  const messages::Cam& cam = *shared;
  const auto& basic = cam.cam.camParameters.basicContainer;
  const auto lat = cdd::latitude_deg(basic.referencePosition.latitude);
  const auto lon = cdd::longitude_deg(basic.referencePosition.longitude);
  if (!lat || !lon)
    return;
  NeighbourSample s;
  s.received = runtime_.steady_now();
  s.received_wall = rx_wall;
  s.generation_delta_time = cam.cam.generationDeltaTime;
  s.generation_time = generation_time(cam.cam.generationDeltaTime, rx_wall);
  s.latitude_deg = *lat;
  s.longitude_deg = *lon;
  // An RSU's CAM (rsuContainerHighFrequency) names a position only: heading and speed stay
  // unknown, as for a vehicle that sends them unavailable.
  if (const auto* hf = messages::vehicle_hf(cam.cam.camParameters)) {
    s.heading_deg = cdd::heading_deg(hf->heading.headingValue);
    s.speed_mps = cdd::speed_mps(hf->speed.speedValue);
    if (s.speed_mps && hf->driveDirection == messages::DriveDirection::backward)
      s.speed_mps = -*s.speed_mps;
  }

  const auto id = cam.header.stationID;
  Neighbour* found = by_row_.get(sender_row);
  // A cell holds its row's neighbour; a caller's wrong row shows as another station id.
  if (found == nullptr || found->station_id != id) {
    auto [slot, is_new] = by_id_.try_emplace(id, nullptr);
    if (is_new) {
      auto [added, _] = neighbours_.try_emplace(id);
      added->second.station_id = id;
      added->second.history = SampleHistory(config_.history_length);
      slot->second = &added->second;
      expiry_checks_.push({s.received + config_.neighbour_timeout, slot->second});
    }
    found = slot->second;
    by_row_.set(sender_row, id, found);
  }
  auto& n = *found;
  n.station_type = basic.stationType;
  n.last_cam = std::move(shared);
  n.history.push_front(s);
  for (auto& l : neighbour_listeners_)
    l(n);
}

DenmOutcome Ldm::add_denm(const messages::Denm& denm) {
  const auto& mc = denm.denm.management;
  const std::int64_t expires =
      static_cast<std::int64_t>(mc.detectionTime) + std::int64_t{mc.validityDuration} * 1000;
  const ActionKey key{mc.actionID.originatingStationID, mc.actionID.sequenceNumber};
  auto notify = [&](const Event& e, DenmOutcome o) {
    for (auto& l : event_listeners_)
      l(e, o);
    return o;
  };
  // A DENM whose validity has ended is dropped (receiving ITS-S operation of EN 302 637-3).
  if (expires <= now_its())
    return DenmOutcome::kExpired;
  auto it = events_.find(key);
  if (it == events_.end()) {
    if (mc.termination)
      return DenmOutcome::kUnknownTermination;
    Event e{denm, runtime_.steady_now(), expires, false};
    auto [pos, _] = events_.emplace(key, e);
    return notify(pos->second, DenmOutcome::kNew);
  }
  Event& e = it->second;
  const auto& held = e.denm.denm.management;
  const auto order = std::make_pair(mc.referenceTime, mc.detectionTime);
  const auto held_order = std::make_pair(held.referenceTime, held.detectionTime);
  if (order < held_order)
    return DenmOutcome::kOutdated;
  if (order == held_order)
    return DenmOutcome::kRepetition;
  if (e.terminated && held.termination == messages::Termination::isCancellation && !mc.termination)
    return DenmOutcome::kOutdated;  // the originator ended it; nothing revives it
  const bool was_terminated = e.terminated;
  const auto held_termination = held.termination;  // `held` is overwritten below
  e.denm = denm;
  e.received = runtime_.steady_now();
  e.expires_its = expires;
  e.terminated = mc.termination.has_value();
  if (!mc.termination)
    return notify(e, DenmOutcome::kUpdate);
  if (was_terminated && held_termination == mc.termination)
    return DenmOutcome::kRepetition;  // a newer repetition of the end: the tombstone moves on
  return notify(e, *mc.termination == messages::Termination::isCancellation
                       ? DenmOutcome::kCancelled
                       : DenmOutcome::kNegated);
}

void Ldm::expire() {
  intersections_.expire();
  const auto now = runtime_.steady_now();
  // Forgotten once unheard for longer than the timeout, as a walk over all neighbours at this
  // sweep would decide.
  while (!expiry_checks_.empty() && expiry_checks_.top().due < now) {
    Neighbour* n = expiry_checks_.top().neighbour;
    expiry_checks_.pop();
    const auto last_heard = n->latest().received;
    if (now - last_heard <= config_.neighbour_timeout) {
      expiry_checks_.push({last_heard + config_.neighbour_timeout, n});
      continue;
    }
    const auto id = n->station_id;
    by_row_.forget(id);
    by_id_.erase(id);
    neighbours_.erase(id);
    for (auto& l : gone_listeners_)
      l(id);
  }
  const auto its = now_its();
  for (auto it = events_.begin(); it != events_.end();) {
    if (it->second.expires_its <= its)
      it = events_.erase(it);
    else
      ++it;
  }
}

const Neighbour* Ldm::neighbour(messages::StationID id) const {
  auto it = by_id_.find(id);
  return it == by_id_.end() ? nullptr : it->second;
}

std::vector<const Event*> Ldm::active_events() const {
  std::vector<const Event*> out;
  const auto its = now_its();
  for (const auto& [_, e] : events_)
    if (!e.terminated && e.expires_its > its)
      out.push_back(&e);
  return out;
}

const Event* Ldm::any_event(const messages::ActionID& id) const {
  auto it = events_.find({id.originatingStationID, id.sequenceNumber});
  return it == events_.end() ? nullptr : &it->second;
}

const Event* Ldm::event(const messages::ActionID& id) const {
  auto it = events_.find({id.originatingStationID, id.sequenceNumber});
  if (it == events_.end() || it->second.terminated)
    return nullptr;
  return &it->second;
}

}  // namespace tb::its::facilities
