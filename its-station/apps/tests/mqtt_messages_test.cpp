#include <gtest/gtest.h>

#include <limits>

#include "common/mqtt/outbox.hpp"
#include "its-station/apps/mqtt/messages.hpp"

namespace tb::its::apps::mqtt {
namespace {

using nlohmann::json;
using std::chrono::milliseconds;

clock::WallTime at_ms(std::int64_t ms) {
  return clock::WallTime{milliseconds{ms}};
}

TEST(Topics, EverythingUnderTheStationPrefix) {
  const Topics t("its", 1001);
  EXPECT_EQ(t.root(), "its/1001");
  EXPECT_EQ(t.status(), "its/1001/status");
  EXPECT_EQ(t.state(), "its/1001/state");
  EXPECT_EQ(t.cam_in(7), "its/1001/in/cam/7");
  EXPECT_EQ(t.denm_in(8), "its/1001/in/denm/8");
  EXPECT_EQ(t.denm_out(), "its/1001/out/denm");
  EXPECT_EQ(t.lcrw(), "its/1001/app/lcrw");
  EXPECT_EQ(t.signal(), "its/1001/app/signal");
  EXPECT_EQ(t.rlvw(), "its/1001/app/rlvw");
}

TEST(Envelope, CarriesTypeOriginVersionSourceAndMilliseconds) {
  const json e = envelope("cam", "remote", 42, at_ms(1'700'000'000'123), json{{"a", 1}});
  EXPECT_EQ(e["type"], "cam");
  EXPECT_EQ(e["origin"], "remote");
  EXPECT_EQ(e["version"], kEnvelopeVersion);
  EXPECT_EQ(e["source_uuid"], "station-42");
  EXPECT_EQ(e["timestamp"], 1'700'000'000'123);
  EXPECT_EQ(e["message"]["a"], 1);
}

TEST(TimestampIts, CountsFrom2004) {
  EXPECT_EQ(timestamp_its(at_ms(1'072'915'200'000)), 0);
  EXPECT_EQ(timestamp_its(at_ms(1'072'915'201'500)), 1500);
}

TEST(CamMessage, CddUnitsAndNames) {
  ReceivedCam c;
  c.station_id = 7;
  c.generation_delta_time = 65000;
  c.kinematics.latitude_deg = 52.5;
  c.kinematics.longitude_deg = -13.25;
  c.kinematics.altitude_m = 40.5;
  c.kinematics.heading_deg = 359.97;
  c.kinematics.speed_mps = 13.891;
  c.kinematics.longitudinal_accel_mps2 = -1.26;
  c.kinematics.length_m = 4.255;
  c.kinematics.width_m = 1.799;
  c.received_at = at_ms(5000);
  const json m = cam_message(c);
  EXPECT_EQ(m["station_id"], 7);
  EXPECT_EQ(m["generation_delta_time"], 65000);
  EXPECT_EQ(m["basic_container"]["station_type"], 5);
  EXPECT_EQ(m["basic_container"]["reference_position"]["latitude"], 525000000);
  EXPECT_EQ(m["basic_container"]["reference_position"]["longitude"], -132500000);
  EXPECT_EQ(m["basic_container"]["reference_position"]["altitude"], 4050);
  const json& hf = m["high_frequency_container"];
  EXPECT_EQ(hf["heading"], 0) << "359.97° rounds to 360.0°, which is north";
  EXPECT_EQ(hf["speed"], 1389);
  EXPECT_EQ(hf["drive_direction"], 0);
  EXPECT_EQ(hf["longitudinal_acceleration"], -13);
  EXPECT_EQ(hf["vehicle_length"], 43);
  EXPECT_EQ(hf["vehicle_width"], 18);
  EXPECT_EQ(m["received_at"], 5000);
}

TEST(CamMessage, SaturatesOutOfRangeAndOmitsUnavailable) {
  ReceivedCam c;
  c.kinematics.speed_mps = 500.0;
  c.kinematics.longitudinal_accel_mps2 = -30.0;
  c.kinematics.reversing = true;
  const json hf = cam_message(c)["high_frequency_container"];
  EXPECT_EQ(hf["speed"], 16382);
  EXPECT_EQ(hf["longitudinal_acceleration"], -160);
  EXPECT_EQ(hf["drive_direction"], 1);
  EXPECT_FALSE(hf.contains("heading"));
  EXPECT_FALSE(hf.contains("vehicle_length"));
  EXPECT_FALSE(cam_message(c)["basic_container"]["reference_position"].contains("altitude"));
}

TEST(CamMessage, WrittenPayloadEqualsTheEnvelopesDump) {
  // Every combination of the optional members, negative values and a reversing car: the
  // publisher's writer must give the tree's text exactly (members sorted as nlohmann keeps them).
  for (unsigned mask = 0; mask < 64; ++mask) {
    ReceivedCam c;
    c.station_id = 4'294'967'295u;
    c.station_type = 10;
    c.generation_delta_time = static_cast<std::uint16_t>(mask * 1000);
    c.kinematics.latitude_deg = -33.8688;
    c.kinematics.longitude_deg = 151.2093;
    c.kinematics.reversing = (mask & 1u) != 0;
    if (mask & 2u)
      c.kinematics.altitude_m = -12.345;
    if (mask & 4u)
      c.kinematics.heading_deg = 271.25;
    if (mask & 8u)
      c.kinematics.speed_mps = 27.78;
    if (mask & 16u)
      c.kinematics.longitudinal_accel_mps2 = -4.5;
    if (mask & 32u) {
      c.kinematics.length_m = 4.5;
      c.kinematics.width_m = 1.9;
    }
    c.received_at = at_ms(1'700'000'000'456);
    const auto now = at_ms(1'700'000'000'789);
    EXPECT_EQ(received_cam_payload(1001, now, c),
              envelope("cam", "remote", 1001, now, cam_message(c)).dump())
        << "optional members " << mask;
  }
}

TEST(StateMessage, WrittenPayloadEqualsTheEnvelopesDump) {
  // Every combination of the optional members, whole and fractional HDOP (nlohmann writes 1.0
  // where fmt writes 1), each fix kind: the writer must give the tree's text exactly.
  const double hdops[] = {0.9, 1.0, 12.25, 99.99};
  for (unsigned mask = 0; mask < 256; ++mask) {
    StationState s;
    s.station_id = 4'294'967'295u - mask;
    s.station_type = static_cast<int>(mask % 16);
    s.fix = static_cast<GnssFix>(mask % 3);
    s.kinematics.latitude_deg = -33.8688;
    s.kinematics.longitude_deg = 151.2093;
    s.kinematics.reversing = (mask & 1u) != 0;
    if (mask & 2u)
      s.kinematics.altitude_m = 512.3;
    if (mask & 4u)
      s.kinematics.heading_deg = 0.05;
    if (mask & 8u) {
      s.kinematics.speed_mps = 13.9;
      s.kinematics.longitudinal_accel_mps2 = 2.25;
    }
    if (mask & 16u) {
      s.kinematics.length_m = 12.0;
      s.kinematics.width_m = 2.55;
    }
    if (mask & 32u)
      s.satellites_used = static_cast<int>(mask % 13);
    if (mask & 64u)
      s.hdop = hdops[mask % 4];
    s.time = at_ms(1'700'000'000'123 + mask);
    const auto now = at_ms(1'700'000'000'789);
    EXPECT_EQ(state_payload(77, now, s),
              envelope("state", "self", 77, now, state_message(s)).dump())
        << "case " << mask;
  }
}

TEST(StateMessage, IncludesGnssFix) {
  StationState s;
  s.station_id = 3;
  s.fix = GnssFix::k3D;
  s.satellites_used = 9;
  s.hdop = 0.9;
  s.time = at_ms(1'072'915'210'000);
  const json m = state_message(s);
  EXPECT_EQ(m["gnss"]["fix"], "3d");
  EXPECT_EQ(m["gnss"]["satellites_used"], 9);
  EXPECT_DOUBLE_EQ(m["gnss"]["hdop"].get<double>(), 0.9);
  EXPECT_EQ(m["timestamp_its"], 10000);
}

TEST(DenmMessage, CollisionRiskFields) {
  DenmView d;
  d.action_id = {11, 3};
  d.cause_code = kCauseCollisionRisk;
  d.sub_cause_code = kSubCauseLongitudinalCollisionRisk;
  d.event_latitude_deg = 48.1;
  d.event_longitude_deg = 11.5;
  d.detection_time = at_ms(1'072'915'200'100);
  d.reference_time = at_ms(1'072'915'200'200);
  d.termination = 0;
  d.relevance_distance = RelevanceDistance::kLessThan200m;
  d.relevance_traffic_direction = RelevanceTrafficDirection::kUpstreamTraffic;
  d.validity_duration_s = 10;
  const json m = denm_message(d);
  EXPECT_EQ(m["station_id"], 11);
  const json& mc = m["management_container"];
  EXPECT_EQ(mc["action_id"]["originating_station_id"], 11);
  EXPECT_EQ(mc["action_id"]["sequence_number"], 3);
  EXPECT_EQ(mc["detection_time"], 100);
  EXPECT_EQ(mc["reference_time"], 200);
  EXPECT_EQ(mc["termination"], 0);
  EXPECT_EQ(mc["event_position"]["latitude"], 481000000);
  EXPECT_EQ(mc["relevance_distance"], 2);
  EXPECT_EQ(mc["relevance_traffic_direction"], 1);
  EXPECT_EQ(mc["validity_duration"], 10);
  EXPECT_EQ(m["situation_container"]["event_type"]["cause"], 97);
  EXPECT_EQ(m["situation_container"]["event_type"]["subcause"], 1);
  d.termination.reset();
  EXPECT_FALSE(denm_message(d)["management_container"].contains("termination"));
}

TEST(LcrwMessage, WarningFieldsAndInfiniteTtcAsNull) {
  LcrwWarning w;
  w.station_id = 1;
  w.other_station_id = 2;
  w.event = WarningEvent::kCleared;
  w.collision_case = CollisionCase::kFrontal;
  w.severity = Severity::kCritical;
  w.clear_reason = ClearReason::kMovingApart;
  w.ttc_s = std::numeric_limits<double>::infinity();
  w.distance_m = 12.5;
  w.relative_speed_mps = -3.0;
  w.raised_at = at_ms(1000);
  w.updated_at = at_ms(2000);
  const json m = lcrw_message(w);
  EXPECT_EQ(m["station_id"], 1);
  EXPECT_EQ(m["other_station_id"], 2);
  EXPECT_EQ(m["event"], "cleared");
  EXPECT_EQ(m["collision_case"], "frontal");
  EXPECT_EQ(m["severity"], "critical");
  EXPECT_EQ(m["clear_reason"], "moving_apart");
  EXPECT_TRUE(m["ttc_s"].is_null());
  EXPECT_DOUBLE_EQ(m["distance_m"].get<double>(), 12.5);
  EXPECT_DOUBLE_EQ(m["relative_speed_mps"].get<double>(), -3.0);
  EXPECT_EQ(m["raised_at"], 1000);
  EXPECT_EQ(m["updated_at"], 2000);
  // Serialisable: JSON has no infinity.
  EXPECT_NO_THROW((void)m.dump());
}

TEST(SignalMessage, TheContractsFieldsWithDsrcNames) {
  signal::SignalStatus s;
  s.station_id = 1001;
  s.intersection_id = 12;
  s.on_lane = true;
  s.lane_id = 2;
  s.signal_group = 3;
  s.state = signal::MovementPhaseState::kPreMovement;
  s.time_to_change_s = 1.5;
  s.distance_to_stop_line_m = 42.25;
  s.advice = signal::SpeedAdvice{25.0 / 3.6, 50.0 / 3.6, {}};
  s.rlvw = false;
  const json m = signal_message(s);
  EXPECT_EQ(m["intersection_id"], 12);
  EXPECT_EQ(m["signal_group"], 3);
  EXPECT_EQ(m["lane_id"], 2);
  EXPECT_EQ(m["state"], "red_amber");
  EXPECT_EQ(m["event_state"], "pre-Movement");
  EXPECT_DOUBLE_EQ(m["time_to_change_s"].get<double>(), 1.5);
  EXPECT_TRUE(m["likely_time_to_change_s"].is_null());
  EXPECT_DOUBLE_EQ(m["distance_to_stop_line_m"].get<double>(), 42.25);
  EXPECT_NEAR(m["advice"]["min_speed_kmh"].get<double>(), 25.0, 1e-9);
  EXPECT_NEAR(m["advice"]["max_speed_kmh"].get<double>(), 50.0, 1e-9);
  EXPECT_EQ(m["rlvw"], false);
  EXPECT_FALSE(m.contains("lane")) << "only the message on leaving carries lane: null";
  s.advice.reset();
  EXPECT_TRUE(signal_message(s)["advice"].is_null());

  // Each state's light and DSRC name.
  using signal::MovementPhaseState;
  const std::pair<MovementPhaseState, std::pair<const char*, const char*>> names[] = {
      {MovementPhaseState::kUnavailable, {"unavailable", "unavailable"}},
      {MovementPhaseState::kDark, {"dark", "dark"}},
      {MovementPhaseState::kStopThenProceed, {"red", "stop-Then-Proceed"}},
      {MovementPhaseState::kStopAndRemain, {"red", "stop-And-Remain"}},
      {MovementPhaseState::kPreMovement, {"red_amber", "pre-Movement"}},
      {MovementPhaseState::kPermissiveMovementAllowed, {"green", "permissive-Movement-Allowed"}},
      {MovementPhaseState::kProtectedMovementAllowed, {"green", "protected-Movement-Allowed"}},
      {MovementPhaseState::kPermissiveClearance, {"amber", "permissive-clearance"}},
      {MovementPhaseState::kProtectedClearance, {"amber", "protected-clearance"}},
      {MovementPhaseState::kCautionConflictingTraffic, {"amber", "caution-Conflicting-Traffic"}},
  };
  for (const auto& [state, n] : names) {
    s.state = state;
    EXPECT_EQ(signal_message(s)["state"], n.first) << static_cast<int>(state);
    EXPECT_EQ(signal_message(s)["event_state"], n.second) << static_cast<int>(state);
  }
}

TEST(SignalMessage, LeavingTheLane) {
  signal::SignalStatus s;
  s.intersection_id = 12;
  s.on_lane = false;
  const json m = signal_message(s);
  EXPECT_EQ(m, (json{{"intersection_id", 12}, {"lane", nullptr}}));
}

TEST(RlvwMessage, TheContractsFields) {
  signal::RlvwWarning w;
  w.event = signal::RlvwEvent::kCleared;
  w.station_id = 1001;
  w.intersection_id = 12;
  w.signal_group = 3;
  w.lane_id = 2;
  w.clear_reason = signal::RlvwClearReason::kLeftLane;
  w.distance_to_stop_line_m = 30.5;
  w.speed_mps = 16.5;
  w.stopping_distance_m = 61.9;
  w.raised_at = at_ms(1000);
  w.updated_at = at_ms(2500);
  json m = rlvw_message(w);
  EXPECT_EQ(m["station_id"], 1001);
  EXPECT_EQ(m["intersection_id"], 12);
  EXPECT_EQ(m["signal_group"], 3);
  EXPECT_EQ(m["lane_id"], 2);
  EXPECT_EQ(m["event"], "cleared");
  EXPECT_EQ(m["severity"], "warning");
  EXPECT_EQ(m["clear_reason"], "left_lane");
  EXPECT_DOUBLE_EQ(m["distance_to_stop_line_m"].get<double>(), 30.5);
  EXPECT_DOUBLE_EQ(m["speed_mps"].get<double>(), 16.5);
  EXPECT_TRUE(m["time_to_red_s"].is_null());
  EXPECT_DOUBLE_EQ(m["stopping_distance_m"].get<double>(), 61.9);
  EXPECT_EQ(m["raised_at"], 1000);
  EXPECT_EQ(m["updated_at"], 2500);
  w.time_to_red_s = 0.0;
  w.event = signal::RlvwEvent::kRaised;
  w.clear_reason = signal::RlvwClearReason::kNone;
  m = rlvw_message(w);
  EXPECT_EQ(m["time_to_red_s"], 0.0);
  EXPECT_EQ(m["event"], "raised");
  EXPECT_EQ(m["clear_reason"], "none");
  for (const auto& [r, name] : {std::pair{signal::RlvwClearReason::kStopped, "stopped"},
                                {signal::RlvwClearReason::kPassed, "passed"},
                                {signal::RlvwClearReason::kGreen, "green"},
                                {signal::RlvwClearReason::kStale, "stale"}}) {
    w.clear_reason = r;
    EXPECT_EQ(rlvw_message(w)["clear_reason"], name);
  }
}

TEST(Outbox, FifoAndDropsOldestWhenFull) {
  tb::mqtt::Outbox box(3);
  for (int i = 0; i < 5; ++i) {
    const bool dropped = box.push(tb::mqtt::OutMessage{"t", std::to_string(i)});
    EXPECT_EQ(dropped, i >= 3);
  }
  EXPECT_EQ(box.size(), 3u);
  EXPECT_EQ(box.dropped(), 2u);
  EXPECT_EQ(box.pop()->payload, "2");
  box.push_front(tb::mqtt::OutMessage{"t", "back"});
  EXPECT_EQ(box.pop()->payload, "back");
  EXPECT_EQ(box.pop()->payload, "3");
  EXPECT_EQ(box.pop()->payload, "4");
  EXPECT_FALSE(box.pop().has_value());
}

}  // namespace
}  // namespace tb::its::apps::mqtt
