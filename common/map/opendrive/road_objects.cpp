#include "common/map/opendrive/road_objects.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tb::map::odr {

namespace {

double lerp(double a, double b, double f) {
  return a + (b - a) * f;
}

double lerp_or(const std::optional<double>& a, const std::optional<double>& b, double fallback,
               double f) {
  if (!a && !b)
    return fallback;
  return lerp(a.value_or(fallback), b.value_or(a.value_or(fallback)), f);
}

}  // namespace

ItemPose item_pose(const Road& road, double s, double t, double z_offset, double hdg) {
  const SurfacePose p = road.surface(std::clamp(s, 0.0, road.length), t);
  return {p.x, p.y, p.z + z_offset, p.heading + hdg};
}

std::vector<PlacedObject> place_object(const Road& road, const RoadObject& o, double piece) {
  std::vector<PlacedObject> out;
  if (o.repeats.empty()) {
    PlacedObject p{
        &o, item_pose(road, o.s, o.t, o.z_offset, o.hdg), o.length, o.width, o.height, o.radius};
    if (o.outline.size() >= 3) {
      // The outline's bounding box: files put the origin anywhere in it (often a corner).
      double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300, h = 0.0;
      for (const OutlineCorner& c : o.outline) {
        u0 = std::min(u0, c.u);
        u1 = std::max(u1, c.u);
        v0 = std::min(v0, c.v);
        v1 = std::max(v1, c.v);
        h = std::max(h, c.z + c.height);
      }
      const double uc = (u0 + u1) / 2, vc = (v0 + v1) / 2;
      const double ch = std::cos(p.pose.heading), sh = std::sin(p.pose.heading);
      p.pose.x += uc * ch - vc * sh;
      p.pose.y += uc * sh + vc * ch;
      p.length = u1 - u0;
      p.width = v1 - v0;
      p.radius = 0.0;
      if (h > 0.0)
        p.height = h;
    }
    out.push_back(p);
    return out;
  }
  for (const ObjectRepeat& r : o.repeats) {
    auto at = [&](double f) {
      PlacedObject p;
      p.object = &o;
      p.length = lerp_or(r.length_start, r.length_end, o.length, f);
      p.width = lerp_or(r.width_start, r.width_end, o.width, f);
      p.height = lerp_or(r.height_start, r.height_end, o.height, f);
      p.radius = lerp_or(r.radius_start, r.radius_end, o.radius, f);
      p.pose = item_pose(road, r.s + f * r.length, lerp(r.t_start, r.t_end, f),
                         lerp(r.z_offset_start, r.z_offset_end, f), o.hdg);
      return p;
    };
    if (r.distance > 0.0) {
      const auto n = static_cast<int>(std::floor(r.length / r.distance + 1e-9));
      for (int i = 0; i <= n; ++i)
        out.push_back(at(r.length > 0.0 ? i * r.distance / r.length : 0.0));
      continue;
    }
    // Continuous: pieces along the road, each the chord between its ends (curves, t changing).
    const int n = std::max(1, static_cast<int>(std::ceil(r.length / std::max(0.1, piece))));
    for (int i = 0; i < n; ++i) {
      const double f0 = static_cast<double>(i) / n, f1 = static_cast<double>(i + 1) / n;
      const PlacedObject a = at(f0), b = at(f1);
      PlacedObject p = at((f0 + f1) / 2);
      p.pose.x = (a.pose.x + b.pose.x) / 2;
      p.pose.y = (a.pose.y + b.pose.y) / 2;
      p.pose.z = std::min(a.pose.z, b.pose.z);
      p.pose.heading = std::atan2(b.pose.y - a.pose.y, b.pose.x - a.pose.x);
      p.length = std::hypot(b.pose.x - a.pose.x, b.pose.y - a.pose.y);
      if (p.width <= 0.0)
        p.width = std::max(p.radius * 2, 0.2);  // a fence: thin
      p.radius = 0.0;
      out.push_back(p);
    }
  }
  return out;
}

ItemPose signal_pose(const Road& road, const RoadSignal& g) {
  const double turn = g.orientation == "-" ? std::numbers::pi : 0.0;
  return item_pose(road, g.s, g.t, g.z_offset, turn + g.h_offset);
}

bool is_stop_line(const RoadSignal& g) {
  return g.type == "294" || g.type == "stopLine";
}

}  // namespace tb::map::odr
