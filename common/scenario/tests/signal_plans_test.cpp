// Fixed-time signal plans (issue 34) read against the shipped four-way junction's lights
// (scenarios/maps/generate.py: junction "100", one controller per arm, ids 1 to 4), and the
// mistakes people writing plans make, each refused with the field named.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "common/scenario/loader.hpp"

namespace tb::scenario {
namespace {

namespace fs = std::filesystem;

fs::path root() {
  const char* r = std::getenv("TESTBED_ROOT");
  return r != nullptr ? fs::path(r) : fs::current_path();
}

/// A scenario on the four-way junction with @p signals (JSON text) as its "signals" field, or
/// none when empty; named as if it were in scenarios/ so that the map path resolves.
Scenario load(const std::string& signals, const std::string& map = "four_way_junction.xodr") {
  const std::string json =
      R"({"name": "plans", "map": {"type": "opendrive", "file": "maps/)" + map +
      R"("}, "origin": {"lat": 48.137, "lon": 11.575},)" +
      (signals.empty() ? std::string() : "\"signals\": " + signals + ",") +
      R"("vehicles": [{"id": "a", "station_id": 1, "spawn": {"road": "1", "lane": 1, "s": 55}}]})";
  return parse(json, (root() / "scenarios" / "plans.json").string());
}

TEST(SignalPlans, APlanIsReadWithItsTimes) {
  const Scenario s = load(R"([{"junction": "100", "offset_s": 7, "amber_s": 4, "all_red_s": 1,
    "red_amber_s": 1, "phases": [{"green": [3, 1], "duration_s": 25},
                                 {"green": [2, 4], "duration_s": 15}]}])");
  ASSERT_EQ(s.signals.size(), 1u);
  const SignalPlan& p = s.signals[0];
  EXPECT_EQ(p.junction, "100");
  EXPECT_FALSE(p.default_plan);
  EXPECT_EQ(p.offset_s, 7.0);
  EXPECT_EQ(p.amber_s, 4.0);
  EXPECT_EQ(p.all_red_s, 1.0);
  EXPECT_EQ(p.red_amber_s, 1.0);
  ASSERT_EQ(p.phases.size(), 2u);
  EXPECT_EQ(p.phases[0].green, (std::vector<int>{1, 3}));
  EXPECT_EQ(p.phases[0].duration_s, 25.0);
  EXPECT_EQ(p.groups, (std::vector<int>{1, 2, 3, 4}));
  // 25 + 15 s of green, and two changes of 4 + 1 + 1 s.
  EXPECT_DOUBLE_EQ(p.cycle_s(), 52.0);
}

TEST(SignalPlans, AJunctionWithLightsAndNoPlanGetsOnePhasePerGroup) {
  const Scenario s = load("");
  ASSERT_EQ(s.signals.size(), 1u);
  const SignalPlan& p = s.signals[0];
  EXPECT_TRUE(p.default_plan);
  EXPECT_EQ(p.junction, "100");
  ASSERT_EQ(p.phases.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(p.phases[static_cast<std::size_t>(i)].green, std::vector<int>{i + 1});
    EXPECT_EQ(p.phases[static_cast<std::size_t>(i)].duration_s, 20.0);
  }
  EXPECT_EQ(p.amber_s, 3.0);
  EXPECT_EQ(p.all_red_s, 2.0);
  EXPECT_EQ(p.red_amber_s, 0.0);
  EXPECT_DOUBLE_EQ(p.cycle_s(), 100.0);
}

TEST(SignalPlans, MapsWithoutLightsHaveNoPlans) {
  EXPECT_TRUE(load("", "motorway_merge.xodr").signals.empty());
}

TEST(SignalPlans, TheShippedScenariosRunTheirPlans) {
  const Scenario four = load_file(root() / "scenarios" / "four-way-junction.json");
  ASSERT_EQ(four.signals.size(), 1u);
  EXPECT_FALSE(four.signals[0].default_plan);
  const Scenario sig = load_file(root() / "scenarios" / "signals-junction.json");
  ASSERT_EQ(sig.signals.size(), 1u);
  EXPECT_FALSE(sig.signals[0].default_plan);
  EXPECT_EQ(sig.signals[0].offset_s, 31.0);
}

struct Bad {
  const char* signals;
  const char* path;
  const char* reason;
};

const Bad kBad[] = {
    {R"([{"junction": "7", "phases": [{"green": [1], "duration_s": 5}]}])", "/signals/0/junction",
     "junction \"7\" does not exist in maps/four_way_junction.xodr (its junctions: \"100\")"},
    {R"([{"phases": [{"green": [1], "duration_s": 5}]}])", "/signals/0/junction",
     "missing required field \"junction\""},
    {R"([{"junction": "100", "phases": [{"green": [1, 2, 3, 9], "duration_s": 5}]}])",
     "/signals/0/phases/0/green/3",
     "signal group 9 is not one of junction \"100\"'s (its signal groups, the <controller>s of "
     "maps/four_way_junction.xodr: 1, 2, 3, 4)"},
    {R"([{"junction": "100", "phases": [{"green": [1, 3], "duration_s": 5},
                                          {"green": [2], "duration_s": 5}]}])",
     "/signals/0/phases", "signal group 4 of junction \"100\" is green in no phase"},
    {R"([{"junction": "100", "phases": [{"green": [1, 3], "duration_s": 0},
                                          {"green": [2, 4], "duration_s": 5}]}])",
     "/signals/0/phases/0/duration_s", "a phase's green time must be longer than 0 s"},
    {R"([{"junction": "100", "phases": [{"green": [1, 3], "duration_s": -5},
                                          {"green": [2, 4], "duration_s": 5}]}])",
     "/signals/0/phases/0/duration_s", "value -5 is out of range [0, 3600]"},
    {R"([{"junction": "100", "amber_s": -1, "phases": [{"green": [1, 2, 3, 4], "duration_s": 5}]}])",
     "/signals/0/amber_s", "value -1 is out of range [0, 10]"},
    {R"([{"junction": "100", "all_red_s": -2, "phases": [{"green": [1, 2, 3, 4], "duration_s": 5}]}])",
     "/signals/0/all_red_s", "value -2 is out of range [0, 60]"},
    {R"([{"junction": "100", "phases": []}])", "/signals/0/phases",
     "expected 1 to 64 elements, found 0"},
    {R"([{"junction": "100", "phases": [{"green": [], "duration_s": 5}]}])",
     "/signals/0/phases/0/green", "expected 1 to 254 elements, found 0"},
    {R"([{"junction": "100", "phases": [{"green": [1, 2, 3, 1], "duration_s": 5}, {"green": [4], "duration_s": 5}]}])",
     "/signals/0/phases/0/green/3", "signal group 1 is named twice in this phase"},
    {R"([{"junction": "100", "phases": [{"green": ["1"], "duration_s": 5}]}])",
     "/signals/0/phases/0/green/0", "expected an integer, found a string"},
    {R"([{"junction": "100", "phases": [{"green": [1, 2, 3, 4], "duration": 5}]}])",
     "/signals/0/phases/0/duration_s", "missing required field \"duration_s\" (found \"duration\""},
    {R"([{"junction": "100", "phases": [{"green": [1, 2, 3, 4], "duration_s": 5, "amber_s": 3}]}])",
     "/signals/0/phases/0/amber_s", "unknown field \"amber_s\""},
    {R"([{"junction": "100", "offset_s": 10, "phases": [{"green": [1, 2, 3, 4], "duration_s": 5}]}])",
     "/signals/0/offset_s", "offset 10 s is not shorter than the cycle (10 s"},
    {R"([{"junction": "100", "phases": [{"green": [1, 2, 3, 4], "duration_s": 5}]},
         {"junction": "100", "phases": [{"green": [1, 2, 3, 4], "duration_s": 9}]}])",
     "/signals/1/junction", "a second plan for junction \"100\" (also /signals/0)"},
    {R"({"junction": "100"})", "/signals", "expected an array, found an object"},
};

TEST(SignalPlans, MistakesAreRefusedWithTheFieldNamed) {
  for (const Bad& b : kBad) {
    try {
      load(b.signals);
      ADD_FAILURE() << "accepted " << b.signals;
    } catch (const ScenarioError& e) {
      EXPECT_EQ(e.path(), b.path) << e.what();
      EXPECT_NE(e.reason().find(b.reason), std::string::npos)
          << "got \"" << e.reason() << "\", want \"" << b.reason << "\"";
    }
  }
  // A junction without lights, on a map that has none.
  try {
    load(R"([{"junction": "100", "phases": [{"green": [1], "duration_s": 5}]}])",
         "motorway_merge.xodr");
    ADD_FAILURE() << "a plan for a junction without lights";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(e.path(), "/signals/0/junction");
    EXPECT_NE(e.reason().find("junction \"100\" of maps/motorway_merge.xodr has no traffic lights"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace tb::scenario
