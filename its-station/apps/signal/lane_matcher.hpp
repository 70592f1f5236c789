#pragma once
/// @file Which ingress lane of an intersection the vehicle is on, and how far its stop line is.
///
/// Rules (README.md, "Lane matching"): the position must lie within half the lane's width plus
/// a GNSS tolerance of the lane's centre line (a polyline of any number of nodes, so curved
/// lanes too), and the heading within a tolerance of the lane's direction there — towards the
/// stop line, i.e. from a node to the one before it. Hysteresis: the lane held is kept while it
/// qualifies, another lane replaces it only when it has been closer by a margin for a number of
/// consecutive fixes, and a lane is lost only after as many fixes outside it, so that GNSS noise
/// does not make the match flicker between adjacent lanes.

#include <cstddef>
#include <cstdint>
#include <optional>

#include "its-station/apps/signal/signal_model.hpp"

namespace tb::its::apps::signal {

/// The vehicle in the intersection's local frame.
struct LocalPose {
  double x = 0.0;            ///< east, m
  double y = 0.0;            ///< north, m
  double heading_deg = 0.0;  ///< ETSI: clockwise from north
  double speed_mps = 0.0;
};

/// A point related to a lane's centre line.
struct LaneProjection {
  /// Distance along the centre line to the stop line (the first node): 0 there, negative
  /// beyond it (measured along the first segment's extension).
  double distance_to_stop_line_m = 0.0;
  /// Distance from the centre line, positive to the right of the direction of travel.
  double lateral_offset_m = 0.0;
  /// Direction of travel on the lane at the projection (towards the stop line), ETSI degrees.
  double lane_heading_deg = 0.0;
  /// Beyond the lane's far end (upstream of its last node).
  bool beyond_far_end = false;
};

/// Projects @p x, @p y onto an ingress lane (≥ 2 nodes, validate()) to its nearest point.
LaneProjection project_onto_lane(const GenericLane& lane, double x, double y);

struct LaneMatcherConfig {
  /// Added to half the lane width for the position error: the default GNSS error model's 1-σ
  /// white noise per axis (docs/scenario.md, `white_noise_m` 1.0 m).
  double gnss_tolerance_m = 1.0;
  /// Largest angle between the heading and the lane's direction: lane changes and the heading
  /// noise of a GNSS track stay well inside, the egress lane beside (180°) and a crossing
  /// approach (90°) well outside.
  double max_heading_error_deg = 45.0;
  /// Below this speed the heading (a GNSS course) is noise: the lane held is kept on position
  /// alone, and no new lane is matched.
  double min_speed_for_heading_mps = 1.0;
  /// Another lane replaces the one held only when it is this much closer laterally ...
  double switch_margin_m = 0.5;
  /// ... for this many consecutive fixes; the lane held is lost after as many fixes outside.
  int confirm_fixes = 3;
  /// The lane held is followed this far past its stop line (negative distances), so that the
  /// application sees the vehicle pass; a new match is never past the stop line.
  double max_past_stop_line_m = 10.0;
};

struct LaneMatch {
  std::uint8_t lane_id = 0;
  LaneProjection projection;
  double heading_error_deg = 0.0;
};

/// Stateful (the hysteresis): one per intersection and vehicle. reset() forgets the lane held.
class IngressLaneMatcher {
 public:
  explicit IngressLaneMatcher(LaneMatcherConfig cfg = {}) : cfg_(cfg) {}

  /// The ingress lane of @p t the vehicle is on after this fix, or none.
  std::optional<LaneMatch> update(const IntersectionTopology& t, const LocalPose& pose);
  void reset();

  /// Whether @p pose satisfies the gates for @p lane, without hysteresis; @p held widens
  /// them as for the lane already matched (past the stop line, standing still).
  std::optional<LaneMatch> candidate(const GenericLane& lane, const LocalPose& pose,
                                     bool held) const;

  const std::optional<std::uint8_t>& held_lane() const { return held_; }
  const LaneMatcherConfig& config() const { return cfg_; }

 private:
  LaneMatcherConfig cfg_;
  std::optional<std::uint8_t> held_;
  std::optional<std::uint8_t> challenger_;
  int challenger_fixes_ = 0;
  int missing_fixes_ = 0;
};

}  // namespace tb::its::apps::signal
