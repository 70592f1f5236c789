#include "common/map/route_plan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>
#include <tuple>

#include <fmt/format.h>

namespace tb::map {
namespace {

constexpr double kLaneChangeCost = 20.0;  // m, as LaneGraph::route's default

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

double wrap(double a) {
  return std::remainder(a, 2.0 * std::numbers::pi);
}

bool contains(const std::vector<std::size_t>& v, std::size_t x) {
  return std::find(v.begin(), v.end(), x) != v.end();
}

}  // namespace

std::uint64_t vehicle_seed(std::uint64_t scenario_seed, std::uint32_t station_id) {
  std::uint64_t state = scenario_seed ^ (static_cast<std::uint64_t>(station_id) << 32);
  return splitmix64(state);
}

std::optional<LaneStart> lane_start(const odr::RoadNetwork& net, const odr::LaneLocator& locator,
                                    double x, double y, double yaw) {
  std::optional<LaneStart> best;
  std::tuple<int, double> best_key{3, 0.0};
  for (const odr::LanePosition& f : locator.locate_all(x, y)) {
    const odr::Road& r = net.roads[static_cast<std::size_t>(f.ref.road)];
    const odr::Lane* lane = r.sections[f.section].lane(f.ref.lane);
    if (lane == nullptr || !lane->drivable)
      continue;
    const odr::SurfacePose p = odr::lane_pose(net, f.ref.road, f.ref.lane, f.s);
    const double travel = r.forward(f.ref.lane) ? p.heading : p.heading + std::numbers::pi;
    const double fit = std::cos(yaw - travel);
    // Aligned (within 60°) before opposed before crosswise; then the nearest lane centre.
    const int group = fit >= 0.5 ? 0 : (fit <= -0.5 ? 1 : 2);
    const double off = std::fabs(f.t - odr::lane_centre_t(r, f.ref.lane, f.s));
    const std::tuple<int, double> key{group, off};
    if (!best || key < best_key) {
      best = LaneStart{f.ref.road, f.ref.lane, f.s, fit < 0.0};
      best_key = key;
    }
  }
  return best;
}

std::optional<LaneStart> vehicle_start(const scenario::Vehicle& v, const ScenarioMap& map) {
  const auto on_lane = [&](const scenario::RoadSpawn& r) -> std::optional<LaneStart> {
    const int road = map.network().road_index(r.road);
    if (road < 0)
      return std::nullopt;
    return LaneStart{road, r.lane, r.s, r.against};
  };
  if (const auto* r = std::get_if<scenario::RoadSpawn>(&v.spawn.where))
    return on_lane(*r);
  if (const auto* l = std::get_if<scenario::LaneSpawn>(&v.spawn.where))
    return on_lane(map.network_spawn(*l));
  // A pose: where the map places it (its heading turned into the map's frame).
  const Placement p = map.place(v.spawn);
  return lane_start(map.network(), map.locator(), p.x, p.y, p.yaw);
}

RoutePlan::RoutePlan(const odr::RoadNetwork& net, const odr::LaneGraph& graph,
                     const scenario::DriveRoute& route, const LaneStart& start, std::uint64_t seed)
    : net_(net), graph_(graph), kind_(route.kind), start_pos_(start), rng_(seed) {
  using Kind = scenario::DriveRoute::Kind;
  const auto node = graph.find(start.road, start.lane, start.s);
  if (!node || !graph.node(*node).drivable) {
    throw RouteError("", fmt::format("the vehicle starts on no drivable lane (road index {}, "
                                     "lane {}, s {:.1f})",
                                     start.road, start.lane, start.s));
  }
  start_ = current_ = *node;
  if (start.against && kind_ != Kind::kLane) {
    throw RouteError(kind_ == Kind::kTo ? "to" : "route",
                     "a route is driven in its lanes' direction of travel, but this vehicle "
                     "spawns driving against its lane (\"direction\": \"against\")");
  }
  if (kind_ == Kind::kRoads)
    plan_roads(route);
  else if (kind_ == Kind::kTo)
    plan_to(route);
}

std::vector<std::size_t> RoutePlan::onward(std::size_t n) const {
  const auto& all = start_pos_.against ? graph_.predecessors(n) : graph_.successors(n);
  std::vector<std::size_t> out;
  for (std::size_t m : all) {
    if (graph_.node(m).drivable)
      out.push_back(m);
  }
  return out;
}

std::size_t RoutePlan::straightest(const std::vector<std::size_t>& nodes) const {
  std::size_t best = nodes.front();
  double best_turn = std::numeric_limits<double>::infinity();
  for (std::size_t n : nodes) {
    const odr::LaneNode& ln = graph_.node(n);
    const odr::Road& r = net_.roads[static_cast<std::size_t>(ln.road)];
    const odr::LaneSection& ls = r.sections[ln.section];
    const double turn = std::fabs(wrap(r.reference(ls.s_end).hdg - r.reference(ls.s).hdg));
    if (turn < best_turn) {
      best_turn = turn;
      best = n;
    }
  }
  return best;
}

std::optional<PlanStep> RoutePlan::choose() {
  using Kind = scenario::DriveRoute::Kind;
  if (kind_ == Kind::kTo || kind_ == Kind::kRoads) {
    if (fixed_next_ < fixed_.size())
      return fixed_[fixed_next_++];
    if (kind_ == Kind::kTo)
      return std::nullopt;
    // After the list: on along the last road (its next lane sections) to its end.
    std::vector<std::size_t> same;
    for (std::size_t m : onward(current_)) {
      if (graph_.node(m).road == last_road_)
        same.push_back(m);
    }
    if (same.empty())
      return std::nullopt;
    return PlanStep{straightest(same), false};
  }
  const std::vector<std::size_t> next = onward(current_);
  if (next.empty()) {
    // A lane that ends beside one that goes on (an acceleration lane): merge into it.
    if (start_pos_.against)
      return std::nullopt;
    for (std::size_t nb : graph_.neighbours(current_)) {
      if (!onward(nb).empty())
        return PlanStep{nb, true};
    }
    return std::nullopt;
  }
  if (kind_ == Kind::kRandom)
    return PlanStep{next[splitmix64(rng_) % next.size()], false};
  return PlanStep{straightest(next), false};
}

std::optional<PlanStep> RoutePlan::next() {
  auto step = choose();
  if (step)
    current_ = step->node;
  return step;
}

void RoutePlan::plan_to(const scenario::DriveRoute& route) {
  const scenario::RouteGoal& to = route.to;
  const int road = net_.road_index(to.road);
  if (road < 0)
    throw RouteError("to/road", fmt::format("road \"{}\" does not exist in the map", to.road));
  const odr::Road& r = net_.roads[static_cast<std::size_t>(road)];
  if (!(to.s >= 0.0 && to.s <= r.length)) {
    throw RouteError("to/s", fmt::format("s {} is outside road \"{}\" (length {:.2f} m)", to.s,
                                         to.road, r.length));
  }
  try {
    (void)odr::spawn_pose(net_, odr::LaneSpawn{to.road, to.lane, to.s, 0.0});
  } catch (const odr::MapError&) {
    const odr::Lane* l = r.sections[r.section_index(to.s)].lane(to.lane);
    throw RouteError("to/lane",
                     l == nullptr
                         ? fmt::format("road \"{}\" has no lane {} at s {}", to.road, to.lane, to.s)
                         : fmt::format("lane {} of road \"{}\" ({}) is not drivable "
                                       "at s {}",
                                       to.lane, to.road, l->type, to.s));
  }
  const auto found = graph_.route({start_pos_.road, start_pos_.lane}, start_pos_.s, {road, to.lane},
                                  to.s, kLaneChangeCost);
  if (!found) {
    throw RouteError(
        "to", fmt::format("road \"{}\" lane {} at s {} cannot be reached from the spawn lane "
                          "(road \"{}\" lane {} at s {:.1f}): no lane path leads there",
                          to.road, to.lane, to.s,
                          net_.roads[static_cast<std::size_t>(start_pos_.road)].id, start_pos_.lane,
                          start_pos_.s));
  }
  for (std::size_t k = 1; k < found->nodes.size(); ++k) {
    const std::size_t n = found->nodes[k];
    fixed_.push_back({n, contains(graph_.neighbours(found->nodes[k - 1]), n)});
  }
  goal_s_ = to.s;
}

void RoutePlan::plan_roads(const scenario::DriveRoute& route) {
  // Stages: the roads in driving order (the spawn road first); stage k is reached on the first
  // node of its road. A node of a junction road carries the stage of the road before it.
  std::vector<int> stage_road;
  std::vector<int> user_index;  // index into route.roads of each stage, -1: the spawn road
  for (std::size_t i = 0; i < route.roads.size(); ++i) {
    const int r = net_.road_index(route.roads[i]);
    if (r < 0) {
      throw RouteError(fmt::format("route/{}", i),
                       fmt::format("road \"{}\" does not exist in the map", route.roads[i]));
    }
    if (i == 0 && r != start_pos_.road) {
      stage_road.push_back(start_pos_.road);
      user_index.push_back(-1);
    }
    stage_road.push_back(r);
    user_index.push_back(static_cast<int>(i));
  }
  const std::size_t stages = stage_road.size();
  const auto in_junction = [&](int road) {
    return net_.roads[static_cast<std::size_t>(road)].junction_index >= 0;
  };
  const std::size_t n = graph_.size();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(n * stages, inf);
  std::vector<std::size_t> via(n * stages, std::numeric_limits<std::size_t>::max());
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  const std::size_t first = start_;  // state = node * stages + stage
  dist[first * stages] = 0.0;
  open.push({0.0, first * stages});
  std::size_t reached = 0;
  std::optional<std::size_t> goal;
  while (!open.empty()) {
    // Plain copies: the lambda below captures them (clang 14 cannot capture bindings).
    const double d = open.top().first;
    const std::size_t state = open.top().second;
    open.pop();
    if (d > dist[state])
      continue;
    const std::size_t node = state / stages, stage = state % stages;
    reached = std::max(reached, stage);
    if (stage + 1 == stages) {
      goal = state;
      break;
    }
    const auto relax = [&](std::size_t m, std::size_t k, double cost) {
      const std::size_t to = m * stages + k;
      if (d + cost < dist[to]) {
        dist[to] = d + cost;
        via[to] = state;
        open.push({dist[to], to});
      }
    };
    const int road = graph_.node(node).road;
    for (std::size_t m : onward(node)) {
      const int mr = graph_.node(m).road;
      const double len = graph_.node(m).length;
      if (mr == stage_road[stage + 1])
        relax(m, stage + 1, len);
      else if (mr == stage_road[stage])
        relax(m, stage, len);
      else if (in_junction(mr) && (road == stage_road[stage] || in_junction(road)))
        relax(m, stage, len);
    }
    for (std::size_t m : graph_.neighbours(node)) {
      if (graph_.node(m).drivable)
        relax(m, stage, kLaneChangeCost);
    }
  }
  if (!goal) {
    const int from = stage_road[reached], to = stage_road[reached + 1];
    throw RouteError(
        fmt::format("route/{}", user_index[reached + 1]),
        fmt::format(
            "no lane leads from {}road \"{}\" to road \"{}\" (the route's roads must follow "
            "one another, through at most the connecting roads of junctions)",
            user_index[reached] < 0 ? "the spawn " : "",
            net_.roads[static_cast<std::size_t>(from)].id,
            net_.roads[static_cast<std::size_t>(to)].id));
  }
  std::vector<std::size_t> nodes;
  for (std::size_t s = *goal; s != first * stages; s = via[s])
    nodes.push_back(s / stages);
  std::reverse(nodes.begin(), nodes.end());
  std::size_t prev = start_;
  for (std::size_t m : nodes) {
    fixed_.push_back({m, contains(graph_.neighbours(prev), m)});
    prev = m;
  }
  last_road_ = stage_road.back();
}

}  // namespace tb::map
