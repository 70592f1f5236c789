#include "common/map/opendrive/road_network.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

namespace tb::map::odr {

namespace {
std::string message(const std::string& file, const std::string& path, const std::string& reason) {
  std::string m = file.empty() ? std::string("<opendrive>") : file;
  if (!path.empty())
    m += ": " + path;
  return m + ": " + reason;
}
}  // namespace

MapError::MapError(std::string file, std::string path, const std::string& reason)
    : std::runtime_error(message(file, path, reason)),
      file_(std::move(file)),
      path_(std::move(path)) {}

const CubicRecord* CubicProfile::at(double s) const {
  if (records_.empty())
    return nullptr;
  auto it = std::upper_bound(records_.begin(), records_.end(), s,
                             [](double v, const CubicRecord& r) { return v < r.s; });
  if (it == records_.begin())
    return &records_.front();  // before the first: hold it
  return &*(it - 1);
}

double CubicProfile::value(double s) const {
  const CubicRecord* r = at(s);
  if (r == nullptr)
    return 0.0;
  const double ds = s - r->s;
  return r->a + ds * (r->b + ds * (r->c + ds * r->d));
}

double CubicProfile::derivative(double s) const {
  const CubicRecord* r = at(s);
  if (r == nullptr)
    return 0.0;
  const double ds = s - r->s;
  return r->b + ds * (2.0 * r->c + 3.0 * ds * r->d);
}

const Lane* LaneSection::lane(int id) const {
  if (id == 0)
    return &center;
  const auto& side = id > 0 ? left : right;
  const auto i = static_cast<std::size_t>(std::abs(id) - 1);
  return i < side.size() ? &side[i] : nullptr;
}

double LaneBorders::inner(int id) const {
  if (id == 0)
    return center;
  if (id > 0)
    return id == 1 ? center : left[static_cast<std::size_t>(id - 2)];
  return id == -1 ? center : right[static_cast<std::size_t>(-id - 2)];
}

double LaneBorders::outer(int id) const {
  if (id == 0)
    return center;
  if (id > 0)
    return left[static_cast<std::size_t>(id - 1)];
  return right[static_cast<std::size_t>(-id - 1)];
}

RefPoint Road::reference(double s) const {
  auto it =
      std::upper_bound(geometries.begin(), geometries.end(), s,
                       [](double v, const std::unique_ptr<Geometry>& g) { return v < g->s0(); });
  const Geometry& g = it == geometries.begin() ? *geometries.front() : **(it - 1);
  return g.at(s - g.s0());
}

double Road::curvature(double s) const {
  auto it =
      std::upper_bound(geometries.begin(), geometries.end(), s,
                       [](double v, const std::unique_ptr<Geometry>& g) { return v < g->s0(); });
  const Geometry& g = it == geometries.begin() ? *geometries.front() : **(it - 1);
  return g.curvature(s - g.s0());
}

std::size_t Road::section_index(double s) const {
  auto it = std::upper_bound(sections.begin(), sections.end(), s,
                             [](double v, const LaneSection& ls) { return v < ls.s; });
  return it == sections.begin() ? 0 : static_cast<std::size_t>(it - sections.begin()) - 1;
}

LaneBorders Road::borders(std::size_t section, double s) const {
  const LaneSection& ls = sections[section];
  const double ds = s - ls.s;
  LaneBorders b;
  b.center = lane_offset.value(s);
  // A lane's width adds to the border of the lane inside it; a lane given by <border> sets its
  // outer border directly (measured from the centre lane, so laneOffset shifts it too).
  double t = b.center;
  b.left.reserve(ls.left.size());
  for (const Lane& l : ls.left) {
    t = l.width.empty() ? b.center + l.border.value(ds) : t + l.width.value(ds);
    b.left.push_back(t);
  }
  t = b.center;
  b.right.reserve(ls.right.size());
  for (const Lane& l : ls.right) {
    t = l.width.empty() ? b.center - l.border.value(ds) : t - l.width.value(ds);
    b.right.push_back(t);
  }
  return b;
}

SurfacePose Road::surface(double s, double t) const {
  const RefPoint r = reference(s);
  const double roll = superelevation.value(s);
  SurfacePose p;
  p.x = r.x - t * std::sin(r.hdg);
  p.y = r.y + t * std::cos(r.hdg);
  p.z = elevation.value(s) + t * std::tan(roll);
  p.heading = r.hdg;
  p.pitch = std::atan(elevation.derivative(s));
  p.roll = roll;
  return p;
}

std::optional<double> Road::speed_limit(double s) const {
  std::optional<double> v;
  for (const RoadType& rt : types) {
    if (rt.s > s)
      break;
    v = rt.max_speed;
  }
  return v;
}

bool RoadSignal::valid_for(int lane_id) const {
  if (validity.empty())
    return true;
  for (const LaneRange& r : validity) {
    if (lane_id >= std::min(r.from, r.to) && lane_id <= std::max(r.from, r.to))
      return true;
  }
  return false;
}

int RoadNetwork::road_index(const std::string& id) const {
  for (std::size_t i = 0; i < roads.size(); ++i) {
    if (roads[i].id == id)
      return static_cast<int>(i);
  }
  return -1;
}

int RoadNetwork::junction_index(const std::string& id) const {
  for (std::size_t i = 0; i < junctions.size(); ++i) {
    if (junctions[i].id == id)
      return static_cast<int>(i);
  }
  return -1;
}

ContactPoint RoadNetwork::incoming_end(const Connection& c, std::size_t junction) const {
  const Road& in = roads[static_cast<std::size_t>(c.incoming_index)];
  const int ji = static_cast<int>(junction);
  if (in.successor && in.successor->to_junction && in.successor->index == ji) {
    return ContactPoint::kEnd;
  }
  if (in.predecessor && in.predecessor->to_junction && in.predecessor->index == ji) {
    return ContactPoint::kStart;
  }
  const Road& con = roads[static_cast<std::size_t>(c.connecting_index)];
  for (const auto* link : {&con.predecessor, &con.successor}) {
    if (*link && !(*link)->to_junction && (*link)->index == c.incoming_index) {
      return (*link)->contact;
    }
  }
  return ContactPoint::kEnd;
}

bool is_drivable(const std::string& lane_type) {
  static constexpr std::array<std::string_view, 13> kDrivable = {
      "driving",  "entry",   "exit", "onRamp", "offRamp", "connectingRamp", "bidirectional",
      "mwyEntry", "mwyExit", "bus",  "taxi",   "HOV",     "roadWorks"};
  return std::find(kDrivable.begin(), kDrivable.end(), lane_type) != kDrivable.end();
}

}  // namespace tb::map::odr
