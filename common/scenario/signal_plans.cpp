#include "common/scenario/signal_plans.hpp"

#include <algorithm>
#include <map>
#include <set>

#include <fmt/format.h>

namespace tb::scenario::detail {

namespace {

std::string list(const std::vector<int>& ids) {
  std::string out;
  for (int id : ids)
    out += (out.empty() ? "" : ", ") + std::to_string(id);
  return out;
}

SignalPlan read_plan(Node& n, const map::odr::SignalLayout& layout,
                     const map::odr::RoadNetwork& net, const std::string& map_name) {
  n.expect_object("a signal plan");
  SignalPlan p;
  Node junction = n.required("junction");
  p.junction = junction.string();
  if (net.junction_index(p.junction) < 0) {
    std::string ids;
    for (const auto& j : net.junctions)
      ids += (ids.empty() ? "" : ", ") + ("\"" + j.id + "\"");
    junction.fail(fmt::format("junction \"{}\" does not exist in {} (its junctions: {})",
                              p.junction, map_name, ids.empty() ? "none" : ids));
  }
  const map::odr::SignalisedJunction* sj = layout.junction(p.junction);
  if (sj == nullptr) {
    junction.fail(fmt::format(
        "junction \"{}\" of {} has no traffic lights (no <controller> switches a light on its "
        "lanes or is listed by it)",
        p.junction, map_name));
  }
  p.groups = sj->groups;
  p.amber_s = n.number_or("amber_s", p.amber_s, 0.0, 10.0);
  p.all_red_s = n.number_or("all_red_s", p.all_red_s, 0.0, 60.0);
  p.red_amber_s = n.number_or("red_amber_s", p.red_amber_s, 0.0, 5.0);
  const std::set<int> known(p.groups.begin(), p.groups.end());
  std::set<int> served;
  Node phases = n.required("phases");
  for (Node& ph : phases.array(1, 64)) {
    ph.expect_object("a phase");
    SignalPhase phase;
    Node d = ph.required("duration_s");
    phase.duration_s = d.number(0.0, 3600.0);
    if (phase.duration_s <= 0.0)
      d.fail("a phase's green time must be longer than 0 s");
    for (const Node& g : ph.required("green").array(1, 254)) {
      const int id = static_cast<int>(g.integer(1, 254));
      if (known.count(id) == 0) {
        g.fail(
            fmt::format("signal group {} is not one of junction \"{}\"'s (its signal groups, "
                        "the <controller>s of {}: {})",
                        id, p.junction, map_name, list(p.groups)));
      }
      if (std::find(phase.green.begin(), phase.green.end(), id) != phase.green.end())
        g.fail(fmt::format("signal group {} is named twice in this phase", id));
      phase.green.push_back(id);
      served.insert(id);
    }
    std::sort(phase.green.begin(), phase.green.end());
    ph.finish();
    p.phases.push_back(std::move(phase));
  }
  for (int id : p.groups) {
    if (served.count(id) == 0) {
      phases.fail(
          fmt::format("signal group {} of junction \"{}\" is green in no phase: every "
                      "light of a junction must turn green",
                      id, p.junction));
    }
  }
  if (auto o = n.optional("offset_s")) {
    p.offset_s = o->number(0.0, 86400.0);
    if (p.offset_s >= p.cycle_s()) {
      o->fail(
          fmt::format("offset {} s is not shorter than the cycle ({} s: the phases' green "
                      "times and a change of amber_s + all_red_s + red_amber_s after each)",
                      p.offset_s, p.cycle_s()));
    }
  }
  n.finish();
  return p;
}

}  // namespace

std::vector<SignalPlan> read_signal_plans(std::optional<Node> node, const map::ScenarioMap& map,
                                          const std::string& map_name, const std::string& file) {
  const map::odr::SignalLayout* layout = nullptr;
  try {
    layout = &map.signals();
  } catch (const map::odr::MapError& e) {
    throw ScenarioError(file, "/map/file", e.what());
  }
  std::vector<SignalPlan> plans;
  std::map<std::string, std::string> planned;  // junction -> path of its plan
  if (node) {
    for (Node& n : node->array(0, 1024)) {
      SignalPlan p = read_plan(n, *layout, map.network(), map_name);
      if (const auto [it, fresh] = planned.emplace(p.junction, n.path()); !fresh) {
        n.required("junction")
            .fail(
                fmt::format("a second plan for junction \"{}\" (also {})", p.junction, it->second));
      }
      plans.push_back(std::move(p));
    }
  }
  std::vector<const map::odr::SignalisedJunction*> rest;
  for (const auto& sj : layout->junctions()) {
    if (planned.count(map.network().junctions[sj.junction].id) == 0)
      rest.push_back(&sj);
  }
  std::sort(rest.begin(), rest.end(),
            [](const auto* a, const auto* b) { return a->intersection_id < b->intersection_id; });
  for (const auto* sj : rest) {
    SignalPlan p;
    p.junction = map.network().junctions[sj->junction].id;
    p.groups = sj->groups;
    p.default_plan = true;
    for (int id : sj->groups)
      p.phases.push_back({{id}, kDefaultGreenS});
    plans.push_back(std::move(p));
  }
  return plans;
}

}  // namespace tb::scenario::detail
