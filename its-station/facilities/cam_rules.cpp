#include "its-station/facilities/cam_rules.hpp"

#include <algorithm>
#include <cmath>

#include "common/geodesy/local_frame.hpp"
#include "common/geodesy/wgs84.hpp"

namespace tb::its::facilities {

std::string_view to_string(CamTrigger t) {
  switch (t) {
    case CamTrigger::kNone:
      return "none";
    case CamTrigger::kFirst:
      return "first";
    case CamTrigger::kHeading:
      return "heading";
    case CamTrigger::kPosition:
      return "position";
    case CamTrigger::kSpeed:
      return "speed";
    case CamTrigger::kTime:
      return "time";
    case CamTrigger::kFixed:
      return "fixed";
  }
  return "?";
}

double distance_m(double lat1_deg, double lon1_deg, double lat2_deg, double lon2_deg) {
  const auto a = geodesy::to_ecef({lat1_deg, lon1_deg, 0.0});
  const auto b = geodesy::to_ecef({lat2_deg, lon2_deg, 0.0});
  return std::hypot(a.x - b.x, a.y - b.y, a.z - b.z);
}

CamRules::CamRules(CamTiming timing, scenario::CamPolicy policy)
    : timing_(timing), policy_(policy), t_gen_cam_(timing.T_GenCamMax) {}

void CamRules::reset() {
  last_.reset();
  last_lf_.reset();
  last_special_.reset();
  t_gen_cam_ = timing_.T_GenCamMax;
  consecutive_time_cams_ = 0;
}

CamTrigger CamRules::check(clock::SteadyTime now, const PositionFix& fix) const {
  if (!last_)
    return CamTrigger::kFirst;
  const auto elapsed = now - last_->time;
  if (policy_.kind == scenario::CamPolicy::Kind::kFixed) {
    const auto period = std::chrono::duration_cast<clock::Duration>(
        std::chrono::duration<double, std::milli>(policy_.period_ms));
    return elapsed >= period ? CamTrigger::kFixed : CamTrigger::kNone;
  }
  // Clause 6.1.3: neither condition may generate before T_GenCam_Dcc has elapsed.
  if (elapsed < timing_.T_GenCam_Dcc)
    return CamTrigger::kNone;
  // Condition 1: the station's dynamics changed since the last CAM.
  if (fix.heading_deg && last_->heading_deg &&
      std::abs(geodesy::heading_difference_deg(*fix.heading_deg, *last_->heading_deg)) >
          timing_.heading_threshold_deg)
    return CamTrigger::kHeading;
  if (distance_m(fix.latitude_deg, fix.longitude_deg, last_->latitude_deg, last_->longitude_deg) >
      timing_.position_threshold_m)
    return CamTrigger::kPosition;
  if (fix.speed_mps && last_->speed_mps &&
      std::abs(*fix.speed_mps - *last_->speed_mps) > timing_.speed_threshold_mps)
    return CamTrigger::kSpeed;
  // Condition 2.
  if (elapsed >= t_gen_cam_)
    return CamTrigger::kTime;
  return CamTrigger::kNone;
}

void CamRules::generated(clock::SteadyTime now, const PositionFix& fix, CamTrigger why) {
  const std::optional<clock::Duration> elapsed =
      last_ ? std::optional<clock::Duration>(now - last_->time) : std::nullopt;
  switch (why) {
    case CamTrigger::kHeading:
    case CamTrigger::kPosition:
    case CamTrigger::kSpeed:
      // Clause 6.1.3: after a condition-1 CAM, T_GenCam becomes the time since the previous
      // CAM (within [T_GenCamMin, T_GenCamMax]) ...
      if (elapsed)
        t_gen_cam_ =
            std::clamp<clock::Duration>(*elapsed, timing_.T_GenCamMin, timing_.T_GenCamMax);
      consecutive_time_cams_ = 0;
      break;
    case CamTrigger::kTime:
      // ... and returns to T_GenCamMax after N_GenCam consecutive condition-2 CAMs.
      if (++consecutive_time_cams_ >= timing_.N_GenCam) {
        t_gen_cam_ = timing_.T_GenCamMax;
        consecutive_time_cams_ = 0;
      }
      break;
    case CamTrigger::kFirst:
    case CamTrigger::kFixed:
    case CamTrigger::kNone:
      break;
  }
  last_ = Last{now, fix.latitude_deg, fix.longitude_deg, fix.heading_deg, fix.speed_mps};
}

bool CamRules::low_frequency_due(clock::SteadyTime now) const {
  return !last_lf_ || now - *last_lf_ >= timing_.lf_interval;
}

bool CamRules::special_vehicle_due(clock::SteadyTime now) const {
  return !last_special_ || now - *last_special_ >= timing_.special_vehicle_interval;
}

std::optional<clock::SteadyTime> CamRules::next_time_due() const {
  if (!last_)
    return std::nullopt;
  if (policy_.kind == scenario::CamPolicy::Kind::kFixed)
    return last_->time + std::chrono::duration_cast<clock::Duration>(
                             std::chrono::duration<double, std::milli>(policy_.period_ms));
  return last_->time + std::max(t_gen_cam_, timing_.T_GenCam_Dcc);
}

std::optional<clock::SteadyTime> CamRules::time_cam_deadline() const {
  const auto due = next_time_due();
  if (!due)
    return std::nullopt;
  if (policy_.kind == scenario::CamPolicy::Kind::kFixed)
    return *due + timing_.fresh_fix_wait;  // the thesis's constant period: no longer wait
  // Clause 6.1.3 has the conditions checked every T_CheckCamGen; a time-based CAM found due at
  // the first check after it fell due is made within one T_CheckCamGen. The interval between
  // two CAMs stays ≤ T_GenCamMax all the same (up to the fix jitter, fresh_fix_wait).
  return std::max(*due + timing_.fresh_fix_wait,
                  std::min(*due + timing_.T_CheckCamGen, last_->time + timing_.T_GenCamMax));
}

}  // namespace tb::its::facilities
