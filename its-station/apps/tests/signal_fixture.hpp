#pragma once
// A four-arm junction for the signal application's tests and benchmark: on every arm two
// ingress lanes (right-hand traffic) and two egress lanes, 3.5 m wide, stop lines 12 m from
// the reference point, 200 m long with a node every 20 m. Arm k is the south arm turned by
// k·90° counter-clockwise (0 south, 1 east, 2 north, 3 west); its lanes are 10k+1, 10k+2
// (ingress, 1 next to the centre line) and 10k+3, 10k+4 (egress); its signal group is k+1.
// Ingress lane 10k+1 connects straight on to the opposite arm's egress lane and left; 10k+2
// straight on and right.

#include <cmath>

#include "its-station/apps/signal/signal_model.hpp"

namespace tb::its::apps::signal::testing {

inline constexpr double kJunctionLatitude = 48.0;
inline constexpr double kJunctionLongitude = 11.0;
inline constexpr double kStopLineOffset = 12.0;
inline constexpr double kLaneWidth = 3.5;

inline LocalPoint rotate(LocalPoint p, int arm) {
  const double th = arm * M_PI / 2.0;
  return {p.x * std::cos(th) - p.y * std::sin(th), p.x * std::sin(th) + p.y * std::cos(th)};
}

inline std::uint8_t lane_id(int arm, int n) {
  return static_cast<std::uint8_t>(10 * (arm % 4) + n);
}

inline IntersectionTopology four_way_junction(std::uint16_t id = 1, std::uint8_t revision = 1) {
  IntersectionTopology t;
  t.intersection_id = id;
  t.revision = revision;
  t.ref_latitude_deg = kJunctionLatitude;
  t.ref_longitude_deg = kJunctionLongitude;
  for (int arm = 0; arm < 4; ++arm) {
    const auto group = static_cast<std::uint8_t>(arm + 1);
    for (int n = 1; n <= 4; ++n) {
      GenericLane l;
      l.lane_id = lane_id(arm, n);
      l.ingress = n <= 2;
      l.egress = !l.ingress;
      l.lane_width_m = kLaneWidth;
      // Ingress lanes east of the centre line on the south arm, egress lanes west of it.
      const double x = (n == 1 || n == 3 ? 0.5 : 1.5) * kLaneWidth * (l.ingress ? 1.0 : -1.0);
      for (int i = 0; i <= 10; ++i) {
        l.nodes.push_back(rotate({x, -kStopLineOffset - 20.0 * i}, arm));
      }
      if (n == 1) {
        l.connects_to = {{lane_id(arm + 2, 3), group}, {lane_id(arm + 3, 3), group}};
      } else if (n == 2) {
        l.connects_to = {{lane_id(arm + 2, 4), group}, {lane_id(arm + 1, 4), group}};
      }
      t.lanes.push_back(l);
    }
  }
  return t;
}

}  // namespace tb::its::apps::signal::testing
