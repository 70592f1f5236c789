#include "its-station/apps/lcrw/lcrw_denm.hpp"

namespace tb::its::apps {

LcrwDenmTrigger::LcrwDenmTrigger(DenService& den, const geodesy::LocalFrame& frame,
                                 LcrwDenmConfig cfg)
    : den_(den), frame_(frame), cfg_(cfg) {}

RelevanceDistance LcrwDenmTrigger::relevance_for(double distance_m) {
  if (distance_m < 50.0) {
    return RelevanceDistance::kLessThan50m;
  }
  if (distance_m < 100.0) {
    return RelevanceDistance::kLessThan100m;
  }
  if (distance_m < 200.0) {
    return RelevanceDistance::kLessThan200m;
  }
  if (distance_m < 500.0) {
    return RelevanceDistance::kLessThan500m;
  }
  return RelevanceDistance::kLessThan1000m;
}

DenEventRequest LcrwDenmTrigger::request_for(const LcrwWarning& w,
                                             const VehicleKinematics& own) const {
  DenEventRequest r;
  r.cause_code = kCauseCollisionRisk;
  r.sub_cause_code = kSubCauseLongitudinalCollisionRisk;
  r.event_position = frame_.to_geodetic(geodesy::Enu{own.x, own.y, 0.0});
  r.event_heading_deg = own.heading_deg;
  r.detection_time = w.updated_at;
  // The area must hold the vehicle at risk: the gap is bumper to bumper, but the event lies at
  // the own reference point and the other is seen at its own, up to a car length or two
  // further, give or take GNSS error. Without the margin a 42 m gap got lessThan50m while the
  // other car stood 46 m from the event, on the area's edge (e2e frontal, issue 31).
  r.relevance_distance = relevance_for(w.distance_m + kRelevanceMarginM);
  // A rear-end risk concerns the traffic coming up behind; a head-on one both directions.
  r.relevance_traffic_direction = w.collision_case == CollisionCase::kForward
                                      ? RelevanceTrafficDirection::kUpstreamTraffic
                                      : RelevanceTrafficDirection::kAllTrafficDirections;
  r.validity_duration = cfg_.validity_duration;
  // A longitudinal collision risk is as time-critical as an emergency electronic brake light:
  // traffic class 0 (the C-ITS service profiles give EEBL 0, other DENMs 1).
  r.traffic_class = 0;
  return r;
}

void LcrwDenmTrigger::on_warning(const LcrwWarning& w, const VehicleKinematics& own) {
  const auto open = open_.find(w.other_station_id);
  if (w.event == WarningEvent::kCleared) {
    if (open != open_.end()) {
      den_.terminate(open->second);
      open_.erase(open);
      sent_.erase(w.other_station_id);
    }
    return;
  }
  const bool wanted = !cfg_.only_critical || w.severity == Severity::kCritical;
  if (open == open_.end()) {
    if (wanted) {
      const DenEventRequest r = request_for(w, own);
      if (const auto id = den_.trigger(r)) {
        open_.emplace(w.other_station_id, *id);
        sent_[w.other_station_id] = Sent{w.severity, r.relevance_distance};
      }
    }
    return;
  }
  // Updates only when the content that receivers act on changes, not at every evaluation: the
  // DEN service repeats the DENM by itself (EN 302 637-3, 8.2.2 T_Repetition).
  const DenEventRequest r = request_for(w, own);
  Sent& last = sent_[w.other_station_id];
  if (last.severity != w.severity || last.relevance != r.relevance_distance) {
    den_.update(open->second, r);
    last = Sent{w.severity, r.relevance_distance};
  }
}

}  // namespace tb::its::apps
