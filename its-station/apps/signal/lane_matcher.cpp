#include "its-station/apps/signal/lane_matcher.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/geodesy/local_frame.hpp"

namespace tb::its::apps::signal {

LaneProjection project_onto_lane(const GenericLane& lane, double x, double y) {
  LaneProjection best;
  double best_d2 = std::numeric_limits<double>::infinity();
  double from_stop_line = 0.0;  // centre-line length from node 0 to node i
  const std::size_t last = lane.nodes.size() - 1;
  for (std::size_t i = 0; i < last; ++i) {
    // Travel runs from node i+1 to node i (towards the stop line at node 0).
    const LocalPoint& to = lane.nodes[i];
    const LocalPoint& from = lane.nodes[i + 1];
    const double ux = to.x - from.x;
    const double uy = to.y - from.y;
    const double len2 = ux * ux + uy * uy;
    if (len2 <= 0.0) {
      continue;  // repeated node
    }
    const double len = std::sqrt(len2);
    const double raw = ((x - from.x) * ux + (y - from.y) * uy) / len2;  // 0 at from, 1 at to
    const bool off_far_end = i + 1 == last && raw < 0.0;
    // Only the first segment extends past the stop line.
    const double tau = std::max(0.0, i == 0 ? raw : std::min(raw, 1.0));
    const double fx = from.x + tau * ux;
    const double fy = from.y + tau * uy;
    const double dx = x - fx;
    const double dy = y - fy;
    const double d2 = dx * dx + dy * dy;
    if (d2 < best_d2) {
      best_d2 = d2;
      // Right of the travel direction (ux, uy) is (uy, -ux).
      const double side = dx * uy - dy * ux;
      best.lateral_offset_m = std::copysign(std::sqrt(d2), side);
      best.distance_to_stop_line_m = from_stop_line + (1.0 - tau) * len;
      best.lane_heading_deg = geodesy::wrap_360(std::atan2(ux, uy) * 180.0 / M_PI);
      best.beyond_far_end = off_far_end;
    }
    from_stop_line += len;
  }
  return best;
}

std::optional<LaneMatch> IngressLaneMatcher::candidate(const GenericLane& lane,
                                                       const LocalPose& pose, bool held) const {
  if (!lane.ingress || lane.nodes.size() < 2 || !std::isfinite(pose.x) || !std::isfinite(pose.y) ||
      !std::isfinite(pose.heading_deg) || !std::isfinite(pose.speed_mps)) {
    return std::nullopt;
  }
  LaneMatch m;
  m.lane_id = lane.lane_id;
  m.projection = project_onto_lane(lane, pose.x, pose.y);
  m.heading_error_deg =
      geodesy::heading_difference_deg(pose.heading_deg, m.projection.lane_heading_deg);
  if (m.projection.beyond_far_end) {
    return std::nullopt;
  }
  if (std::abs(m.projection.lateral_offset_m) > lane.lane_width_m / 2.0 + cfg_.gnss_tolerance_m) {
    return std::nullopt;
  }
  const double past_limit = held ? -cfg_.max_past_stop_line_m : 0.0;
  if (m.projection.distance_to_stop_line_m < past_limit) {
    return std::nullopt;
  }
  if (pose.speed_mps >= cfg_.min_speed_for_heading_mps) {
    if (std::abs(m.heading_error_deg) > cfg_.max_heading_error_deg) {
      return std::nullopt;
    }
  } else if (!held) {
    return std::nullopt;  // standing: the course says nothing about the direction
  }
  return m;
}

std::optional<LaneMatch> IngressLaneMatcher::update(const IntersectionTopology& t,
                                                    const LocalPose& pose) {
  if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.heading_deg) ||
      !std::isfinite(pose.speed_mps)) {
    return std::nullopt;  // not a position: the lane held is neither kept nor lost by it
  }
  const GenericLane* held_lane = held_ ? t.lane(*held_) : nullptr;
  if (held_ && (held_lane == nullptr || !held_lane->ingress)) {
    reset();  // the map's revision has no such lane any more
  }
  std::optional<LaneMatch> held_match;
  std::optional<LaneMatch> best_other;
  for (const GenericLane& lane : t.lanes) {
    if (held_ && lane.lane_id == *held_) {
      held_match = candidate(lane, pose, true);
      continue;
    }
    auto c = candidate(lane, pose, false);
    if (c && (!best_other || std::abs(c->projection.lateral_offset_m) <
                                 std::abs(best_other->projection.lateral_offset_m))) {
      best_other = c;
    }
  }

  auto take = [&](const LaneMatch& m) {
    held_ = m.lane_id;
    challenger_.reset();
    challenger_fixes_ = 0;
    missing_fixes_ = 0;
    return m;
  };
  if (!held_) {
    if (best_other) {
      return take(*best_other);
    }
    return std::nullopt;
  }

  const bool other_better =
      best_other &&
      (!held_match || std::abs(best_other->projection.lateral_offset_m) + cfg_.switch_margin_m <
                          std::abs(held_match->projection.lateral_offset_m));
  if (other_better) {
    if (challenger_ == best_other->lane_id) {
      ++challenger_fixes_;
    } else {
      challenger_ = best_other->lane_id;
      challenger_fixes_ = 1;
    }
    if (challenger_fixes_ >= cfg_.confirm_fixes) {
      return take(*best_other);
    }
  } else {
    challenger_.reset();
    challenger_fixes_ = 0;
  }

  if (held_match) {
    missing_fixes_ = 0;
    return held_match;
  }
  if (++missing_fixes_ >= cfg_.confirm_fixes) {
    held_.reset();
    challenger_.reset();
    challenger_fixes_ = 0;
    missing_fixes_ = 0;
    return std::nullopt;
  }
  // Grace: one noisy fix outside the lane does not end the match.
  LaneMatch grace;
  grace.lane_id = *held_;
  grace.projection = project_onto_lane(*held_lane, pose.x, pose.y);
  grace.heading_error_deg =
      geodesy::heading_difference_deg(pose.heading_deg, grace.projection.lane_heading_deg);
  return grace;
}

void IngressLaneMatcher::reset() {
  held_.reset();
  challenger_.reset();
  challenger_fixes_ = 0;
  missing_fixes_ = 0;
}

}  // namespace tb::its::apps::signal
