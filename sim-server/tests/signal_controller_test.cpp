// The fixed-time controllers driven by an injected world time: states over whole cycles against
// the schedule worked out by hand from the plan, and the rules of a signal plan (RiLSA-style
// intergreens): never two conflicting groups released at once, amber before every red, the
// next change announced when it really comes.

#include "sim-server/signals/signal_controller.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "sim-server/signals/signal_set.hpp"

namespace tb::server {
namespace {

using S = MovementPhaseState;
constexpr std::int64_t kStart = 1'795'000'000'000;  // world start, Unix ms
constexpr std::int64_t kStep = 10;                  // the physics step, ms

scenario::SignalPlan plan(std::vector<std::pair<std::vector<int>, double>> phases, double amber = 3,
                          double all_red = 2, double red_amber = 1, double offset = 0,
                          std::string junction = "100") {
  scenario::SignalPlan p;
  p.junction = std::move(junction);
  p.amber_s = amber;
  p.all_red_s = all_red;
  p.red_amber_s = red_amber;
  p.offset_s = offset;
  for (auto& [green, d] : phases) {
    p.phases.push_back({green, d});
    for (int g : green)
      if (std::find(p.groups.begin(), p.groups.end(), g) == p.groups.end())
        p.groups.push_back(g);
  }
  std::sort(p.groups.begin(), p.groups.end());
  return p;
}

std::map<int, S> at(const SignalController& c, std::int64_t t) {
  std::map<int, S> out;
  for (const GroupState& g : c.states(t))
    out[g.signal_group] = g.state;
  return out;
}

TEST(SignalController, TheFourWayPlanOverAWholeCycle) {
  // Groups 1+3 green 20 s, amber 3 s, all-red 2 s, red+amber 1 s for 2+4, their green 20 s,
  // and back: 52 s. Worked out by hand (seconds from the cycle's start):
  struct Span {
    std::int64_t from_ms, to_ms;
    S a, b;  // groups 1 and 3 / groups 2 and 4
  };
  const Span schedule[] = {
      {0, 20'000, S::kProtectedMovementAllowed, S::kStopAndRemain},
      {20'000, 23'000, S::kProtectedClearance, S::kStopAndRemain},
      {23'000, 25'000, S::kStopAndRemain, S::kStopAndRemain},
      {25'000, 26'000, S::kStopAndRemain, S::kPreMovement},
      {26'000, 46'000, S::kStopAndRemain, S::kProtectedMovementAllowed},
      {46'000, 49'000, S::kStopAndRemain, S::kProtectedClearance},
      {49'000, 51'000, S::kStopAndRemain, S::kStopAndRemain},
      {51'000, 52'000, S::kPreMovement, S::kStopAndRemain},
  };
  const SignalController c(plan({{{1, 3}, 20}, {{2, 4}, 20}}), kStart);
  EXPECT_EQ(c.intersection_id(), 100);
  EXPECT_EQ(c.groups(), (std::vector<int>{1, 2, 3, 4}));
  EXPECT_EQ(c.cycle_ms(), 52'000);
  for (int cycle = 0; cycle < 2; ++cycle) {
    for (const Span& sp : schedule) {
      for (std::int64_t t = sp.from_ms; t < sp.to_ms; t += kStep) {
        const std::int64_t now = kStart + cycle * 52'000 + t;
        const auto s = at(c, now);
        ASSERT_EQ(s.at(1), sp.a) << "at " << t << " ms";
        ASSERT_EQ(s.at(3), sp.a) << "at " << t << " ms";
        ASSERT_EQ(s.at(2), sp.b) << "at " << t << " ms";
        ASSERT_EQ(s.at(4), sp.b) << "at " << t << " ms";
      }
    }
  }
  // minEndTime: group 1 green from the start ends at 20 s, its amber at 23 s, its red at 51 s
  // (red+amber), that at 52 s; group 2's red holds until 25 s.
  const auto s0 = c.states(kStart + 5'000);
  EXPECT_EQ(s0[0].next_change_ms, kStart + 20'000);
  EXPECT_EQ(s0[1].next_change_ms, kStart + 25'000);
  EXPECT_EQ(c.states(kStart + 21'000)[0].next_change_ms, kStart + 23'000);
  EXPECT_EQ(c.states(kStart + 30'000)[0].next_change_ms, kStart + 51'000);
  EXPECT_EQ(c.states(kStart + 51'500)[0].next_change_ms, kStart + 52'000);
  // In the last stretch the next change of group 2 lies in the next cycle.
  EXPECT_EQ(c.states(kStart + 51'500)[1].next_change_ms, kStart + 52'000 + 25'000);
}

TEST(SignalController, TheCycleStartsAtTheWorldStartPlusOffsetAndRunsBeforeIt) {
  // Offset 31 s (scenarios/signals-junction.json): at sim time 0 groups 1 and 3 are 21 s into
  // the cycle, amber until 2 s; during the warm-up (negative sim time) the cycle runs on.
  const SignalController c(plan({{{1, 3}, 20}, {{2, 4}, 20}}, 3, 2, 1, 31), kStart);
  EXPECT_EQ(at(c, kStart).at(1), S::kProtectedClearance);
  EXPECT_EQ(c.states(kStart)[0].next_change_ms, kStart + 2'000);
  EXPECT_EQ(at(c, kStart + 2'000).at(1), S::kStopAndRemain);
  EXPECT_EQ(at(c, kStart + 5'000).at(2), S::kProtectedMovementAllowed);
  EXPECT_EQ(at(c, kStart - 1'010).at(1), S::kProtectedMovementAllowed);  // warm-up: green
  EXPECT_EQ(at(c, kStart - 1'000).at(1), S::kProtectedClearance);
  EXPECT_EQ(c.states(kStart - 3'000)[0].next_change_ms, kStart - 1'000);
}

/// Groups that never share a phase conflict.
bool conflict(const scenario::SignalPlan& p, int a, int b) {
  for (const auto& ph : p.phases) {
    const bool has_a = std::find(ph.green.begin(), ph.green.end(), a) != ph.green.end();
    const bool has_b = std::find(ph.green.begin(), ph.green.end(), b) != ph.green.end();
    if (has_a && has_b)
      return false;
  }
  return true;
}

bool released(S s) {
  return s == S::kProtectedMovementAllowed || s == S::kProtectedClearance;
}

TEST(SignalController, RulesOfAPlanHoldOverWholeCyclesOfEveryShape) {
  const scenario::SignalPlan plans[] = {
      plan({{{1, 3}, 20}, {{2, 4}, 20}}),
      plan({{{1}, 20}, {{2}, 20}, {{3}, 20}, {{4}, 20}}, 3, 2, 0),  // the loader's default
      plan({{{1, 2}, 12.5}, {{2, 3}, 7}, {{4}, 9.99}}, 4, 0, 1.5),  // 2 green in two phases
      plan({{{1}, 5}, {{2}, 5}}, 3, 0, 0, 3.3),                     // no all-red at all
      plan({{{5, 6, 7}, 30}}, 3, 2, 1),                             // one phase: always green
  };
  for (const auto& p : plans) {
    const SignalController c(p, kStart);
    SCOPED_TRACE("cycle " + std::to_string(c.cycle_ms()));
    std::map<int, S> before = at(c, kStart - kStep);
    std::map<int, std::int64_t> amber_since;
    std::set<int> seen_green;
    for (std::int64_t t = kStart; t < kStart + 2 * c.cycle_ms(); t += kStep) {
      const auto now = c.states(t);
      for (const GroupState& g : now) {
        // Never two conflicting groups released (green or amber) at once.
        for (const GroupState& h : now) {
          if (g.signal_group < h.signal_group && released(g.state) && released(h.state)) {
            ASSERT_FALSE(conflict(p, g.signal_group, h.signal_group))
                << g.signal_group << " and " << h.signal_group << " at " << t - kStart;
          }
        }
        const S was = before.at(g.signal_group);
        if (g.state != was) {
          // Green only ends in amber, and amber lasts amber_s before red.
          if (was == S::kProtectedMovementAllowed) {
            ASSERT_EQ(g.state, S::kProtectedClearance) << "group " << g.signal_group;
          }
          if (g.state == S::kProtectedClearance)
            amber_since[g.signal_group] = t;
          if (was == S::kProtectedClearance) {
            ASSERT_EQ(g.state, S::kStopAndRemain);
            ASSERT_EQ(t - amber_since.at(g.signal_group), std::llround(p.amber_s * 1000));
          }
          // Green comes after red+amber when the plan has it.
          if (g.state == S::kProtectedMovementAllowed && p.red_amber_s > 0) {
            ASSERT_EQ(was, S::kPreMovement);
          }
        }
        if (g.state == S::kProtectedMovementAllowed)
          seen_green.insert(g.signal_group);
        // The announced change comes then, and not before.
        if (g.next_change_ms) {
          ASSERT_GT(*g.next_change_ms, t);
          ASSERT_EQ(at(c, *g.next_change_ms - kStep / 10).at(g.signal_group), g.state);
          ASSERT_NE(at(c, *g.next_change_ms).at(g.signal_group), g.state);
        } else {
          ASSERT_EQ(at(c, t + c.cycle_ms() / 2).at(g.signal_group), g.state);
        }
      }
      before.clear();
      for (const GroupState& g : now)
        before[g.signal_group] = g.state;
    }
    EXPECT_EQ(seen_green.size(), c.groups().size());
  }
}

TEST(SignalController, AGroupGreenInConsecutivePhasesStaysGreenThroughTheChange) {
  // 2 is green in both phases: through amber, all-red and red+amber of the others it stays
  // green, and it never changes at all.
  const SignalController c(plan({{{1, 2}, 10}, {{2, 3}, 10}}, 3, 2, 1), kStart);
  for (std::int64_t t = 0; t < c.cycle_ms(); t += kStep)
    ASSERT_EQ(at(c, kStart + t).at(2), S::kProtectedMovementAllowed) << t;
  EXPECT_FALSE(c.states(kStart)[1].next_change_ms.has_value());
  EXPECT_EQ(at(c, kStart + 10'000).at(1), S::kProtectedClearance);
  EXPECT_EQ(at(c, kStart + 15'000).at(3), S::kPreMovement);
}

TEST(SignalController, RefusesPlansItCannotRun) {
  EXPECT_THROW(SignalController(plan({}), kStart), std::invalid_argument);
  EXPECT_THROW(SignalController(plan({{{1}, 5}}, 3, 2, 1, 0, "J1"), kStart), std::invalid_argument);
  EXPECT_THROW(SignalController(plan({{{1}, 5}}, 3, 2, 1, 0, "70000"), kStart),
               std::invalid_argument);
}

TEST(SignalSet, ReportsEveryGroupFirstThenOnlyChanges) {
  SignalSet set({plan({{{1, 3}, 20}, {{2, 4}, 20}}), plan({{{9}, 5}, {{8}, 5}}, 3, 0, 0, 0, "7")},
                kStart);
  auto first = set.step(kStart);
  ASSERT_EQ(first.size(), 6u);
  // Ascending by intersection, then group.
  EXPECT_EQ(first[0].intersection_id, 7);
  EXPECT_EQ(first[0].signal_group, 8);
  EXPECT_EQ(first[2].intersection_id, 100);
  EXPECT_EQ(first[2].signal_group, 1);
  EXPECT_EQ(first[2].state, S::kProtectedMovementAllowed);
  EXPECT_EQ(first[2].next_change_ms, kStart + 20'000);
  EXPECT_EQ(first[2].likely_change_ms, kStart + 20'000);
  EXPECT_TRUE(set.step(kStart + kStep).empty());
  // At 5 s junction 7 turns 9 amber; at 20 s junction 100 turns 1 and 3 amber.
  auto five = set.step(kStart + 5'000);
  ASSERT_EQ(five.size(), 1u);
  EXPECT_EQ(five[0].signal_group, 9);
  EXPECT_EQ(five[0].state, S::kProtectedClearance);
  auto twenty = set.step(kStart + 20'000);
  std::set<int> groups;
  for (const auto& g : twenty)
    if (g.intersection_id == 100)
      groups.insert(g.signal_group);
  EXPECT_EQ(groups, (std::set<int>{1, 3}));
  EXPECT_EQ(set.latest().world_time_ms, kStart + 20'000);
  EXPECT_EQ(set.latest().groups.size(), 6u);
  EXPECT_THROW(SignalSet({plan({{{1}, 5}}), plan({{{1}, 5}})}, kStart), std::invalid_argument);
}

}  // namespace
}  // namespace tb::server
