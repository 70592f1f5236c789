#include "its-station/facilities/path_history.hpp"

#include <cmath>

#include "common/geodesy/local_frame.hpp"
#include "its-station/facilities/cam_rules.hpp"

namespace tb::its::facilities {

void PathHistoryRecorder::add(const PositionFix& fix) {
  if (!points_.empty()) {
    const auto& last = points_.front();
    if (fix.time <= last.time)
      return;
    const double d =
        distance_m(fix.latitude_deg, fix.longitude_deg, last.latitude_deg, last.longitude_deg);
    const bool turned = fix.heading_deg && last.heading_deg &&
                        std::abs(geodesy::heading_difference_deg(
                            *fix.heading_deg, *last.heading_deg)) > kHeadingStepDeg;
    if (d < kSpacingM && !(turned && d > 0.5))
      return;
  }
  points_.push_front({fix.time, fix.latitude_deg, fix.longitude_deg, fix.heading_deg});
  // Keep a little more than one CAM's worth beyond what build() can use.
  while (points_.size() > messages::kPathHistoryMaxPoints + 2)
    points_.pop_back();
}

messages::PathHistory PathHistoryRecorder::build(const PositionFix& reference) const {
  messages::PathHistory out;
  double prev_lat = reference.latitude_deg;
  double prev_lon = reference.longitude_deg;
  clock::WallTime prev_time = reference.time;
  double covered = 0.0;
  for (const auto& p : points_) {
    if (p.time >= reference.time)
      continue;
    if (out.full() || covered >= kMaxLengthM)
      break;
    const auto dlat = std::lround((p.latitude_deg - prev_lat) * 1e7);
    const auto dlon = std::lround((p.longitude_deg - prev_lon) * 1e7);
    // DeltaLatitude/DeltaLongitude reach ±131071 (about 13 m): a gap wider than that (a fix
    // outage) ends the history rather than sending a wrong point.
    if (std::abs(dlat) > 131071 || std::abs(dlon) > 131071)
      break;
    const auto dt_10ms =
        std::chrono::duration_cast<std::chrono::milliseconds>(prev_time - p.time).count() / 10;
    if (dt_10ms > 65535)
      break;
    messages::PathPoint pp;
    pp.pathPosition.deltaLatitude = static_cast<messages::DeltaLatitude>(dlat);
    pp.pathPosition.deltaLongitude = static_cast<messages::DeltaLongitude>(dlon);
    pp.pathPosition.deltaAltitude = messages::kDeltaAltitudeUnavailable;
    pp.pathDeltaTime = static_cast<messages::PathDeltaTime>(std::max<long long>(1, dt_10ms));
    out.push_back(pp);
    covered += distance_m(p.latitude_deg, p.longitude_deg, prev_lat, prev_lon);
    prev_lat = p.latitude_deg;
    prev_lon = p.longitude_deg;
    prev_time = p.time;
  }
  return out;
}

}  // namespace tb::its::facilities
