#include "common/map/opendrive/lane_graph.hpp"

#include <algorithm>
#include <limits>
#include <queue>

namespace tb::map::odr {

LaneGraph::LaneGraph(const RoadNetwork& net) : net_(net) {
  first_.resize(net.roads.size());
  for (std::size_t r = 0; r < net.roads.size(); ++r) {
    const Road& road = net.roads[r];
    for (std::size_t k = 0; k < road.sections.size(); ++k) {
      const LaneSection& ls = road.sections[k];
      first_[r].push_back(nodes_.size());
      for (const auto* side : {&ls.left, &ls.right}) {
        for (const Lane& l : *side) {
          nodes_.push_back(
              {static_cast<int>(r), k, l.id, ls.s_end - ls.s, road.forward(l.id), l.drivable});
        }
      }
    }
  }
  next_.resize(nodes_.size());
  prev_.resize(nodes_.size());
  side_.resize(nodes_.size());
  link_roads();
  link_junctions();
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const LaneNode& n = nodes_[i];
    for (int d : {-1, 1}) {
      const int other = n.lane + d;
      if (other == 0 || (other > 0) != (n.lane > 0))
        continue;
      const auto j = find_in_section(n.road, n.section, other);
      if (j && nodes_[*j].forward == n.forward && nodes_[*j].drivable && n.drivable) {
        side_[i].push_back(*j);
      }
    }
  }
}

std::optional<std::size_t> LaneGraph::find_in_section(int road, std::size_t section,
                                                      int lane) const {
  if (road < 0 || static_cast<std::size_t>(road) >= first_.size())
    return std::nullopt;
  const auto& starts = first_[static_cast<std::size_t>(road)];
  if (section >= starts.size() || lane == 0)
    return std::nullopt;
  const LaneSection& ls = net_.roads[static_cast<std::size_t>(road)].sections[section];
  if (ls.lane(lane) == nullptr)
    return std::nullopt;
  // Nodes of a section: left lanes 1..n, then right lanes -1..-m.
  const std::size_t offset = lane > 0 ? static_cast<std::size_t>(lane - 1)
                                      : ls.left.size() + static_cast<std::size_t>(-lane - 1);
  return starts[section] + offset;
}

std::optional<std::size_t> LaneGraph::find(int road, int lane, double s) const {
  if (road < 0 || static_cast<std::size_t>(road) >= net_.roads.size())
    return std::nullopt;
  return find_in_section(road, net_.roads[static_cast<std::size_t>(road)].section_index(s), lane);
}

std::optional<std::size_t> LaneGraph::at_end(int road, ContactPoint end, int lane) const {
  const Road& r = net_.roads[static_cast<std::size_t>(road)];
  return find_in_section(road, end == ContactPoint::kEnd ? r.sections.size() - 1 : 0, lane);
}

void LaneGraph::add_edge(std::size_t from, std::size_t to) {
  if (std::find(next_[from].begin(), next_[from].end(), to) != next_[from].end())
    return;
  next_[from].push_back(to);
  prev_[to].push_back(from);
}

void LaneGraph::link_roads() {
  for (std::size_t r = 0; r < net_.roads.size(); ++r) {
    const Road& road = net_.roads[r];
    const int ri = static_cast<int>(r);
    for (std::size_t k = 0; k < road.sections.size(); ++k) {
      const LaneSection& ls = road.sections[k];
      for (const auto* side : {&ls.left, &ls.right}) {
        for (const Lane& l : *side) {
          const std::size_t self = *find_in_section(ri, k, l.id);
          const bool fwd = road.forward(l.id);
          // The link in the direction of travel; without a <link> the lane of the same id
          // continues it (what most generators mean by leaving links out).
          const std::optional<int> link = fwd ? l.successor : l.predecessor;
          const std::optional<int> target =
              link ? link : (l.has_link ? std::nullopt : std::optional<int>(l.id));
          if (!target)
            continue;
          const bool last = fwd ? k + 1 == road.sections.size() : k == 0;
          if (!last) {
            const auto j = find_in_section(ri, fwd ? k + 1 : k - 1, *target);
            if (j && nodes_[*j].forward == fwd)
              add_edge(self, *j);
            continue;
          }
          const auto& rl = fwd ? road.successor : road.predecessor;
          if (!rl || rl->to_junction || !link)
            continue;  // junctions: link_junctions()
          const auto j = at_end(rl->index, rl->contact, *link);
          // Entering the next road at its start means driving along its s, at its end against.
          if (j && nodes_[*j].forward == (rl->contact == ContactPoint::kStart))
            add_edge(self, *j);
        }
      }
    }
  }
}

void LaneGraph::link_junctions() {
  for (std::size_t ji = 0; ji < net_.junctions.size(); ++ji) {
    for (const Connection& c : net_.junctions[ji].connections) {
      const ContactPoint in_end = net_.incoming_end(c, ji);
      for (const LaneLink& ll : c.lane_links) {
        const auto a = at_end(c.incoming_index, in_end, ll.from);
        const auto b = at_end(c.connecting_index, c.contact, ll.to);
        if (!a || !b)
          continue;
        // The incoming lane drives into the junction when it runs towards the touching end.
        const bool inbound = nodes_[*a].forward == (in_end == ContactPoint::kEnd);
        const bool b_from_contact = nodes_[*b].forward == (c.contact == ContactPoint::kStart);
        if (inbound && b_from_contact)
          add_edge(*a, *b);
        if (!inbound && !b_from_contact)
          add_edge(*b, *a);
      }
    }
  }
}

std::optional<Route> LaneGraph::route(LaneRef from, double from_s, LaneRef to, double to_s,
                                      double lane_change_cost) const {
  (void)lane_at(net_, from.road, from.lane, from_s);
  (void)lane_at(net_, to.road, to.lane, to_s);
  const std::size_t start = *find(from.road, from.lane, from_s);
  const std::size_t goal = *find(to.road, to.lane, to_s);
  const LaneNode& sn = nodes_[start];
  // Distance from a position to the end of its node, in the direction of travel.
  auto remaining = [&](const LaneNode& n, double s) {
    const LaneSection& ls = net_.roads[static_cast<std::size_t>(n.road)].sections[n.section];
    return n.forward ? ls.s_end - s : s - ls.s;
  };
  if (start == goal && remaining(sn, from_s) >= remaining(sn, to_s)) {
    return Route{{start}, remaining(sn, from_s) - remaining(sn, to_s), 0};
  }
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(nodes_.size(), inf);
  std::vector<std::size_t> via(nodes_.size(), std::numeric_limits<std::size_t>::max());
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  // Costs count distance to the end of each node; the goal's remainder is subtracted at the end.
  dist[start] = remaining(sn, from_s);
  open.push({dist[start], start});
  while (!open.empty()) {
    // Plain copies, not a structured binding: the lambda below captures them (C++20 allows
    // capturing bindings, clang 14 does not).
    const double d = open.top().first;
    const std::size_t i = open.top().second;
    open.pop();
    if (d > dist[i])
      continue;
    if (i == goal)
      break;
    auto relax = [&](std::size_t j, double cost) {
      if (!nodes_[j].drivable || d + cost >= dist[j])
        return;
      dist[j] = d + cost;
      via[j] = i;
      open.push({dist[j], j});
    };
    for (std::size_t j : next_[i])
      relax(j, nodes_[j].length);
    for (std::size_t j : side_[i])
      relax(j, lane_change_cost);
  }
  // A goal behind the start on the start's own node would need a loop back to it; such a goal
  // is reported unreachable rather than searched for.
  if (dist[goal] == inf || goal == start)
    return std::nullopt;
  Route route;
  route.length = dist[goal] - remaining(nodes_[goal], to_s);
  for (std::size_t i = goal; i != start; i = via[i])
    route.nodes.push_back(i);
  route.nodes.push_back(start);
  std::reverse(route.nodes.begin(), route.nodes.end());
  for (std::size_t k = 1; k < route.nodes.size(); ++k) {
    const auto& side = side_[route.nodes[k - 1]];
    if (std::find(side.begin(), side.end(), route.nodes[k]) != side.end()) {
      ++route.lane_changes;
      route.length -= lane_change_cost;
    }
  }
  return route;
}

}  // namespace tb::map::odr
