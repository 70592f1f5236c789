#include "its-station/apps/lcrw/lcrw_denm.hpp"

#include "its-station/apps/lcrw/lcrw_app.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

namespace tb::its::apps {
namespace {

/// Records the requests as the facilities' DEN service would receive them.
class RecordingDen : public DenService {
 public:
  std::optional<ActionId> trigger(const DenEventRequest& r) override {
    triggered.push_back(r);
    if (refuse) {
      return std::nullopt;
    }
    return ActionId{1, ++seq};
  }
  bool update(const ActionId& id, const DenEventRequest& r) override {
    updated.emplace_back(id, r);
    return true;
  }
  bool terminate(const ActionId& id) override {
    terminated.push_back(id);
    return true;
  }
  std::vector<DenEventRequest> triggered;
  std::vector<std::pair<ActionId, DenEventRequest>> updated;
  std::vector<ActionId> terminated;
  std::uint16_t seq = 0;
  bool refuse = false;
};

class LcrwDenmTest : public ::testing::Test {
 protected:
  LcrwWarning warning(WarningEvent e, Severity s, double distance) {
    LcrwWarning w;
    w.event = e;
    w.station_id = 1;
    w.other_station_id = 2;
    w.collision_case = CollisionCase::kFrontal;
    w.severity = s;
    w.distance_m = distance;
    w.updated_at = clock::WallTime{std::chrono::seconds{1'700'000'100}};
    return w;
  }
  VehicleKinematics own() {
    VehicleKinematics v;
    v.station_id = 1;
    v.x = 100;
    v.y = 50;
    v.heading_deg = 90;
    return v;
  }
  geodesy::LocalFrame frame{geodesy::Geodetic{52.0, 13.0, 40.0}};
  RecordingDen den;
};

TEST_F(LcrwDenmTest, RaisedWarningTriggersCollisionRiskDenmAtOwnPosition) {
  LcrwDenmTrigger t(den, frame);
  t.on_warning(warning(WarningEvent::kRaised, Severity::kWarning, 80), own());
  ASSERT_EQ(den.triggered.size(), 1u);
  const auto& r = den.triggered[0];
  EXPECT_EQ(r.cause_code, 97);
  EXPECT_EQ(r.sub_cause_code, 1);
  const auto p = frame.to_enu(r.event_position);
  EXPECT_NEAR(p.east, 100.0, 0.01);
  EXPECT_NEAR(p.north, 50.0, 0.01);
  // 80 m gap + 20 m for the reference points and GNSS error: 100 m is not "less than 100 m".
  EXPECT_EQ(r.relevance_distance, RelevanceDistance::kLessThan200m);
  EXPECT_EQ(r.relevance_traffic_direction, RelevanceTrafficDirection::kAllTrafficDirections);
  EXPECT_EQ(r.traffic_class, 0);  // time-critical, as the emergency electronic brake light
  EXPECT_EQ(r.detection_time, warning(WarningEvent::kRaised, Severity::kWarning, 80).updated_at);
  EXPECT_EQ(t.open_events().size(), 1u);
}

TEST_F(LcrwDenmTest, UpdatesOnlyWhenSeverityOrRelevanceChanges) {
  LcrwDenmTrigger t(den, frame);
  t.on_warning(warning(WarningEvent::kRaised, Severity::kWarning, 75), own());   // 95 m
  t.on_warning(warning(WarningEvent::kUpdated, Severity::kWarning, 65), own());  // 85 m
  EXPECT_TRUE(den.updated.empty());
  t.on_warning(warning(WarningEvent::kUpdated, Severity::kWarning, 25), own());  // 45 m
  ASSERT_EQ(den.updated.size(), 1u);
  EXPECT_EQ(den.updated[0].second.relevance_distance, RelevanceDistance::kLessThan50m);
  t.on_warning(warning(WarningEvent::kUpdated, Severity::kCritical, 20), own());
  ASSERT_EQ(den.updated.size(), 2u);
  EXPECT_EQ(den.updated[1].first, (ActionId{1, 1}));
}

// The frontal case's numbers: a 42 m gap, the other car's reference point 46 m from the own.
TEST_F(LcrwDenmTest, RelevanceAreaHoldsTheOtherVehicleNotOnlyTheGap) {
  LcrwDenmTrigger t(den, frame);
  t.on_warning(warning(WarningEvent::kRaised, Severity::kWarning, 42), own());
  ASSERT_EQ(den.triggered.size(), 1u);
  EXPECT_EQ(den.triggered[0].relevance_distance, RelevanceDistance::kLessThan100m);
}

TEST_F(LcrwDenmTest, ClearedWarningTerminatesTheEvent) {
  LcrwDenmTrigger t(den, frame);
  t.on_warning(warning(WarningEvent::kRaised, Severity::kWarning, 80), own());
  t.on_warning(warning(WarningEvent::kCleared, Severity::kWarning, 80), own());
  ASSERT_EQ(den.terminated.size(), 1u);
  EXPECT_EQ(den.terminated[0], (ActionId{1, 1}));
  EXPECT_TRUE(t.open_events().empty());
  // A clear without an open event terminates nothing.
  t.on_warning(warning(WarningEvent::kCleared, Severity::kWarning, 80), own());
  EXPECT_EQ(den.terminated.size(), 1u);
}

TEST_F(LcrwDenmTest, OnlyCriticalWaitsForCriticalSeverity) {
  LcrwDenmConfig cfg;
  cfg.only_critical = true;
  LcrwDenmTrigger t(den, frame, cfg);
  t.on_warning(warning(WarningEvent::kRaised, Severity::kWarning, 80), own());
  EXPECT_TRUE(den.triggered.empty());
  t.on_warning(warning(WarningEvent::kUpdated, Severity::kCritical, 20), own());
  ASSERT_EQ(den.triggered.size(), 1u);
}

TEST_F(LcrwDenmTest, RefusedTriggerLeavesNoOpenEvent) {
  den.refuse = true;
  LcrwDenmTrigger t(den, frame);
  t.on_warning(warning(WarningEvent::kRaised, Severity::kWarning, 80), own());
  EXPECT_TRUE(t.open_events().empty());
  t.on_warning(warning(WarningEvent::kCleared, Severity::kWarning, 80), own());
  EXPECT_TRUE(den.terminated.empty());
}

TEST_F(LcrwDenmTest, ForwardCaseConcernsUpstreamTraffic) {
  LcrwDenmTrigger t(den, frame);
  auto w = warning(WarningEvent::kRaised, Severity::kWarning, 150);
  w.collision_case = CollisionCase::kForward;
  t.on_warning(w, own());
  ASSERT_EQ(den.triggered.size(), 1u);
  EXPECT_EQ(den.triggered[0].relevance_traffic_direction,
            RelevanceTrafficDirection::kUpstreamTraffic);
  EXPECT_EQ(den.triggered[0].relevance_distance, RelevanceDistance::kLessThan200m);
}

}  // namespace
}  // namespace tb::its::apps

namespace tb::its::apps {
namespace {

TEST(LcrwApplication, ForwardsEventsAndKeepsDenmsInStep) {
  clock::ManualClock clk;
  RecordingDen den;
  const geodesy::LocalFrame frame(geodesy::Geodetic{52.0, 13.0, 40.0});
  LcrwDenmTrigger trigger(den, frame);
  std::vector<LcrwWarning> seen;
  LcrwApplication app(
      clk, LcrwConfig{}, [&](const LcrwWarning& w) { seen.push_back(w); }, &trigger);
  VehicleKinematics own;
  own.station_id = 1;
  own.speed_mps = 10;
  own.time = clk.wall_now();
  VehicleKinematics other = own;
  other.station_id = 2;
  other.y = 24;  // stopped, 19.5 m gap (default lengths 4.5 m), TTC 1.95 s
  other.speed_mps = 0;
  app.update(own, std::vector{other});
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0].event, WarningEvent::kRaised);
  ASSERT_EQ(den.triggered.size(), 1u);
  app.update(own, {});  // neighbour lost
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[1].clear_reason, ClearReason::kNeighbourLost);
  EXPECT_EQ(den.terminated.size(), 1u);
}

}  // namespace
}  // namespace tb::its::apps

namespace tb::its::apps {
namespace {

TEST(LcrwApplication, TracesEachDecisionWithTheNeighboursCam) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("hmi-lcrw-trace-" + std::to_string(::getpid()) + ".jsonl");
  clock::ManualClock clk;
  {
    trace::Tracer tracer(path.string(), "its-station");
    LcrwApplication app(clk, LcrwConfig{}, nullptr, nullptr, &tracer);
    VehicleKinematics own;
    own.station_id = 1;
    own.speed_mps = 10;
    own.time = clk.wall_now();
    VehicleKinematics near = own, far = own;
    near.station_id = 2;
    near.y = 24;  // stopped
    near.speed_mps = 0;
    far.station_id = 3;
    far.y = 500;
    far.speed_mps = 10;
    far.time = clk.wall_now() - std::chrono::milliseconds(100);
    app.update(own, std::vector{own, near, far});
    tracer.flush();
  }
  std::ifstream in(path);
  std::vector<nlohmann::json> records;
  for (std::string line; std::getline(in, line);) {
    records.push_back(nlohmann::json::parse(line));
  }
  std::filesystem::remove(path);
  ASSERT_EQ(records.size(), 2u) << "one per neighbour, none for the own station";
  EXPECT_EQ(records[0]["ev"], "its.lcrw");
  EXPECT_EQ(records[0]["station"], 1);
  EXPECT_EQ(records[0]["from"], 2);
  EXPECT_EQ(records[0]["gdt"], generation_delta_time(clk.wall_now()));
  EXPECT_EQ(records[0]["warn"], true);
  EXPECT_DOUBLE_EQ(records[0]["ttc"].get<double>(), 1.95);  // 24 m − 4.5 m at 10 m/s
  EXPECT_EQ(records[1]["from"], 3);
  EXPECT_EQ(records[1]["warn"], false);
  EXPECT_TRUE(records[1]["ttc"].is_null()) << "no contact: infinite TTC";
  EXPECT_EQ(records[1]["gdt"], generation_delta_time(clk.wall_now()) - 100);
}

TEST(ItsTime, GenerationDeltaTimeWrapsEvery65536Ms) {
  const clock::WallTime epoch{std::chrono::milliseconds{kItsEpochUnixMs}};
  EXPECT_EQ(generation_delta_time(epoch), 0);
  EXPECT_EQ(generation_delta_time(epoch + std::chrono::milliseconds{65535}), 65535);
  EXPECT_EQ(generation_delta_time(epoch + std::chrono::milliseconds{65537}), 1);
  EXPECT_EQ(generation_delta_time(epoch - std::chrono::milliseconds{1}), 65535);
}

}  // namespace
}  // namespace tb::its::apps
