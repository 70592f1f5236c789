// Road-side units of a scenario (issue 34), read against the shipped four-way junction
// (scenarios/maps/four_way_junction.xodr: junction "100" at the origin with lights, arms of
// 3.5 m lanes and 2 m sidewalks from 12 m to 80 m out along the axes, loops in the north-east
// and south-west quadrants), and every mistake refused with the field named.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "common/map/scenario_map.hpp"
#include "common/scenario/loader.hpp"
#include "common/scenario/rsus.hpp"

namespace tb::scenario {
namespace {

namespace fs = std::filesystem;

fs::path root() {
  const char* r = std::getenv("TESTBED_ROOT");
  return r != nullptr ? fs::path(r) : fs::current_path();
}

const char* kRsu =
    R"({"id": "rsu-100", "station_id": 5001, "junction": "100",
        "position": {"x": 14.0, "y": 14.0}, "height": 5.0})";

/// A scenario on @p map with @p rsus (JSON text) as its "rsus" field (none when empty) and one
/// vehicle "a" of station 1; named as if it were in scenarios/ so that the map path resolves.
Scenario load(const std::string& rsus, const std::string& map = "four_way_junction.xodr",
              std::optional<std::string_view> map_text = std::nullopt) {
  const std::string spawn = map == "motorway_merge.xodr" ? R"({"road": "1", "lane": -1, "s": 40})"
                                                         : R"({"road": "1", "lane": 1, "s": 55})";
  const std::string json = R"({"name": "rsus", "map": {"type": "opendrive", "file": "maps/)" + map +
                           R"("}, "origin": {"lat": 48.137, "lon": 11.575},)" +
                           (rsus.empty() ? std::string() : "\"rsus\": " + rsus + ",") +
                           R"("vehicles": [{"id": "a", "station_id": 1, "spawn": )" + spawn + "}]}";
  return parse(json, (root() / "scenarios" / "rsus.json").string(), map_text);
}

/// The error of loading @p rsus: the field it names, with the reason checked by the caller.
ScenarioError refused(const std::string& rsus, const std::string& map = "four_way_junction.xodr",
                      std::optional<std::string_view> map_text = std::nullopt) {
  try {
    load(rsus, map, map_text);
  } catch (const ScenarioError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted: " << rsus;
  return ScenarioError("", "", "");
}

TEST(Rsus, AnRsuIsReadWithItsFields) {
  const Scenario s = load(std::string("[") + kRsu + "]");
  ASSERT_EQ(s.rsus.size(), 1u);
  const Rsu& r = s.rsus[0];
  EXPECT_EQ(r.id, "rsu-100");
  EXPECT_EQ(r.station_id, 5001u);
  EXPECT_EQ(r.junction, "100");
  EXPECT_EQ(r.x, 14.0);
  EXPECT_EQ(r.y, 14.0);
  EXPECT_EQ(r.height_m, 5.0);
  EXPECT_EQ(s.find_rsu(5001), &r);
  EXPECT_EQ(s.find_rsu(1), nullptr);
  EXPECT_EQ(s.find_station(5001), nullptr);  // not a vehicle
}

TEST(Rsus, NoneUnlessGiven) {
  EXPECT_TRUE(load("").rsus.empty());
  EXPECT_TRUE(load("[]").rsus.empty());
}

TEST(Rsus, AJunctionIdMayBeANumber) {
  const Scenario s = load(
      R"([{"id": "r", "station_id": 9, "junction": 100, "position": {"x": -14, "y": 14},
           "height": 6}])");
  EXPECT_EQ(s.rsus.at(0).junction, "100");
}

TEST(Rsus, TheShippedSignalsScenarioHasOneAtJunction100) {
  const Scenario s = load_file(root() / "scenarios" / "signals-junction.json");
  ASSERT_EQ(s.rsus.size(), 1u);
  EXPECT_EQ(s.rsus[0].junction, "100");
  EXPECT_EQ(s.rsus[0].height_m, 5.0);
  // A corner of the junction: off every lane, within a few metres of the arms' sidewalks.
  const map::ScenarioMap m(s);
  EXPECT_FALSE(m.locator().locate(s.rsus[0].x, s.rsus[0].y).has_value());
  EXPECT_LT(detail::distance_to_road(*s.network, s.rsus[0].x, s.rsus[0].y), 10.0);
}

TEST(Rsus, AnUnknownJunctionIsRefused) {
  const ScenarioError e = refused(
      R"([{"id": "r", "station_id": 9, "junction": "7", "position": {"x": 14, "y": 14},
           "height": 5}])");
  EXPECT_EQ(e.path(), "/rsus/0/junction");
  EXPECT_NE(e.reason().find("junction \"7\" does not exist"), std::string::npos) << e.what();
  EXPECT_NE(e.reason().find("\"100\""), std::string::npos) << e.what();
}

TEST(Rsus, AJunctionWithoutLightsIsRefused) {
  // The motorway map's junctions are a merge and an exit: no controllers.
  const ScenarioError e = refused(
      R"([{"id": "r", "station_id": 9, "junction": "100", "position": {"x": 100, "y": 10},
           "height": 5}])",
      "motorway_merge.xodr");
  EXPECT_EQ(e.path(), "/rsus/0/junction");
  EXPECT_NE(e.reason().find("has no traffic lights"), std::string::npos) << e.what();
}

TEST(Rsus, DistanceToTheRoadFollowsTheMapsGeometry) {
  const Scenario s = load("");
  const auto& net = *s.network;
  // On arm 1's lane -1 (y from 0 to -3.5).
  EXPECT_EQ(detail::distance_to_road(net, 40.0, -1.0), 0.0);
  // South-east quadrant: arm 4 (x = 0, sidewalk to x = 5.5) is 34.5 m away, arm 1 44.5 m.
  EXPECT_NEAR(detail::distance_to_road(net, 40.0, -50.0), 34.5, 0.5);
  // Arm 4 54.5 m, arm 1 64.5 m; the south-west loop's last arc (centre (-25, -80), radius 25,
  // 6.5 m to its outer edge) about 54 m.
  EXPECT_NEAR(detail::distance_to_road(net, 60.0, -70.0), 54.1, 1.0);
}

TEST(Rsus, AnRsuFartherThan50mFromEveryRoadIsRefused) {
  EXPECT_NO_THROW(load(
      R"([{"id": "r", "station_id": 9, "junction": "100", "position": {"x": 40, "y": -50},
           "height": 5}])"));
  const ScenarioError e = refused(
      R"([{"id": "r", "station_id": 9, "junction": "100", "position": {"x": 60, "y": -70},
           "height": 5}])");
  EXPECT_EQ(e.path(), "/rsus/0/position");
  EXPECT_NE(e.reason().find("within 50 m of a road"), std::string::npos) << e.what();
  const ScenarioError far = refused(
      R"([{"id": "r", "station_id": 9, "junction": "100", "position": {"x": 5000, "y": 0},
           "height": 5}])");
  EXPECT_EQ(far.path(), "/rsus/0/position");
}

TEST(Rsus, AnRsuOutsideTheExtentOfTheMapsHeaderIsRefused) {
  std::ifstream in(root() / "scenarios" / "maps" / "four_way_junction.xodr");
  std::ostringstream buf;
  buf << in.rdbuf();
  std::string text = buf.str();
  const std::string header = "<header revMajor=\"1\"";
  const auto at = text.find(header);
  ASSERT_NE(at, std::string::npos);
  text.insert(at + header.size(), " north=\"20\" south=\"-20\" east=\"20\" west=\"-20\"");
  EXPECT_NO_THROW(load(std::string("[") + kRsu + "]", "four_way_junction.xodr", text));
  // 3 m beside arm 1's sidewalk, but east of the extent.
  const ScenarioError e = refused(
      R"([{"id": "r", "station_id": 9, "junction": "100", "position": {"x": 30, "y": 8.5},
           "height": 5}])",
      "four_way_junction.xodr", text);
  EXPECT_EQ(e.path(), "/rsus/0/position");
  EXPECT_NE(e.reason().find("outside the map's extent"), std::string::npos) << e.what();
}

TEST(Rsus, AStationIdUsedTwiceIsRefused) {
  // A vehicle's.
  ScenarioError e = refused(
      R"([{"id": "r", "station_id": 1, "junction": "100", "position": {"x": 14, "y": 14},
           "height": 5}])");
  EXPECT_EQ(e.path(), "/rsus/0/station_id");
  EXPECT_NE(e.reason().find("already used by /vehicles/0"), std::string::npos) << e.what();
  // Another RSU's.
  e = refused(std::string("[") + kRsu +
              R"(, {"id": "r2", "station_id": 5001, "junction": "100",
                    "position": {"x": -14, "y": -14}, "height": 5}])");
  EXPECT_EQ(e.path(), "/rsus/1/station_id");
  EXPECT_NE(e.reason().find("already used by /rsus/0"), std::string::npos) << e.what();
}

TEST(Rsus, AnIdUsedTwiceIsRefused) {
  ScenarioError e = refused(
      R"([{"id": "a", "station_id": 9, "junction": "100", "position": {"x": 14, "y": 14},
           "height": 5}])");
  EXPECT_EQ(e.path(), "/rsus/0/id");
  EXPECT_NE(e.reason().find("already used by /vehicles/0"), std::string::npos) << e.what();
  e = refused(R"([{"id": "bad id", "station_id": 9, "junction": "100",
                   "position": {"x": 14, "y": 14}, "height": 5}])");
  EXPECT_EQ(e.path(), "/rsus/0/id");
}

TEST(Rsus, MissingFieldsAreNamed) {
  const std::string fields[] = {R"("id": "r")", R"("station_id": 9)", R"("junction": "100")",
                                R"("position": {"x": 14, "y": 14})", R"("height": 5)"};
  const std::string names[] = {"id", "station_id", "junction", "position", "height"};
  for (std::size_t left_out = 0; left_out < 5; ++left_out) {
    std::string obj;
    for (std::size_t i = 0; i < 5; ++i) {
      if (i != left_out)
        obj += (obj.empty() ? "" : ", ") + fields[i];
    }
    const ScenarioError e = refused("[{" + obj + "}]");
    EXPECT_EQ(e.path(), "/rsus/0/" + names[left_out]) << e.what();
    EXPECT_NE(e.reason().find("missing"), std::string::npos) << e.what();
  }
  const ScenarioError e = refused(
      R"([{"id": "r", "station_id": 9, "junction": "100", "position": {"x": 14}, "height": 5}])");
  EXPECT_EQ(e.path(), "/rsus/0/position/y");
}

TEST(Rsus, UnknownFieldsAndBadValuesAreRefused) {
  EXPECT_EQ(refused(R"([{"id": "r", "station_id": 9, "junction": "100",
                         "position": {"x": 14, "y": 14}, "height": 5, "hight": 5}])")
                .path(),
            "/rsus/0/hight");
  EXPECT_EQ(refused(R"([{"id": "r", "station_id": 9, "junction": "100",
                         "position": {"x": 14, "y": 14}, "height": -1}])")
                .path(),
            "/rsus/0/height");
  EXPECT_EQ(refused(R"([{"id": "r", "station_id": -3, "junction": "100",
                         "position": {"x": 14, "y": 14}, "height": 5}])")
                .path(),
            "/rsus/0/station_id");
  EXPECT_EQ(refused(R"({"id": "r"})").path(), "/rsus");
}

}  // namespace
}  // namespace tb::scenario
