#include "sim-client/driver/drive_map.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <numbers>

#include "common/map/opendrive/mesh.hpp"

namespace tb::client {
namespace {

namespace odr = map::odr;

// Two junction lanes whose centre lines come closer than this can put two cars side by side
// in less room than two car widths (1.8 m each) and a margin: they conflict.
constexpr double kConflictDistance = 2.6;  // m
// How far back from a junction a chain of single lanes still counts as its approach.
constexpr double kApproachChain = 200.0;  // m

struct Seg {
  double ax, ay, bx, by;
};

double point_segment(double px, double py, const Seg& s) {
  const double dx = s.bx - s.ax, dy = s.by - s.ay;
  const double len2 = dx * dx + dy * dy;
  double u = len2 > 0 ? ((px - s.ax) * dx + (py - s.ay) * dy) / len2 : 0.0;
  u = std::clamp(u, 0.0, 1.0);
  return std::hypot(px - (s.ax + u * dx), py - (s.ay + u * dy));
}

double cross(double ax, double ay, double bx, double by) {
  return ax * by - ay * bx;
}

double segment_distance(const Seg& a, const Seg& b) {
  // Proper intersection: the ends of each lie on opposite sides of the other.
  const double d1 = cross(b.bx - b.ax, b.by - b.ay, a.ax - b.ax, a.ay - b.ay);
  const double d2 = cross(b.bx - b.ax, b.by - b.ay, a.bx - b.ax, a.by - b.ay);
  const double d3 = cross(a.bx - a.ax, a.by - a.ay, b.ax - a.ax, b.ay - a.ay);
  const double d4 = cross(a.bx - a.ax, a.by - a.ay, b.bx - a.ax, b.by - a.ay);
  if (((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0)))
    return 0.0;
  return std::min({point_segment(a.ax, a.ay, b), point_segment(a.bx, a.by, b),
                   point_segment(b.ax, b.ay, a), point_segment(b.bx, b.by, a)});
}

std::vector<Seg> centre_segments(const odr::RoadNetwork& net, const odr::LaneNode& n) {
  const auto pts =
      odr::lane_centre(net.roads[static_cast<std::size_t>(n.road)], n.section, n.lane, 0.05);
  std::vector<Seg> out;
  for (std::size_t i = 1; i < pts.size(); ++i)
    out.push_back({pts[i - 1].x, pts[i - 1].y, pts[i].x, pts[i].y});
  return out;
}

// Heading of travel on a lane at s, and how well it matches @p yaw (cosine).
double fit(const odr::RoadNetwork& net, const odr::LanePosition& f, double yaw) {
  const odr::Road& r = net.roads[static_cast<std::size_t>(f.ref.road)];
  const odr::SurfacePose p = odr::lane_pose(net, f.ref.road, f.ref.lane, f.s);
  const double travel = r.forward(f.ref.lane) ? p.heading : p.heading + std::numbers::pi;
  return std::cos(yaw - travel);
}

bool drivable(const odr::RoadNetwork& net, const odr::LanePosition& f) {
  const odr::Lane* l =
      net.roads[static_cast<std::size_t>(f.ref.road)].sections[f.section].lane(f.ref.lane);
  return l != nullptr && l->drivable;
}

}  // namespace

namespace {

std::int64_t cell_of(double v) {
  return static_cast<std::int64_t>(std::floor(v / Traffic::kCell));
}

std::uint64_t cell_key(std::int64_t cx, std::int64_t cy) {
  return (static_cast<std::uint64_t>(cx) << 32) ^ (static_cast<std::uint64_t>(cy) & 0xffffffffu);
}

}  // namespace

void Traffic::index() {
  cells_.clear();
  stations_.clear();
  max_length_ = 0.0;
  for (std::size_t i = 0; i < vehicles.size(); ++i) {
    const Observed& o = vehicles[i];
    max_length_ = std::max(max_length_, o.length);
    stations_.emplace_back(o.state.station_id, i);
    // A position beyond any map (a wild value on the wire) goes in no cell: the scan finds it.
    const double x = o.state.position[0], y = o.state.position[1];
    if (std::isfinite(x) && std::isfinite(y) && std::abs(x) < 1e9 && std::abs(y) < 1e9)
      cells_.emplace_back(cell_key(cell_of(x), cell_of(y)), i);
  }
  std::sort(cells_.begin(), cells_.end());
  // Stable: with two vehicles of one station id, find() returns the first as the scan does.
  std::stable_sort(stations_.begin(), stations_.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  indexed_ = cells_.size() == vehicles.size();
  indexed_size_ = vehicles.size();
}

const Observed* Traffic::find(std::uint32_t station_id) const {
  if (indexed_size_ == vehicles.size() && !stations_.empty()) {
    const auto it = std::lower_bound(stations_.begin(), stations_.end(), station_id,
                                     [](const std::pair<std::uint32_t, std::size_t>& e,
                                        std::uint32_t id) { return e.first < id; });
    return it != stations_.end() && it->first == station_id ? &vehicles[it->second] : nullptr;
  }
  for (const Observed& o : vehicles) {
    if (o.state.station_id == station_id)
      return &o;
  }
  return nullptr;
}

std::vector<const Observed*> Traffic::near(double x, double y, double radius) const {
  std::vector<const Observed*> out;
  if (!indexed_ || indexed_size_ != vehicles.size() || !std::isfinite(x) || !std::isfinite(y) ||
      !(radius < 1e6) || std::abs(x) >= 1e9 || std::abs(y) >= 1e9) {
    for (const Observed& o : vehicles)
      out.push_back(&o);
    return out;
  }
  std::vector<std::size_t> found;
  const std::int64_t x0 = cell_of(x - radius), x1 = cell_of(x + radius);
  const std::int64_t y0 = cell_of(y - radius), y1 = cell_of(y + radius);
  for (std::int64_t cx = x0; cx <= x1; ++cx) {
    for (std::int64_t cy = y0; cy <= y1; ++cy) {
      const std::uint64_t key = cell_key(cx, cy);
      auto it = std::lower_bound(cells_.begin(), cells_.end(), std::pair{key, std::size_t{0}});
      for (; it != cells_.end() && it->first == key; ++it)
        found.push_back(it->second);
    }
  }
  std::sort(found.begin(), found.end());
  out.reserve(found.size());
  for (const std::size_t i : found)
    out.push_back(&vehicles[i]);
  return out;
}

bool goes_before(const Observed& a, const Observed& b) {
  if (a.inside != b.inside)
    return a.inside;
  const double ta = a.to_entry / std::max<double>(a.state.speed, 1.0);
  const double tb = b.to_entry / std::max<double>(b.state.speed, 1.0);
  if (ta != tb)
    return ta < tb;
  return a.state.station_id < b.state.station_id;
}

DriveMap::DriveMap(std::shared_ptr<const map::ScenarioMap> map)
    : map_(std::move(map)),
      net_(&map_->network()),
      graph_(map_->graph()),
      locator_(map_->locator()) {
  junction_.resize(graph_.size());
  for (std::size_t i = 0; i < graph_.size(); ++i)
    junction_[i] = net_->roads[static_cast<std::size_t>(graph_.node(i).road)].junction_index;
  find_conflicts();
  find_approaches();
}

int DriveMap::junction_of(std::size_t node) const {
  return junction_[node];
}

bool DriveMap::conflict(std::size_t a, std::size_t b) const {
  const auto& c = conflict_[a];
  return std::binary_search(c.begin(), c.end(), b);
}

const DriveMap::Approach* DriveMap::approach(std::size_t node) const {
  return approach_[node] ? &*approach_[node] : nullptr;
}

double DriveMap::approach_horizon(double speed) {
  return std::max(40.0, speed * speed / (2.0 * 2.0) + 25.0);
}

void DriveMap::find_conflicts() {
  conflict_.resize(graph_.size());
  std::vector<std::vector<std::size_t>> by_junction(net_->junctions.size());
  for (std::size_t i = 0; i < graph_.size(); ++i) {
    if (junction_[i] >= 0 && graph_.node(i).drivable)
      by_junction[static_cast<std::size_t>(junction_[i])].push_back(i);
  }
  for (const auto& lanes : by_junction) {
    std::vector<std::vector<Seg>> segs;
    for (std::size_t n : lanes)
      segs.push_back(centre_segments(*net_, graph_.node(n)));
    for (std::size_t i = 0; i < lanes.size(); ++i) {
      for (std::size_t j = i + 1; j < lanes.size(); ++j) {
        // Lanes that split from one lane: the cars on them are in one queue before the split.
        const auto& pa = graph_.predecessors(lanes[i]);
        const auto& pb = graph_.predecessors(lanes[j]);
        const bool split = std::any_of(pa.begin(), pa.end(), [&](std::size_t p) {
          return std::find(pb.begin(), pb.end(), p) != pb.end();
        });
        if (split)
          continue;
        double d = 1e300;
        for (const Seg& a : segs[i]) {
          for (const Seg& b : segs[j])
            d = std::min(d, segment_distance(a, b));
        }
        if (d < kConflictDistance) {
          conflict_[lanes[i]].push_back(lanes[j]);
          conflict_[lanes[j]].push_back(lanes[i]);
        }
      }
    }
  }
  for (auto& c : conflict_)
    std::sort(c.begin(), c.end());
}

void DriveMap::find_approaches() {
  approach_.resize(graph_.size());
  std::deque<std::size_t> open;
  for (std::size_t p = 0; p < graph_.size(); ++p) {
    if (junction_[p] >= 0 || !graph_.node(p).drivable)
      continue;
    Approach a;
    for (std::size_t c : graph_.successors(p)) {
      if (junction_[c] >= 0 && graph_.node(c).drivable) {
        a.junction = junction_[c];
        a.entries.push_back(c);
      }
    }
    if (a.junction >= 0) {
      approach_[p] = std::move(a);
      open.push_back(p);
    }
  }
  // Back along lanes whose only way on is the lane already known to lead into the junction.
  while (!open.empty()) {
    const std::size_t p = open.front();
    open.pop_front();
    const Approach& ap = *approach_[p];
    const double after = ap.after + graph_.node(p).length;
    if (after > kApproachChain)
      continue;
    for (std::size_t q : graph_.predecessors(p)) {
      if (approach_[q] || junction_[q] >= 0 || !graph_.node(q).drivable)
        continue;
      const auto& next = graph_.successors(q);
      if (next.size() != 1)
        continue;
      approach_[q] = Approach{ap.junction, after, ap.entries};
      open.push_back(q);
    }
  }
}

void DriveMap::observe_one(Observed& o) const {
  const double x = o.state.position[0], y = o.state.position[1], yaw = o.state.yaw;
  const auto found = locator_.locate_all(x, y);
  std::vector<std::size_t> any_junction;
  double best_inside = -2.0;
  for (const odr::LanePosition& f : found) {
    const odr::Road& r = net_->roads[static_cast<std::size_t>(f.ref.road)];
    if (r.junction_index < 0 || !drivable(*net_, f))
      continue;
    const auto node = graph_.find_in_section(f.ref.road, f.section, f.ref.lane);
    if (!node)
      continue;
    o.inside = true;
    o.junction = r.junction_index;
    any_junction.push_back(*node);
    const double c = fit(*net_, f, yaw);
    if (c > std::cos(std::numbers::pi / 4)) {
      o.junction_lanes.push_back(*node);
      if (c > best_inside) {
        best_inside = c;
        o.lane = f;
      }
    }
  }
  if (o.inside) {
    // Crosswise in the junction (skidding, turning round): it may be on any lane under it.
    if (o.junction_lanes.empty())
      o.junction_lanes = std::move(any_junction);
    return;
  }
  double best = 1e300;
  for (const odr::LanePosition& f : found) {
    if (!drivable(*net_, f) || fit(*net_, f, yaw) < 0.5)
      continue;
    const odr::Road& r = net_->roads[static_cast<std::size_t>(f.ref.road)];
    const double off = std::fabs(f.t - odr::lane_centre_t(r, f.ref.lane, f.s));
    if (off < best) {
      best = off;
      o.lane = f;
    }
  }
  if (!o.lane)
    return;
  const auto node = graph_.find_in_section(o.lane->ref.road, o.lane->section, o.lane->ref.lane);
  const Approach* ap = node ? approach(*node) : nullptr;
  if (ap == nullptr)
    return;
  const odr::LaneSection& ls =
      net_->roads[static_cast<std::size_t>(o.lane->ref.road)].sections[o.lane->section];
  const double left = graph_.node(*node).forward ? ls.s_end - o.lane->s : o.lane->s - ls.s;
  const double to_entry = left + ap->after;
  if (to_entry > approach_horizon(std::max<double>(o.state.speed, 0.0)))
    return;
  o.junction = ap->junction;
  o.to_entry = to_entry;
  o.junction_lanes = ap->entries;
}

Traffic DriveMap::observe(std::span<const wire::VehicleState> states,
                          std::span<const VehicleSize> sizes) const {
  Traffic t;
  t.vehicles.reserve(states.size());
  for (std::size_t i = 0; i < states.size(); ++i) {
    const wire::VehicleState& s = states[i];
    Observed o;
    o.state = s;
    // The sizes come in the frame's order (the scenario's); a search only when they do not.
    const VehicleSize* size =
        i < sizes.size() && sizes[i].station_id == s.station_id ? &sizes[i] : nullptr;
    for (std::size_t k = 0; size == nullptr && k < sizes.size(); ++k) {
      if (sizes[k].station_id == s.station_id)
        size = &sizes[k];
    }
    if (size != nullptr) {
      o.length = size->length;
      o.width = size->width;
    }
    observe_one(o);
    t.vehicles.push_back(std::move(o));
  }
  t.index();
  return t;
}

}  // namespace tb::client
