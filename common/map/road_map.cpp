#include "common/map/road_map.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace tb::map {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};
template <class... Ts>
Overloaded(Ts...) -> Overloaded<Ts...>;

double wrap_positive(double v, double period) {
  double w = std::fmod(v, period);
  if (w < 0.0)
    w += period;
  return w >= period ? 0.0 : w;
}

// Centre line of a lane whose middle is `offset` metres left of the road's reference line.
CentreLine offset_line(const CentreLine& reference, double offset, bool reversed) {
  return std::visit(
      Overloaded{[&](const Segment& seg) -> CentreLine {
                   const Point left{-seg.dir.y, seg.dir.x};
                   Point start{seg.start.x + left.x * offset, seg.start.y + left.y * offset};
                   if (!reversed)
                     return Segment{start, seg.dir, seg.length};
                   return Segment{
                       {start.x + seg.dir.x * seg.length, start.y + seg.dir.y * seg.length},
                       {-seg.dir.x, -seg.dir.y},
                       seg.length};
                 },
                 [&](const Circle& c) -> CentreLine {
                   // Left of a counter-clockwise circle is towards its centre.
                   const double r = c.ccw ? c.radius - offset : c.radius + offset;
                   return Circle{c.centre, r, reversed ? !c.ccw : c.ccw};
                 }},
      reference);
}

Road make_road(int road_index, const CentreLine& reference, const scenario::MapSpec& spec) {
  Road road;
  road.reference = reference;
  road.width = spec.lanes * spec.lane_width;
  for (int i = 0; i < spec.lanes; ++i) {
    const double offset = -road.width / 2.0 + (i + 0.5) * spec.lane_width;
    const bool oncoming = i >= spec.lanes - spec.oncoming_lanes;
    road.lanes.push_back(
        Lane{road_index, i, spec.lane_width, oncoming, offset_line(reference, offset, oncoming)});
  }
  return road;
}

}  // namespace

double length(const CentreLine& line) {
  return std::visit(Overloaded{[](const Segment& s) { return s.length; },
                               [](const Circle& c) { return kTwoPi * c.radius; }},
                    line);
}

bool is_closed(const CentreLine& line) {
  return std::holds_alternative<Circle>(line);
}

Pose pose_at(const CentreLine& line, double s) {
  return std::visit(
      Overloaded{[&](const Segment& seg) {
                   const double t = std::clamp(s, 0.0, seg.length);
                   return Pose{{seg.start.x + seg.dir.x * t, seg.start.y + seg.dir.y * t},
                               std::atan2(seg.dir.y, seg.dir.x)};
                 },
                 [&](const Circle& c) {
                   // s = 0 is the circle's easternmost point.
                   const double a = wrap_positive(s, kTwoPi * c.radius) / c.radius;
                   const double theta = c.ccw ? a : -a;
                   const double yaw =
                       c.ccw ? theta + std::numbers::pi / 2 : theta - std::numbers::pi / 2;
                   return Pose{{c.centre.x + c.radius * std::cos(theta),
                                c.centre.y + c.radius * std::sin(theta)},
                               std::remainder(yaw, kTwoPi)};
                 }},
      line);
}

Projection project(const CentreLine& line, Point p) {
  return std::visit(Overloaded{[&](const Segment& seg) {
                                 const double dx = p.x - seg.start.x, dy = p.y - seg.start.y;
                                 const double s = dx * seg.dir.x + dy * seg.dir.y;
                                 const double lateral = seg.dir.x * dy - seg.dir.y * dx;
                                 return Projection{s, lateral, s >= 0.0 && s <= seg.length};
                               },
                               [&](const Circle& c) {
                                 const double dx = p.x - c.centre.x, dy = p.y - c.centre.y;
                                 const double d = std::hypot(dx, dy);
                                 const double theta = std::atan2(dy, dx);
                                 const double s = wrap_positive((c.ccw ? theta : -theta) * c.radius,
                                                                kTwoPi * c.radius);
                                 return Projection{s, c.ccw ? c.radius - d : d - c.radius, true};
                               }},
                    line);
}

RoadMap::RoadMap(const scenario::MapSpec& spec) : spec_(spec) {
  if (spec.lanes < 1 || spec.lane_width <= 0.0 || spec.oncoming_lanes < 0 ||
      spec.oncoming_lanes > spec.lanes) {
    throw std::invalid_argument("invalid lane layout");
  }
  switch (spec.type) {
    case scenario::MapType::kStraight:
      if (spec.length <= 0.0)
        throw std::invalid_argument("straight road needs a length > 0");
      roads_.push_back(make_road(0, Segment{{0.0, 0.0}, {1.0, 0.0}, spec.length}, spec));
      break;
    case scenario::MapType::kRing:
      if (spec.radius <= spec.lanes * spec.lane_width / 2.0) {
        throw std::invalid_argument("ring radius must exceed half the road width");
      }
      roads_.push_back(make_road(0, Circle{{0.0, 0.0}, spec.radius, true}, spec));
      break;
    case scenario::MapType::kCrossing:
      if (spec.arm_length <= 0.0)
        throw std::invalid_argument("crossing needs arm_length > 0");
      roads_.push_back(
          make_road(0, Segment{{-spec.arm_length, 0.0}, {1.0, 0.0}, 2 * spec.arm_length}, spec));
      roads_.push_back(
          make_road(1, Segment{{0.0, -spec.arm_length}, {0.0, 1.0}, 2 * spec.arm_length}, spec));
      break;
    case scenario::MapType::kOpenDrive:
      throw std::invalid_argument("an OpenDRIVE map is not a built-in layout");
  }
}

const Lane& RoadMap::lane(int road, int lane) const {
  if (road < 0 || road >= static_cast<int>(roads_.size())) {
    throw std::out_of_range("no road " + std::to_string(road));
  }
  const auto& lanes = roads_[road].lanes;
  if (lane < 0 || lane >= static_cast<int>(lanes.size())) {
    throw std::out_of_range("no lane " + std::to_string(lane) + " on road " + std::to_string(road));
  }
  return lanes[lane];
}

Pose RoadMap::lane_pose(int road, int lane_index, double s) const {
  return pose_at(lane(road, lane_index).centre, s);
}

std::optional<LaneMatch> RoadMap::find_lane(Point p, double yaw) const {
  std::optional<LaneMatch> best;
  double best_score = 0.0;
  for (const Road& road : roads_) {
    for (const Lane& lane : road.lanes) {
      const Projection pr = project(lane.centre, p);
      if (!pr.within || std::abs(pr.lateral) > lane.width / 2.0)
        continue;
      // Inside the lane's area; several lanes overlap only in a crossing's middle. Prefer the
      // lane that runs closest to the vehicle's own direction.
      const double lane_yaw = pose_at(lane.centre, pr.s).yaw;
      const double score = std::cos(yaw - lane_yaw);
      if (!best || score > best_score) {
        best = LaneMatch{lane.road, lane.index, pr};
        best_score = score;
      }
    }
  }
  return best;
}

bool RoadMap::on_road(Point p) const {
  for (const Road& road : roads_) {
    const Projection pr = project(road.reference, p);
    if (pr.within && std::abs(pr.lateral) <= road.width / 2.0)
      return true;
  }
  return false;
}

std::vector<Marking> RoadMap::markings() const {
  std::vector<Marking> out;
  for (const Road& road : roads_) {
    const int n = static_cast<int>(road.lanes.size());
    for (int i = 0; i <= n; ++i) {
      const double offset = -road.width / 2.0 + i * spec_.lane_width;
      Marking::Style style = Marking::Style::kDashed;
      if (i == 0 || i == n) {
        style = Marking::Style::kEdge;
      } else if (i == n - spec_.oncoming_lanes) {
        style = Marking::Style::kSolid;  // between the two directions of travel
      }
      out.push_back(Marking{style, offset_line(road.reference, offset, false)});
    }
  }
  return out;
}

}  // namespace tb::map
