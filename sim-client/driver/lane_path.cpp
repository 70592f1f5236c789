#include "sim-client/driver/lane_path.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/map/opendrive/mesh.hpp"

namespace tb::client {
namespace {

namespace odr = map::odr;

constexpr double kSampleTolerance = 0.02;    // m, chord error of the sampled lane centres
constexpr double kMaxStep = 2.0;             // m between points on lanes
constexpr double kBlendStep = 1.0;           // m between points in lane changes
constexpr double kChangeLateralAccel = 2.0;  // m/s², sets the length of a lane change
constexpr double kChangeMin = 15.0, kChangeMax = 80.0;  // m
constexpr double kSamePoint = 0.01;                     // m
constexpr double kChangeDelay = 10.0;  // m from the start to a lane change the plan begins with

// Smoothstep and its second derivative, for lane-change blends.
double smooth(double u) {
  return u * u * (3.0 - 2.0 * u);
}
double smooth2(double u) {
  return 6.0 - 12.0 * u;
}

}  // namespace

LanePath::LanePath(const DriveMap& map, map::RoutePlan plan, double change_speed)
    : map_(map), plan_(std::move(plan)), change_speed_(std::max(change_speed, 5.0)) {
  goal_ = plan_.goal_s();
  node_ = plan_.start_node();
  const map::LaneStart& st = plan_.start();
  // The start node is on the path from its entry, so that the vehicle finds itself on it and
  // can reverse along it.
  emit(node_, map_.graph().node(node_).lane, entry_s(node_), st.s, false);
  s_ = st.s;
  start_d_ = points_.empty() ? 0.0 : points_.back().d;
  pending_ = plan_.next();
  if (pending_ && pending_->lane_change) {
    // A lane change right away starts a little ahead, so that the driver can look for a gap
    // (and wait for one) before it begins.
    const double ahead = std::min(kChangeDelay, std::fabs(exit_s(node_) - s_) / 2.0);
    emit(node_, st.lane, s_, s_ + direction(node_) * ahead, false);
    s_ += direction(node_) * ahead;
  }
  if (points_.empty()) {
    const odr::Road& r = map_.network().roads[static_cast<std::size_t>(st.road)];
    const odr::SurfacePose p = r.surface(st.s, odr::lane_centre_t(r, st.lane, st.s));
    points_.push_back({p.x, p.y, 0.0, 0.0});
  }
  grow();
}

int LanePath::direction(std::size_t node) const {
  return map_.graph().node(node).forward != plan_.start().against ? 1 : -1;
}

double LanePath::entry_s(std::size_t node) const {
  const odr::LaneNode& n = map_.graph().node(node);
  const odr::LaneSection& ls =
      map_.network().roads[static_cast<std::size_t>(n.road)].sections[n.section];
  return direction(node) > 0 ? ls.s : ls.s_end;
}

double LanePath::exit_s(std::size_t node) const {
  const odr::LaneNode& n = map_.graph().node(node);
  const odr::LaneSection& ls =
      map_.network().roads[static_cast<std::size_t>(n.road)].sections[n.section];
  return direction(node) > 0 ? ls.s_end : ls.s;
}

void LanePath::emit(std::size_t node, int from_lane, double s_a, double s_b, bool front) {
  if (std::fabs(s_b - s_a) < 1e-9)
    return;
  const odr::LaneNode& n = map_.graph().node(node);
  const odr::Road& r = map_.network().roads[static_cast<std::size_t>(n.road)];
  const int dir = s_b > s_a ? 1 : -1;
  const bool blend = from_lane != n.lane;
  const double lo = std::min(s_a, s_b), hi = std::max(s_a, s_b);
  const double reach = std::fabs(odr::lane_centre_t(r, n.lane, (lo + hi) / 2)) + 2.0;
  std::vector<double> ss =
      odr::sample_s(r, lo, hi, kSampleTolerance, reach, blend ? kBlendStep : kMaxStep);
  if (dir < 0)
    std::reverse(ss.begin(), ss.end());
  const double span = hi - lo;
  std::vector<Point> pts;
  pts.reserve(ss.size());
  for (double s : ss) {
    double t = odr::lane_centre_t(r, n.lane, s);
    double t2 = 0.0;  // d²t/ds² of a blend
    if (blend) {
      const double u = std::clamp(std::fabs(s - s_a) / span, 0.0, 1.0);
      const double from = odr::lane_centre_t(r, from_lane, s);
      t = from + (t - from) * smooth(u);
      t2 = (odr::lane_centre_t(r, n.lane, s) - from) * smooth2(u) / (span * span);
    }
    const odr::SurfacePose p = r.surface(s, t);
    const double k = r.curvature(s);
    const double stretch = std::max(1.0 - k * t, 0.1);
    pts.push_back({p.x, p.y, 0.0, dir * (k / stretch + t2)});
  }
  if (pts.empty())
    return;
  Step step;
  step.node = node;
  step.road = n.road;
  step.lane = n.lane;
  step.from_lane = from_lane;
  step.junction = map_.junction_of(node);
  step.s0 = s_a;
  step.s1 = s_b;
  if (!front) {
    std::size_t i = 0;
    if (!points_.empty() &&
        std::hypot(pts[0].x - points_.back().x, pts[0].y - points_.back().y) < kSamePoint) {
      i = 1;
    }
    step.d0 = points_.empty() ? 0.0 : points_.back().d;
    for (; i < pts.size(); ++i) {
      const double d = points_.empty() ? 0.0
                                       : points_.back().d + std::hypot(pts[i].x - points_.back().x,
                                                                       pts[i].y - points_.back().y);
      pts[i].d = d;
      points_.push_back(pts[i]);
    }
    step.d1 = points_.back().d;
    steps_.push_back(step);
    return;
  }
  // Prepended: the step ends where the path now begins.
  std::size_t i = pts.size();
  if (std::hypot(pts.back().x - points_.front().x, pts.back().y - points_.front().y) < kSamePoint)
    --i;
  step.d1 = points_.front().d;
  while (i-- > 0) {
    pts[i].d =
        points_.front().d - std::hypot(pts[i].x - points_.front().x, pts[i].y - points_.front().y);
    points_.push_front(pts[i]);
  }
  step.d0 = points_.front().d;
  steps_.push_front(step);
}

void LanePath::grow() {
  if (ended_)
    return;
  const odr::LaneNode& n = map_.graph().node(node_);
  const int dir = direction(node_);
  double exit = exit_s(node_);
  if (pending_ && pending_->lane_change) {
    // Change lanes from here, as early as the plan allows, within this lane section.
    const std::size_t to = pending_->node;
    const odr::Road& r = map_.network().roads[static_cast<std::size_t>(n.road)];
    const double dt = std::fabs(odr::lane_centre_t(r, map_.graph().node(to).lane, s_) -
                                odr::lane_centre_t(r, n.lane, s_));
    double len = std::clamp(change_speed_ * std::sqrt(6.0 * dt / kChangeLateralAccel), kChangeMin,
                            kChangeMax);
    len = std::min(len, std::fabs(exit - s_));
    const double end = s_ + dir * len;
    emit(to, n.lane, s_, end, false);
    node_ = to;
    s_ = end;
    pending_ = plan_.next();
    return;
  }
  if (!pending_ && goal_) {
    // The goal's s on the last node; a goal inside the last lane change ends the path there.
    exit = (*goal_ - s_) * dir > 0 ? *goal_ : s_;
  }
  emit(node_, n.lane, s_, exit, false);
  if (!pending_) {
    ended_ = true;
    return;
  }
  node_ = pending_->node;
  s_ = entry_s(node_);
  pending_ = plan_.next();
}

void LanePath::extend_to(double d) {
  // Bounded so that a plan of zero-length lanes cannot spin.
  for (int guard = 0; guard < 10000 && !ended_ && points_.back().d < d; ++guard)
    grow();
}

void LanePath::extend_back_to(double d) {
  for (int guard = 0; guard < 1000 && points_.front().d > d; ++guard) {
    const Step& first = steps_.front();
    if (first.lane_change() || std::fabs(first.s0 - entry_s(first.node)) > 1e-9)
      return;
    const auto& prev = plan_.start().against ? map_.graph().successors(first.node)
                                             : map_.graph().predecessors(first.node);
    std::optional<std::size_t> only;
    for (std::size_t p : prev) {
      if (!map_.graph().node(p).drivable)
        continue;
      if (only)
        return;  // more than one way back: which one is unknown
      only = p;
    }
    if (!only)
      return;
    emit(*only, map_.graph().node(*only).lane, entry_s(*only), exit_s(*only), true);
  }
}

void LanePath::trim_before(double d) {
  while (steps_.size() > 1 && steps_.front().d1 < d)
    steps_.pop_front();
  while (points_.size() > 2 && points_[1].d <= steps_.front().d0)
    points_.pop_front();
}

std::size_t LanePath::index_at(double d) const {
  const auto it = std::lower_bound(points_.begin(), points_.end(), d,
                                   [](const Point& p, double v) { return p.d < v; });
  return static_cast<std::size_t>(it - points_.begin());
}

LanePath::Projection LanePath::project(double x, double y, double hint) const {
  if (points_.size() < 2)
    return {points_.front().d, 0.0};
  std::size_t i0 = index_at(hint - 15.0);
  std::size_t i1 = std::min(index_at(hint + 40.0) + 1, points_.size());
  i0 = i0 > 0 ? i0 - 1 : 0;
  if (i1 - i0 < 2) {
    i0 = std::min(i0, points_.size() - 2);
    i1 = i0 + 2;
  }
  Projection best;
  double best_dist = 1e300;
  for (std::size_t i = i0; i + 1 < i1; ++i) {
    const Point& a = points_[i];
    const Point& b = points_[i + 1];
    const double dx = b.x - a.x, dy = b.y - a.y;
    // Squared lengths: the nearest segment is the same, without a square root per segment.
    const double len2 = dx * dx + dy * dy;
    if (len2 < 1e-18)
      continue;
    double u = ((x - a.x) * dx + (y - a.y) * dy) / len2;
    // Beyond the ends of the path the end segments go on.
    const double lo = i == 0 ? -1e9 : 0.0, hi = i + 2 == points_.size() ? 1e9 : 1.0;
    u = std::clamp(u, lo, hi);
    const double px = a.x + u * dx, py = a.y + u * dy;
    const double dist2 = (x - px) * (x - px) + (y - py) * (y - py);
    if (dist2 < best_dist) {
      best_dist = dist2;
      best.d = a.d + u * (b.d - a.d);
      best.lateral = (dx * (y - a.y) - dy * (x - a.x)) / std::sqrt(len2);
    }
  }
  return best;
}

void LanePath::at(double d, double& x, double& y) const {
  if (points_.size() == 1) {
    x = points_.front().x;
    y = points_.front().y;
    return;
  }
  std::size_t i = index_at(d);
  i = std::clamp<std::size_t>(i, 1, points_.size() - 1);
  const Point& a = points_[i - 1];
  const Point& b = points_[i];
  const double u = b.d > a.d ? (d - a.d) / (b.d - a.d) : 0.0;
  x = a.x + u * (b.x - a.x);
  y = a.y + u * (b.y - a.y);
}

double LanePath::curvature(double d) const {
  const std::size_t i = index_at(d);
  if (i == 0 || i >= points_.size())
    return 0.0;
  const Point& a = points_[i - 1];
  const Point& b = points_[i];
  const double u = b.d > a.d ? (d - a.d) / (b.d - a.d) : 0.0;
  return a.curvature + u * (b.curvature - a.curvature);
}

void LanePath::tangent(double d, double& tx, double& ty) const {
  tx = 1.0;
  ty = 0.0;
  if (points_.size() < 2)
    return;
  std::size_t i = std::clamp<std::size_t>(index_at(d), 1, points_.size() - 1);
  const Point& a = points_[i - 1];
  const Point& b = points_[i];
  const double len = std::hypot(b.x - a.x, b.y - a.y);
  if (len > 1e-9) {
    tx = (b.x - a.x) / len;
    ty = (b.y - a.y) / len;
  }
}

}  // namespace tb::client
