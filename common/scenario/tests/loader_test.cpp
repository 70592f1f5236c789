#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/scenario/loader.hpp"
#include "common/wire/vehicle_state.hpp"

namespace tb::scenario {
namespace {

namespace fs = std::filesystem;

fs::path root() {
  const char* r = std::getenv("TESTBED_ROOT");
  return r != nullptr ? fs::path(r) : fs::current_path();
}
fs::path bad_dir() {
  return root() / "common/scenario/tests/bad";
}

struct BadCase {
  const char* file;
  const char* path;    // JSON pointer the error must name
  const char* reason;  // a part of the reason it must give
};

// Every bad file and the message it must produce: file, JSON path, reason.
const BadCase kBadCases[] = {
    {"unknown-key.json", "/map/lane_widht",
     "unknown field \"lane_widht\"; did you mean \"lane_width\"?"},
    {"misspelled-required.json", "/vehicles",
     "missing required field \"vehicles\" (found \"vehicels\": misspelled?)"},
    {"wrong-type.json", "/vehicles/0/station_id", "expected an integer, found a string"},
    {"out-of-range.json", "/origin/lat", "value 95 is out of range [-89, 89]"},
    {"duplicate-vehicle-id.json", "/vehicles/1/id",
     "duplicate vehicle id \"a\" (also /vehicles/0)"},
    {"duplicate-station-id.json", "/vehicles/1/station_id",
     "duplicate station_id 1 (also /vehicles/0)"},
    {"spawn-off-road.json", "/vehicles/0/spawn", "spawn point (50, 20) is off the road"},
    {"invalid-json.json", "", "invalid JSON at line 2, column"},
    {"lane-out-of-range.json", "/vehicles/0/spawn/lane", "value 2 is out of range [0, 1]"},
    {"duplicate-key.json", "/map/lanes", "duplicate key \"lanes\""},
    {"bad-map-type.json", "/map/type",
     "\"circle\" is not one of \"straight\", \"ring\", \"crossing\""},
    {"field-of-other-map-type.json", "/map/radius",
     "field \"radius\" is not allowed here: only for map type \"ring\""},
    {"timeline-out-of-order.json", "/vehicles/0/driver/steps/1", "steps must be in time order"},
    {"overlapping-spawn.json", "/vehicles/1/spawn",
     "vehicle \"b\" would spawn 2.0 m from \"a\", its footprint overlapping that one's"},
    {"antenna-off-the-car.json", "/vehicles/0/model/antenna/forward_m",
     "value 3 is out of range [-2.1275, 2.1275]"},
    {"bad-start-time.json", "/start_time", "\"2025-02-30T10:00:00Z\" is not a valid date"},
    {"start-time-not-utc.json", "/start_time", "the time must be UTC and end in Z"},
    {"no-vehicles.json", "/vehicles", "expected 1 to 5000 elements, found 0"},
    {"speed-profile-mixed-keys.json", "/vehicles/0/driver/speed_profile/1",
     "must use the same key"},
    {"station-id-too-large.json", "/vehicles/0/station_id",
     "value 4294967296 is out of range [0, 4294967295]"},
    {"cam-period-with-etsi.json", "/cam/period_ms", "only with \"policy\": \"fixed\""},
    {"negative-mass.json", "/vehicles/0/model/mass_kg", "value -5 is out of range"},
    {"bad-driver.json", "/vehicles/0/driver", "\"robot\" is not one of \"human\""},
    {"noise-on-ideal-gnss.json", "/gnss/white_noise_m", "only with \"model\": \"noisy\""},
    {"not-an-object.json", "", "expected a scenario (an object), found an array"},
    {"station-command-empty.json", "/vehicles/0/station/command",
     "expected 1 to 256 elements, found 0"},
    {"bad-security.json", "/security", "\"sign\" is not one of \"none\", \"signed\""},
    // Station kinds (issue 33): pooled stations are scripted vehicles on its-station's stack.
    {"station-kind-unknown.json", "/vehicles/0/station/kind",
     "\"shared\" is not one of \"full\", \"pooled\""},
    {"pooled-human-driver.json", "/vehicles/0/station/kind",
     "a vehicle with a \"human\" driver cannot have a \"pooled\" station (human-driven "
     "vehicles get full stations)"},
    {"pooled-no-driver.json", "/vehicles/0/station/kind",
     "a vehicle without a driver is driven by a human and cannot have a \"pooled\" station"},
    {"pooled-with-command.json", "/vehicles/0/station/kind",
     "a \"pooled\" station runs its-station's stack, not a \"command\""},
    {"pooled-without-station-id.json", "/vehicles/0/station_id",
     "missing required field \"station_id\""},
    {"pooled-lcrw-not-bool.json", "/vehicles/0/station/lcrw",
     "expected true or false, found a string"},
    // OpenDRIVE maps (issue 17, "Bad input"); the maps are in tests/maps.
    {"opendrive-missing-file.json", "/map/file", "../maps/no-such-map.xodr: no such file"},
    {"opendrive-malformed.json", "/map/file", "malformed XML"},
    // Traffic lights (issue 34): a signal group naming a signal the map lacks.
    {"opendrive-controller-unknown-signal.json", "/map/file",
     "controller-unknown-signal.xodr: controller[@id='8']/control[1]: attribute 'signalId' is "
     "'light-9': no road has that signal"},
    {"opendrive-bad-proj.json", "/map/file",
     "header/geoReference: unreadable PROJ string '+proj=no_such_projection +lat_0=48'"},
    {"opendrive-no-origin.json", "/origin",
     "the map ../maps/straight-100.xodr has no geoReference, so the origin must place"},
    {"opendrive-builtin-field.json", "/map/lanes",
     "field \"lanes\" is not allowed here: only for the built-in layouts"},
    {"opendrive-spawn-missing-road.json", "/vehicles/0/spawn/road",
     "road \"99\" does not exist in ../maps/straight-100.xodr"},
    {"opendrive-spawn-missing-lane.json", "/vehicles/0/spawn/lane",
     "road[@id='12']: lane -3 does not exist at s 30"},
    {"opendrive-spawn-not-drivable.json", "/vehicles/0/spawn/lane",
     "maps/straight-100.xodr: road[@id='12']: lane -2 (sidewalk, 2 m wide) is not drivable at s "
     "30"},
    {"opendrive-spawn-past-end.json", "/vehicles/0/spawn/s",
     "s 150 is past the end of road \"12\" (length 100.000 m)"},
    {"opendrive-spawn-lane-zero.json", "/vehicles/0/spawn/lane",
     "lane 0 is the centre line, not a lane"},
    {"opendrive-spawn-pose-off-road.json", "/vehicles/0/spawn",
     "spawn point (50, -4.5) is off the road (on no drivable lane of ../maps/straight-100.xodr)"},
    {"opendrive-spawn-builtin-form.json", "/vehicles/0/spawn/road",
     "missing required field \"road\""},
    {"unknown-role.json", "/vehicles/0/role",
     "\"ambulance\" is not one of \"default\", \"publicTransport\", \"specialTransport\", "
     "\"dangerousGoods\", \"roadWork\", \"rescue\", \"emergency\", \"safetyCar\""},
    {"dangerous-goods-without-role.json", "/vehicles/0/dangerous_goods",
     "only for a vehicle with \"role\": \"dangerousGoods\""},
    {"dangerous-goods-role-without-goods.json", "/vehicles/0/dangerous_goods",
     "missing required field \"dangerous_goods\""},
    {"unknown-dangerous-goods.json", "/vehicles/0/dangerous_goods",
     "\"petrol\" is not a CDD DangerousGoodsBasic"},
    {"unknown-light.json", "/vehicles/0/lights/1",
     "\"blue_light\" is not one of \"low_beam\", \"high_beam\""},
    {"warmup-too-long.json", "/warmup_s", "value 90 is out of range [0, 60]"},
    {"warmup-before-its-epoch.json", "/start_time",
     "sim time -3 s (the warm-up, warmup_s) falls before the ITS epoch 2004-01-01T00:00:00Z"},
    {"route-missing-road.json", "/vehicles/0/driver/route/1",
     "road \"7\" does not exist in the map"},
    {"route-disconnected.json", "/vehicles/0/driver/route/1",
     "no lane leads from road \"0\" to road \"1\""},
    {"route-to-unreachable.json", "/vehicles/0/driver/to",
     "road \"0\" lane 1 at s 300 cannot be reached from the spawn lane (road \"0\" lane -1"},
};

TEST(ScenarioLoader, EveryBadFileGetsAnErrorNamingFilePathAndReason) {
  std::size_t files_on_disk = 0;
  for (const auto& e : fs::directory_iterator(bad_dir()))
    files_on_disk += e.is_regular_file();
  EXPECT_EQ(files_on_disk, std::size(kBadCases)) << "every bad file needs an expected message";

  for (const BadCase& c : kBadCases) {
    const fs::path file = bad_dir() / c.file;
    try {
      load_file(file);
      ADD_FAILURE() << c.file << " loaded without error";
    } catch (const ScenarioError& e) {
      EXPECT_EQ(e.file(), file.string()) << c.file;
      EXPECT_EQ(e.path(), c.path) << c.file << ": " << e.what();
      EXPECT_NE(e.reason().find(c.reason), std::string::npos)
          << c.file << ": got \"" << e.reason() << "\", want \"" << c.reason << "\"";
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(file.string() + ": ", 0), 0u) << what;
    }
  }
}

TEST(ScenarioLoader, MissingFileIsAnError) {
  try {
    load_file("/no/such/scenario.json");
    FAIL();
  } catch (const ScenarioError& e) {
    EXPECT_EQ(std::string(e.what()), "/no/such/scenario.json: /: no such file");
  }
}

TEST(ScenarioLoader, ShippedScenariosLoad) {
  for (const char* name :
       {"demo", "lcrw-frontal", "lcrw-forward", "lcrw-different-lanes", "lcrw-three-vehicles",
        "lcrw-curve", "lcrw-reversing", "brake-at-start"}) {
    const Scenario s = load_file(root() / "scenarios" / (std::string(name) + ".json"));
    EXPECT_EQ(s.name, name);
    EXPECT_GE(s.vehicles.size(), 2u);
  }
}

TEST(ScenarioLoader, DefaultsAreFilledAndDocumentedValuesRead) {
  const Scenario s = parse(R"({
    "name": "defaults",
    "map": {"type": "ring", "lanes": 2},
    "origin": {"lat": 48.1, "lon": 11.5},
    "vehicles": [{"id": "v1", "station_id": 7, "spawn": {"lane": 1, "s": 3.5, "speed": 10}}]
  })",
                           "inline.json");
  EXPECT_EQ(s.map.type, MapType::kRing);
  EXPECT_EQ(s.map.oncoming_lanes, 0);  // rings default to one-way
  EXPECT_DOUBLE_EQ(s.map.radius, 150.0);
  EXPECT_DOUBLE_EQ(s.origin->altitude_m, 0.0);
  EXPECT_DOUBLE_EQ(s.rates.physics_hz, 100.0);
  EXPECT_DOUBLE_EQ(s.rates.gnss_hz, 10.0);
  EXPECT_EQ(s.cam.kind, CamPolicy::Kind::kEtsi);
  EXPECT_EQ(s.security, SecurityMode::kNone);
  EXPECT_EQ(s.channel.kind, ChannelModel::Kind::kIdeal);
  EXPECT_TRUE(s.gnss.ideal);
  EXPECT_FALSE(s.duration_s.has_value());
  EXPECT_DOUBLE_EQ(s.warmup_s, kDefaultWarmupS);
  // No start_time: the world starts when sim-server starts, on the second.
  EXPECT_FALSE(s.start_time.has_value());
  const auto now =
      std::chrono::system_clock::time_point{std::chrono::milliseconds{1'795'000'000'750}};
  EXPECT_EQ(world_start(s, now),
            std::chrono::system_clock::time_point{std::chrono::seconds{1'795'000'000}});
  ASSERT_EQ(s.vehicles.size(), 1u);
  const Vehicle& v = s.vehicles[0];
  EXPECT_EQ(v.station_type, 5);
  EXPECT_TRUE(std::holds_alternative<HumanDriver>(v.driver));
  EXPECT_DOUBLE_EQ(v.model.mass_kg, VehicleModel{}.mass_kg);
  const auto& spawn = std::get<LaneSpawn>(v.spawn.where);
  EXPECT_EQ(spawn.lane, 1);
  EXPECT_DOUBLE_EQ(spawn.s, 3.5);
  EXPECT_DOUBLE_EQ(v.spawn.speed, 10.0);
  EXPECT_TRUE(v.station_command.empty());  // its-station
}

TEST(ScenarioLoader, ReadsRoutesTrafficAndTheSeed) {
  const Scenario s = parse(R"({
    "name": "routes", "seed": 42,
    "map": {"type": "straight", "lanes": 3, "oncoming_lanes": 1, "length": 600},
    "origin": {"lat": 48.1, "lon": 11.5},
    "vehicles": [
      {"id": "a", "station_id": 1, "spawn": {"lane": 0, "s": 10},
       "driver": {"type": "lane_follow", "speed_profile": [{"t": 0, "speed": 10}],
                  "route": "random", "max_lateral_accel": 2.5}},
      {"id": "b", "station_id": 2, "spawn": {"lane": 0, "s": 40},
       "driver": {"type": "lane_follow", "speed_profile": [{"t": 0, "speed": 10}],
                  "to": {"road": 0, "lane": -1, "s": 500}, "traffic": "ignore",
                  "obey_signals": false}},
      {"id": "c", "station_id": 3, "spawn": {"lane": 1, "s": 40},
       "driver": {"type": "lane_follow", "speed_profile": [{"t": 0, "speed": 10}],
                  "route": ["0"]}},
      {"id": "d", "station_id": 4, "spawn": {"lane": 1, "s": 80},
       "driver": {"type": "lane_follow", "speed_profile": [{"t": 0, "speed": 10}],
                  "traffic": "yield"}},
      {"id": "e", "station_id": 5, "spawn": {"lane": 0, "s": 80},
       "driver": {"type": "lane_follow", "speed_profile": [{"t": 0, "speed": 10}]}}
    ]})",
                           "inline.json");
  EXPECT_EQ(s.seed, 42u);
  const auto driver = [&](std::size_t i) {
    return std::get<LaneFollowDriver>(s.vehicles[i].driver);
  };
  using Kind = DriveRoute::Kind;
  EXPECT_EQ(driver(0).route.kind, Kind::kRandom);
  EXPECT_DOUBLE_EQ(driver(0).max_lateral_accel, 2.5);
  EXPECT_TRUE(driver(0).yield_to_traffic);  // a route: traffic by default
  EXPECT_EQ(driver(1).route.kind, Kind::kTo);
  EXPECT_EQ(driver(1).route.to.road, "0");
  EXPECT_EQ(driver(1).route.to.lane, -1);
  EXPECT_DOUBLE_EQ(driver(1).route.to.s, 500.0);
  EXPECT_FALSE(driver(1).yield_to_traffic);
  EXPECT_FALSE(driver(1).obey_signals);
  EXPECT_TRUE(driver(0).obey_signals);  // lights are obeyed unless a test runs one
  EXPECT_EQ(driver(2).route.kind, Kind::kRoads);
  EXPECT_EQ(driver(2).route.roads, std::vector<std::string>{"0"});
  EXPECT_TRUE(driver(3).yield_to_traffic);
  EXPECT_EQ(driver(4).route.kind, Kind::kLane);
  EXPECT_DOUBLE_EQ(driver(4).max_lateral_accel, 3.0);
  EXPECT_FALSE(driver(4).yield_to_traffic);  // a script, as the LCRW cases need

  const auto error = [](const std::string& driver_json) {
    try {
      parse(R"({"name": "x", "map": {"type": "straight"}, "origin": {"lat": 48.1, "lon": 11.5},
                "vehicles": [{"id": "a", "station_id": 1, "spawn": {"lane": 0, "s": 10},
                "driver": {"type": "lane_follow", "speed_profile": [{"t": 0, "speed": 10}], )" +
                driver_json + "}}]}",
            "x.json");
    } catch (const ScenarioError& e) {
      return e.path() + ": " + e.reason();
    }
    return std::string("no error");
  };
  EXPECT_EQ(error(R"("route": "random", "to": {"road": "0", "lane": -1, "s": 5})"),
            "/vehicles/0/driver/to: give either \"route\" or \"to\", not both");
  EXPECT_EQ(error(R"("route": "sometimes")").substr(0, 48),
            "/vehicles/0/driver/route: \"sometimes\" is not one");
  EXPECT_EQ(error(R"("route": 5)"),
            "/vehicles/0/driver/route: a route is \"random\" or a list of road ids");
  EXPECT_EQ(error(R"("to": {"road": "0", "lane": 0, "s": 5})"),
            "/vehicles/0/driver/to/lane: lane 0 is the centre line; give a lane id (negative: "
            "right)");
  EXPECT_EQ(error(R"("to": {"road": "0", "lane": -1, "s": 5000})").substr(0, 46),
            "/vehicles/0/driver/to/s: s 5000 is outside roa");
  EXPECT_EQ(error(R"("traffic": "maybe")").substr(0, 38),
            "/vehicles/0/driver/traffic: \"maybe\" is");
  EXPECT_EQ(error(R"("obey_signals": "yes")").substr(0, 32), "/vehicles/0/driver/obey_signals:");
}

TEST(ScenarioLoader, AVehicleMayBringItsOwnStationProgram) {
  const Scenario s = parse(R"({
    "name": "byo",
    "map": {"type": "ring", "lanes": 2},
    "origin": {"lat": 48.1, "lon": 11.5},
    "vehicles": [{"id": "v1", "station_id": 7, "spawn": {"lane": 1, "s": 3.5, "speed": 10},
                  "station": {"command": ["its-gn-probe", "--interface", "{radio}"]}}]
  })",
                           "inline.json");
  EXPECT_EQ(s.vehicles[0].station_command,
            (std::vector<std::string>{"its-gn-probe", "--interface", "{radio}"}));
  try {
    parse(R"({"name": "byo", "map": {"type": "ring", "lanes": 2},
      "origin": {"lat": 48.1, "lon": 11.5},
      "vehicles": [{"id": "v1", "station_id": 7, "spawn": {"lane": 1, "s": 3.5},
                    "station": {"cmd": ["x"]}}]})",
          "inline.json");
    FAIL() << "a misspelled station field loaded";
  } catch (const ScenarioError& e) {
    EXPECT_EQ(e.path(), "/vehicles/0/station/cmd") << e.what();
  }
}

TEST(ScenarioLoader, StationKindAndItsDefaults) {
  const Scenario s = parse(R"({
    "name": "pool", "map": {"type": "straight", "lanes": 2, "length": 500},
    "origin": {"lat": 48.1, "lon": 11.5},
    "vehicles": [
      {"id": "ego", "station_id": 1, "spawn": {"lane": 0, "s": 10}},
      {"id": "p1", "station_id": 2, "spawn": {"lane": 0, "s": 40},
       "driver": {"type": "lane_follow", "speed_profile": [{"t": 0, "speed": 10}]},
       "station": {"kind": "pooled"}},
      {"id": "p2", "station_id": 3, "spawn": {"lane": 0, "s": 70},
       "driver": {"type": "lane_follow", "speed_profile": [{"t": 0, "speed": 10}]},
       "station": {"kind": "pooled", "mqtt": true, "lcrw": true, "signals": true}},
      {"id": "f1", "station_id": 4, "spawn": {"lane": 0, "s": 100},
       "driver": {"type": "lane_follow", "speed_profile": [{"t": 0, "speed": 10}]},
       "station": {"kind": "full", "mqtt": false, "lcrw": false, "signals": false}}]
  })",
                           "inline.json");
  ASSERT_EQ(s.vehicles.size(), 4u);
  // A human-driven vehicle without a "station" is full, mirrored to MQTT and runs LCRW.
  EXPECT_EQ(s.vehicles[0].station_kind, StationKind::kFull);
  EXPECT_TRUE(s.vehicles[0].station_mqtt);
  EXPECT_TRUE(s.vehicles[0].station_lcrw);
  EXPECT_TRUE(s.vehicles[0].station_signals);
  // Pooled: silent on MQTT and without LCRW unless asked.
  EXPECT_EQ(s.vehicles[1].station_kind, StationKind::kPooled);
  EXPECT_FALSE(s.vehicles[1].station_mqtt);
  EXPECT_FALSE(s.vehicles[1].station_lcrw);
  EXPECT_FALSE(s.vehicles[1].station_signals);
  EXPECT_EQ(s.vehicles[2].station_kind, StationKind::kPooled);
  EXPECT_TRUE(s.vehicles[2].station_mqtt);
  EXPECT_TRUE(s.vehicles[2].station_lcrw);
  EXPECT_TRUE(s.vehicles[2].station_signals);
  EXPECT_EQ(s.vehicles[3].station_kind, StationKind::kFull);
  EXPECT_FALSE(s.vehicles[3].station_mqtt);
  EXPECT_FALSE(s.vehicles[3].station_lcrw);
  EXPECT_FALSE(s.vehicles[3].station_signals);
}

TEST(ScenarioLoader, AStationMayComeFromAnotherPki) {
  const char* fmt = R"({
    "name": "foreign", "map": {"type": "ring", "lanes": 2}, "origin": {"lat": 48.1, "lon": 11.5},
    "security": "signed",
    "vehicles": [{"id": "v1", "station_id": 7, "spawn": {"lane": 1, "s": 3.5}},
                 {"id": "v2", "station_id": 8, "spawn": {"lane": 1, "s": 30},
                  "station": {"pki": %s}}]
  })";
  auto with = [&](const std::string& pki) {
    std::string text(std::snprintf(nullptr, 0, fmt, pki.c_str()), '\0');
    std::snprintf(text.data(), text.size() + 1, fmt, pki.c_str());
    return text;
  };
  const Scenario s = parse(with("\"elsewhere\""), "inline.json");
  EXPECT_TRUE(s.vehicles[0].station_pki.empty());  // the scenario's PKI
  EXPECT_EQ(s.vehicles[1].station_pki, "elsewhere");
  EXPECT_TRUE(s.vehicles[1].station_command.empty());  // still its-station
  for (const std::string bad : {"\"\"", "\"../x\"", "7"}) {
    try {
      parse(with(bad), "inline.json");
      FAIL() << "PKI name " << bad << " loaded";
    } catch (const ScenarioError& e) {
      EXPECT_EQ(e.path(), "/vehicles/1/station/pki") << e.what();
    }
  }
}

TEST(ScenarioLoader, SecurityTimeWindowsByItsAid) {
  const char* fmt = R"({
    "name": "windows", "map": {"type": "ring", "lanes": 2}, "origin": {"lat": 48.1, "lon": 11.5},
    "security": "signed", "security_time_windows": %s,
    "vehicles": [{"id": "v1", "station_id": 7, "spawn": {"lane": 1, "s": 3.5}}]
  })";
  auto with = [&](const std::string& windows) {
    std::string text(std::snprintf(nullptr, 0, fmt, windows.c_str()), '\0');
    std::snprintf(text.data(), text.size() + 1, fmt, windows.c_str());
    return text;
  };
  const Scenario s =
      parse(with(R"({"37": {"past_ms": 10000, "future_ms": 100}, "36": {"past_ms": 1500}})"),
            "inline.json");
  ASSERT_EQ(s.security_time_windows.size(), 2u);
  EXPECT_EQ(s.security_time_windows.at(37).past_ms, 10000);
  EXPECT_EQ(s.security_time_windows.at(37).future_ms, 100);
  EXPECT_EQ(s.security_time_windows.at(36).past_ms, 1500);
  EXPECT_FALSE(s.security_time_windows.at(36).future_ms);
  EXPECT_TRUE(parse(with("{}"), "inline.json").security_time_windows.empty());

  const std::pair<const char*, const char*> bad[] = {
      {R"({"cam": {"past_ms": 10}})", "/security_time_windows/cam"},
      {R"({"37": {"past_ms": 600001}})", "/security_time_windows/37/past_ms"},
      {R"({"37": {"future_ms": -1}})", "/security_time_windows/37/future_ms"},
      {R"({"37": {"past": 10}})", "/security_time_windows/37/past"},
      {R"({"37": {}})", "/security_time_windows/37"},
      {R"({"37": 2000})", "/security_time_windows/37"},
      {"[]", "/security_time_windows"},
  };
  for (const auto& [windows, path] : bad) {
    try {
      parse(with(windows), "inline.json");
      ADD_FAILURE() << windows << " loaded";
    } catch (const ScenarioError& e) {
      EXPECT_EQ(e.path(), path) << windows << ": " << e.what();
    }
  }
}

TEST(ScenarioLoader, ARoleWithItsLightsAndCargo) {
  const Scenario s = parse(R"({
    "name": "roles",
    "map": {"type": "straight", "lanes": 2, "length": 500},
    "origin": {"lat": 48.1, "lon": 11.5},
    "vehicles": [{"id": "amb", "station_id": 7, "spawn": {"lane": 0, "s": 10},
                  "role": "emergency", "lights": ["light_bar", "siren", "low_beam"]},
                 {"id": "tank", "station_id": 8, "spawn": {"lane": 1, "s": 10},
                  "role": "dangerousGoods", "dangerous_goods": "flammableLiquids"},
                 {"id": "cab", "station_id": 9, "spawn": {"lane": 0, "s": 40}, "role": "taxi"},
                 {"id": "car", "station_id": 10, "spawn": {"lane": 1, "s": 40}}]
  })",
                           "inline.json");
  EXPECT_EQ(s.vehicles[0].role, VehicleRole::kEmergency);
  EXPECT_EQ(s.vehicles[0].lights, wire::kLightBar | wire::kSiren | wire::kLowBeam);
  EXPECT_FALSE(s.vehicles[0].dangerous_goods);
  EXPECT_EQ(s.vehicles[1].role, VehicleRole::kDangerousGoods);
  EXPECT_EQ(s.vehicles[1].dangerous_goods, 9);
  EXPECT_EQ(s.vehicles[1].lights, 0);
  EXPECT_EQ(s.vehicles[2].role, VehicleRole::kTaxi);
  EXPECT_EQ(static_cast<int>(s.vehicles[2].role), 12);  // the CDD value
  EXPECT_EQ(s.vehicles[3].role, VehicleRole::kDefault);
}

TEST(ScenarioLoader, ReadsEveryKindOfSection) {
  const Scenario s = parse(R"({
    "name": "full",
    "map": {"type": "crossing", "lanes": 4, "oncoming_lanes": 2, "lane_width": 3.0,
            "arm_length": 250},
    "origin": {"lat": 41.0, "lon": 29.0, "alt": 12.5},
    "start_time": "2026-03-04T05:06:07.250Z",
    "duration_s": 90,
    "warmup_s": 0,
    "rates": {"physics_hz": 200, "gnss_hz": 5, "can_dynamics_hz": 50, "can_body_hz": 5},
    "gnss": {"model": "noisy", "white_noise_m": 0.5, "bias_walk_m": 0.2, "hdop": 1.1,
             "satellites": 7, "fix_loss": [{"from_s": 10, "to_s": 12.5}]},
    "cam": {"policy": "fixed", "period_ms": 100},
    "security": "signed-permissive",
    "channel": {"model": "log_distance", "tx_power_dbm": 20, "path_loss_exponent": 2.5,
                "packet_error_rate": 0.01, "delay_ms": 1, "jitter_ms": 0.5},
    "vehicles": [
      {"id": "a", "station_id": 4294967295, "station_type": 6, "color": "#00ff00",
       "model": {"mass_kg": 1500, "gear_ratios": [3.5, 2.0, 1.2], "torque_curve": [[1000, 100], [5000, 150]]},
       "spawn": {"road": 1, "lane": 3, "s": 20, "direction": "against"},
       "driver": {"type": "lane_follow", "max_accel": 1.5,
                  "speed_profile": [{"s": 0, "speed": 5}, {"s": 100, "speed": 10}]}},
      {"id": "b", "station_id": 0,
       "spawn": {"x": 100, "y": 1.0, "heading_deg": 90},
       "driver": {"type": "timeline", "steps": [{"t": 0, "throttle": 0.3, "steer": -0.2},
                                                 {"t": 5, "brake": 1, "handbrake": true}]}}
    ]
  })",
                           "inline.json");
  EXPECT_EQ(s.map.type, MapType::kCrossing);
  EXPECT_EQ(s.map.oncoming_lanes, 2);
  EXPECT_EQ(s.security, SecurityMode::kSignedPermissive);
  EXPECT_DOUBLE_EQ(*s.duration_s, 90.0);
  EXPECT_DOUBLE_EQ(s.warmup_s, 0.0);  // no warm-up: sim time starts at 0 as before
  ASSERT_TRUE(s.start_time.has_value());
  EXPECT_EQ(std::chrono::duration_cast<std::chrono::milliseconds>(s.start_time->time_since_epoch())
                .count(),
            1772600767250LL);
  // A pinned start time is the world's, whenever the run starts.
  EXPECT_EQ(world_start(s, std::chrono::system_clock::now()), *s.start_time);
  EXPECT_DOUBLE_EQ(s.rates.physics_hz, 200.0);
  EXPECT_FALSE(s.gnss.ideal);
  EXPECT_EQ(s.gnss.satellites, 7);
  ASSERT_EQ(s.gnss.fix_loss.size(), 1u);
  EXPECT_DOUBLE_EQ(s.gnss.fix_loss[0].to_s, 12.5);
  EXPECT_EQ(s.cam.kind, CamPolicy::Kind::kFixed);
  EXPECT_EQ(s.channel.kind, ChannelModel::Kind::kLogDistance);
  EXPECT_DOUBLE_EQ(s.channel.path_loss_exponent, 2.5);
  const Vehicle& a = s.vehicles[0];
  EXPECT_EQ(a.station_id, 4294967295u);
  EXPECT_EQ(a.model.gear_ratios.size(), 3u);
  EXPECT_EQ(a.model.torque_curve.size(), 2u);
  const auto& spawn = std::get<LaneSpawn>(a.spawn.where);
  EXPECT_EQ(spawn.road, 1);
  EXPECT_TRUE(spawn.against);
  const auto& follow = std::get<LaneFollowDriver>(a.driver);
  EXPECT_TRUE(follow.by_distance);
  EXPECT_DOUBLE_EQ(follow.max_accel, 1.5);
  const auto& timeline = std::get<TimelineDriver>(s.vehicles[1].driver);
  ASSERT_EQ(timeline.steps.size(), 2u);
  EXPECT_TRUE(timeline.steps[1].handbrake);
  EXPECT_DOUBLE_EQ(timeline.steps[0].steer, -0.2);
  EXPECT_EQ(s.find_station(0), &s.vehicles[1]);
  EXPECT_EQ(s.find_vehicle("a"), &s.vehicles[0]);
  EXPECT_EQ(s.find_vehicle("zz"), nullptr);
}

// The validator program exits with 2 and prints the loader's message.
// Footprints, not centre distances (issue 22): cars abreast in adjacent lanes are fine, a car
// turned across the lane next to another is not, nose to tail 0.1 m apart is fine.
TEST(ScenarioLoader, SpawnOverlapComparesFootprints) {
  const auto two = [](const std::string& a, const std::string& b) {
    return parse(R"({"name": "t", "map": {"type": "straight", "lanes": 2, "length": 500},
      "origin": {"lat": 41.1, "lon": 29.0}, "vehicles": [
      {"id": "a", "station_id": 1, "spawn": )" +
                     a + R"(}, {"id": "b", "station_id": 2, "spawn": )" + b + "}]}",
                 "t.json");
  };
  const auto expect_overlap = [](const auto& f, const std::string& a, const std::string& b) {
    try {
      f(a, b);
      ADD_FAILURE() << "accepted overlapping spawns " << a << " and " << b;
    } catch (const ScenarioError& e) {
      EXPECT_NE(std::string(e.what()).find("footprint overlapping"), std::string::npos) << e.what();
    }
  };
  EXPECT_EQ(two(R"({"lane": 0, "s": 50})", R"({"lane": 1, "s": 50})").vehicles.size(), 2u);
  EXPECT_EQ(two(R"({"x": 100, "y": 0, "heading_deg": 90})",
                R"({"x": 104.355, "y": 0, "heading_deg": 90})")
                .vehicles.size(),
            2u);
  // 2 m abreast, the second turned by 90°: its 4.255 m length reaches across the first.
  expect_overlap(two, R"({"x": 100, "y": 0, "heading_deg": 90})",
                 R"({"x": 100, "y": 2.5, "heading_deg": 0})");
  expect_overlap(two, R"({"x": 100, "y": 0, "heading_deg": 90})",
                 R"({"x": 104.0, "y": 0, "heading_deg": 90})");
}

TEST(ScenarioLoader, AntennaDefaultsToTheCentre) {
  const Scenario s = parse(R"({"name": "t", "map": {"type": "straight", "lanes": 2, "length": 500},
      "origin": {"lat": 41.1, "lon": 29.0}, "vehicles": [
      {"id": "a", "station_id": 1, "spawn": {"lane": 0, "s": 50}},
      {"id": "b", "station_id": 2, "spawn": {"lane": 0, "s": 80},
       "model": {"antenna": {"forward_m": -0.8, "left_m": 0.3}}}]})",
                           "t.json");
  EXPECT_EQ(s.vehicles[0].model.antenna.forward_m, 0.0);
  EXPECT_EQ(s.vehicles[0].model.antenna.left_m, 0.0);
  EXPECT_EQ(s.vehicles[1].model.antenna.forward_m, -0.8);
  EXPECT_EQ(s.vehicles[1].model.antenna.left_m, 0.3);
}

// scenario-check on a bad file: its exit status and what it printed.
std::pair<int, std::string> check(const std::string& file) {
  const char* bin = std::getenv("TESTBED_BIN");
  if (bin == nullptr)
    return {-1, "TESTBED_BIN is not set (ctest sets it)"};
  const std::string cmd =
      std::string(bin) + "/scenario-check " + (bad_dir() / file).string() + " 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  if (p == nullptr)
    return {-1, "popen failed"};
  std::string out;
  std::array<char, 512> buf{};
  while (std::fgets(buf.data(), buf.size(), p) != nullptr)
    out += buf.data();
  const int status = ::pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

TEST(ScenarioCheck, ExitsWithTwoAndNamesTheProblem) {
  const auto [code, out] = check("unknown-key.json");
  EXPECT_EQ(code, kExitBadScenario);
  EXPECT_NE(out.find("unknown-key.json: /map/lane_widht: unknown field"), std::string::npos) << out;
}

TEST(ScenarioCheck, ShowsEachStationsKindAndRefusesAPooledHumanDriver) {
  const fs::path good = fs::temp_directory_path() / "scenario_check_pooled.json";
  {
    std::ofstream(good) << R"({"name": "t", "map": {"type": "straight", "lanes": 2, "length": 500},
      "origin": {"lat": 41.1, "lon": 29.0},
      "vehicles": [{"id": "ego", "station_id": 1, "spawn": {"lane": 0, "s": 10}},
                   {"id": "bg", "station_id": 2, "spawn": {"lane": 0, "s": 40},
                    "driver": {"type": "lane_follow", "speed_profile": [{"t": 0, "speed": 9}]},
                    "station": {"kind": "pooled"}}]})";
  }
  const auto [ok_code, ok_out] = check(good.string());
  fs::remove(good);
  EXPECT_EQ(ok_code, 0) << ok_out;
  EXPECT_NE(ok_out.find("ego          station 1          driver human       full mqtt lcrw"),
            std::string::npos)
      << ok_out;
  EXPECT_NE(ok_out.find("bg           station 2          driver lane_follow pooled\n"),
            std::string::npos)
      << ok_out;

  const auto [code, out] = check("pooled-human-driver.json");
  EXPECT_EQ(code, kExitBadScenario);
  EXPECT_NE(out.find("pooled-human-driver.json: /vehicles/0/station/kind: a vehicle with a "
                     "\"human\" driver cannot have a \"pooled\" station"),
            std::string::npos)
      << out;
}

TEST(ScenarioCheck, RoutesTheMapCannotGiveExitTwo) {
  const std::pair<const char*, const char*> cases[] = {
      {"route-missing-road.json", "/vehicles/0/driver/route/1: road \"7\" does not exist"},
      {"route-disconnected.json", "/vehicles/0/driver/route/1: no lane leads from road \"0\""},
      {"route-to-unreachable.json", "/vehicles/0/driver/to: road \"0\" lane 1 at s 300 cannot"},
  };
  for (const auto& [file, message] : cases) {
    const auto [code, out] = check(file);
    EXPECT_EQ(code, kExitBadScenario) << file << ": " << out;
    EXPECT_NE(out.find(std::string(file) + ": " + message), std::string::npos) << out;
  }
}

}  // namespace
}  // namespace tb::scenario
