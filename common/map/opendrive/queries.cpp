#include "common/map/opendrive/queries.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>

namespace tb::map::odr {

namespace {
std::string road_path(const RoadNetwork& net, int road) {
  return "road[@id='" + net.roads[static_cast<std::size_t>(road)].id + "']";
}

/// A number for messages: millimetres at most, no trailing zeros ("30", "2.5", "100.125").
std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3f", v);
  std::string s(buf);
  if (s.find('.') != std::string::npos) {
    s.erase(s.find_last_not_of('0') + 1);
    if (s.back() == '.')
      s.pop_back();
  }
  return s == "-0" ? "0" : s;
}
}  // namespace

const Lane& lane_at(const RoadNetwork& net, int road, int lane, double s) {
  if (road < 0 || static_cast<std::size_t>(road) >= net.roads.size()) {
    throw MapError(net.source, "road[" + std::to_string(road + 1) + "]", "road does not exist");
  }
  const Road& r = net.roads[static_cast<std::size_t>(road)];
  if (!(s >= 0.0 && s <= r.length)) {
    throw MapError(net.source, road_path(net, road),
                   "s " + num(s) + " outside the road (length " + num(r.length) + ")");
  }
  const Lane* l = r.sections[r.section_index(s)].lane(lane);
  if (l == nullptr) {
    throw MapError(net.source, road_path(net, road),
                   "lane " + std::to_string(lane) + " does not exist at s " + num(s));
  }
  return *l;
}

double lane_centre_t(const Road& road, int lane, double s) {
  const LaneBorders b = road.borders(road.section_index(s), s);
  return lane == 0 ? b.center : (b.inner(lane) + b.outer(lane)) / 2.0;
}

SurfacePose lane_pose(const RoadNetwork& net, int road, int lane, double s, double offset) {
  (void)lane_at(net, road, lane, s);
  const Road& r = net.roads[static_cast<std::size_t>(road)];
  const double t = lane_centre_t(r, lane, s);
  SurfacePose p = r.surface(s, t + offset);
  // The centre line of a lane that widens or shifts drifts in t; its heading follows.
  const double h = 0.05;
  const double a = std::max(0.0, s - h);
  const double b = std::min(r.length, s + h);
  if (b > a) {
    const double dt = (lane_centre_t(r, lane, b) - lane_centre_t(r, lane, a)) / (b - a);
    const double stretch = std::max(0.1, 1.0 - r.curvature(s) * (t + offset));
    p.heading += std::atan2(dt, stretch);
  }
  return p;
}

SurfacePose spawn_pose(const RoadNetwork& net, const LaneSpawn& spawn) {
  const int road = net.road_index(spawn.road);
  const std::string path = "road[@id='" + spawn.road + "']";
  if (road < 0)
    throw MapError(net.source, path, "road does not exist");
  const Road& r = net.roads[static_cast<std::size_t>(road)];
  if (!(spawn.s >= 0.0 && spawn.s <= r.length)) {
    throw MapError(net.source, path,
                   "s " + num(spawn.s) + " past the road's end (length " + num(r.length) + ")");
  }
  const Lane& lane = lane_at(net, road, spawn.lane, spawn.s);
  const LaneBorders b = r.borders(r.section_index(spawn.s), spawn.s);
  const double width = std::fabs(b.outer(spawn.lane) - b.inner(spawn.lane));
  if (spawn.lane == 0 || !lane.drivable || width < 1.0) {
    throw MapError(net.source, path,
                   "lane " + std::to_string(spawn.lane) + " (" + lane.type + ", " + num(width) +
                       " m wide) is not drivable at s " + num(spawn.s));
  }
  SurfacePose p = lane_pose(net, road, spawn.lane, spawn.s, spawn.offset);
  if (!r.forward(spawn.lane)) {
    p.heading = std::remainder(p.heading + std::numbers::pi, 2 * std::numbers::pi);
    p.pitch = -p.pitch;
    p.roll = -p.roll;
  }
  return p;
}

int lane_of(const Road& road, std::size_t section, double s, double t) {
  const LaneBorders b = road.borders(section, s);
  if (t >= b.center) {
    for (std::size_t i = 0; i < b.left.size(); ++i) {
      if (t <= b.left[i] && b.left[i] > b.inner(static_cast<int>(i) + 1)) {
        return static_cast<int>(i) + 1;
      }
    }
  } else {
    for (std::size_t i = 0; i < b.right.size(); ++i) {
      if (t >= b.right[i] && b.right[i] < b.inner(-static_cast<int>(i) - 1)) {
        return -static_cast<int>(i) - 1;
      }
    }
  }
  return 0;
}

LaneLocator::LaneLocator(const RoadNetwork& net) : net_(net) {
  for (std::size_t i = 0; i < net.roads.size(); ++i)
    add_road(static_cast<int>(i));
  build_grid();
}

void LaneLocator::add_road(int index) {
  const Road& r = net_.roads[static_cast<std::size_t>(index)];
  // Cut at geometry starts so that no piece spans a kink in curvature, then every 2 m.
  std::vector<double> cuts;
  for (const auto& g : r.geometries) {
    if (g->s0() > 0 && g->s0() < r.length)
      cuts.push_back(g->s0());
  }
  for (const LaneSection& ls : r.sections) {
    if (ls.s > 0)
      cuts.push_back(ls.s);
  }
  cuts.push_back(0.0);
  cuts.push_back(r.length);
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  constexpr double kStep = 2.0;
  for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
    const double a = cuts[c];
    const double span = cuts[c + 1] - a;
    if (span <= 1e-9)
      continue;
    const int n = static_cast<int>(std::ceil(span / kStep));
    for (int k = 0; k < n; ++k) {
      Piece p{};
      p.road = index;
      p.s0 = a + span * k / n;
      p.s1 = k + 1 == n ? cuts[c + 1] : a + span * (k + 1) / n;
      const double mid = (p.s0 + p.s1) / 2;
      p.geometry = r.geometries.front().get();
      for (const auto& g : r.geometries) {
        if (g->s0() <= mid)
          p.geometry = g.get();
      }
      const RefPoint start = r.reference(p.s0);
      p.x0 = start.x;
      p.y0 = start.y;
      p.c0 = std::cos(start.hdg);
      p.s0n = std::sin(start.hdg);
      double reach = 0.0;
      double kmax = 0.0;
      for (double s : {p.s0, (p.s0 + p.s1) / 2, p.s1}) {
        const LaneBorders b = r.borders(r.section_index(std::min(s, p.s1 - 1e-9)), s);
        reach = std::max(reach, std::fabs(b.center));
        for (double v : b.left)
          reach = std::max(reach, std::fabs(v));
        for (double v : b.right)
          reach = std::max(reach, std::fabs(v));
        kmax = std::max(kmax, std::fabs(r.curvature(std::min(s, p.s1 - 1e-9))));
      }
      const double len = p.s1 - p.s0;
      p.reach = reach + 0.5 + kmax * len * len;
      p.slack = 0.5 + (reach + len) * std::min(1.0, kmax * len) + kmax * len * len;
      pieces_.push_back(p);
    }
  }
}

void LaneLocator::build_grid() {
  if (pieces_.empty())
    return;
  // Boxes around each piece's lanes, then a CSR grid of the boxes.
  struct Box {
    double x0, y0, x1, y1;
  };
  std::vector<Box> boxes;
  boxes.reserve(pieces_.size());
  double gx0 = std::numeric_limits<double>::max(), gy0 = gx0;
  double gx1 = std::numeric_limits<double>::lowest(), gy1 = gx1;
  for (const Piece& p : pieces_) {
    const Road& r = net_.roads[static_cast<std::size_t>(p.road)];
    // The lane area of the piece: the reference line offset by +-reach at its ends and middle
    // (the pieces are short, so the sagitta between them is in the margin of reach).
    Box b{p.x0, p.y0, p.x0, p.y0};
    for (double s : {p.s0, (p.s0 + p.s1) / 2, p.s1}) {
      const RefPoint q = r.reference(s);
      for (double side : {-1.0, 1.0}) {
        const double x = q.x - side * p.reach * std::sin(q.hdg);
        const double y = q.y + side * p.reach * std::cos(q.hdg);
        b.x0 = std::min(b.x0, x);
        b.y0 = std::min(b.y0, y);
        b.x1 = std::max(b.x1, x);
        b.y1 = std::max(b.y1, y);
      }
    }
    constexpr double kMargin = 0.25;
    b.x0 -= kMargin;
    b.y0 -= kMargin;
    b.x1 += kMargin;
    b.y1 += kMargin;
    gx0 = std::min(gx0, b.x0);
    gy0 = std::min(gy0, b.y0);
    gx1 = std::max(gx1, b.x1);
    gy1 = std::max(gy1, b.y1);
    boxes.push_back(b);
  }
  // Cells of 8 m, coarser only when the map is so large that the grid would pass 4 M cells.
  cell_ = std::max(8.0, std::sqrt((gx1 - gx0) * (gy1 - gy0) / 4e6));
  min_x_ = gx0;
  min_y_ = gy0;
  nx_ = static_cast<std::size_t>((gx1 - gx0) / cell_) + 1;
  ny_ = static_cast<std::size_t>((gy1 - gy0) / cell_) + 1;
  auto cells = [&](const Box& b, auto&& fn) {
    const auto cx0 = static_cast<std::size_t>((b.x0 - min_x_) / cell_);
    const auto cy0 = static_cast<std::size_t>((b.y0 - min_y_) / cell_);
    const auto cx1 = std::min(nx_ - 1, static_cast<std::size_t>((b.x1 - min_x_) / cell_));
    const auto cy1 = std::min(ny_ - 1, static_cast<std::size_t>((b.y1 - min_y_) / cell_));
    for (std::size_t cy = cy0; cy <= cy1; ++cy) {
      for (std::size_t cx = cx0; cx <= cx1; ++cx)
        fn(cy * nx_ + cx);
    }
  };
  cell_start_.assign(nx_ * ny_ + 1, 0);
  for (const Box& b : boxes)
    cells(b, [&](std::size_t c) { ++cell_start_[c + 1]; });
  for (std::size_t i = 1; i < cell_start_.size(); ++i)
    cell_start_[i] += cell_start_[i - 1];
  items_.resize(cell_start_.back());
  std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    cells(boxes[i], [&](std::size_t c) { items_[fill[c]++] = static_cast<std::uint32_t>(i); });
  }
}

bool LaneLocator::project(const Piece& p, double x, double y, double& s, double& t) const {
  const double dx = x - p.x0;
  const double dy = y - p.y0;
  const double along = dx * p.c0 + dy * p.s0n;
  const double across = -dx * p.s0n + dy * p.c0;
  const double len = p.s1 - p.s0;
  if (along < -p.slack || along > len + p.slack || std::fabs(across) > p.reach + p.slack) {
    return false;
  }
  const Geometry& g = *p.geometry;
  s = std::clamp(p.s0 + along, p.s0, p.s1);
  for (int i = 0; i < 8; ++i) {
    const RefPoint q = g.at(s - g.s0());
    const double ch = std::cos(q.hdg);
    const double sh = std::sin(q.hdg);
    const double ex = x - q.x;
    const double ey = y - q.y;
    const double ds = ex * ch + ey * sh;
    t = -ex * sh + ey * ch;
    // Newton on the foot point: on a curve the distance along the offset line is scaled by
    // (1 - k t) relative to the reference line.
    const double scale = std::max(0.1, 1.0 - g.curvature(s - g.s0()) * t);
    const double next = s + ds / scale;
    if (std::fabs(ds) < 1e-9)
      break;
    if ((next < p.s0 - 1e-9 && s <= p.s0) || (next > p.s1 + 1e-9 && s >= p.s1))
      return false;
    s = std::clamp(next, p.s0, p.s1);
  }
  const RefPoint q = g.at(s - g.s0());
  const double ch = std::cos(q.hdg);
  const double sh = std::sin(q.hdg);
  const double ds = (x - q.x) * ch + (y - q.y) * sh;
  t = -(x - q.x) * sh + (y - q.y) * ch;
  return std::fabs(ds) < 1e-6;
}

std::vector<LanePosition> LaneLocator::locate_all(double x, double y) const {
  std::vector<LanePosition> found;
  if (pieces_.empty() || !std::isfinite(x) || !std::isfinite(y))
    return found;
  const double fx = (x - min_x_) / cell_;
  const double fy = (y - min_y_) / cell_;
  if (fx < 0 || fy < 0 || fx >= static_cast<double>(nx_) || fy >= static_cast<double>(ny_)) {
    return found;
  }
  const std::size_t c = static_cast<std::size_t>(fy) * nx_ + static_cast<std::size_t>(fx);
  for (std::uint32_t i = cell_start_[c]; i < cell_start_[c + 1]; ++i) {
    const Piece& p = pieces_[items_[i]];
    if (std::any_of(found.begin(), found.end(),
                    [&](const LanePosition& f) { return f.ref.road == p.road; })) {
      continue;
    }
    double s = 0.0;
    double t = 0.0;
    if (!project(p, x, y, s, t))
      continue;
    const Road& r = net_.roads[static_cast<std::size_t>(p.road)];
    const std::size_t section = r.section_index(s);
    const int lane = lane_of(r, section, s, t);
    if (lane == 0)
      continue;
    const double z = r.elevation.value(s) + t * std::tan(r.superelevation.value(s));
    found.push_back({{p.road, lane}, section, s, t, z});
  }
  return found;
}

std::optional<LanePosition> LaneLocator::locate(double x, double y, std::optional<double> z,
                                                std::span<const LaneRef> prefer) const {
  std::vector<LanePosition> found = locate_all(x, y);
  if (found.empty())
    return std::nullopt;
  if (z) {
    const auto near = [&](const LanePosition& f) { return std::fabs(f.z - *z) <= 3.0; };
    if (std::any_of(found.begin(), found.end(), near)) {
      found.erase(
          std::remove_if(found.begin(), found.end(), [&](const auto& f) { return !near(f); }),
          found.end());
    }
  }
  for (const LaneRef& want : prefer) {
    for (const LanePosition& f : found) {
      if (f.ref == want)
        return f;
    }
  }
  auto rank = [&](const LanePosition& f) {
    const Road& r = net_.roads[static_cast<std::size_t>(f.ref.road)];
    const bool drivable = r.sections[f.section].lane(f.ref.lane)->drivable;
    return std::make_tuple(z ? std::fabs(f.z - *z) : 0.0, !drivable, f.ref.road);
  };
  return *std::min_element(found.begin(), found.end(),
                           [&](const auto& a, const auto& b) { return rank(a) < rank(b); });
}

}  // namespace tb::map::odr
