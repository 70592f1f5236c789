#pragma once
// Test helpers: what a sim-server would send, and decoding what the client sent.

#include <string>
#include <vector>

#include "common/wire/sim_protocol.hpp"

namespace tb::client::testing {

// A straight two-lane road with a human car, a timeline car and a lane-following car.
inline const char* kScenarioJson = R"({
  "name": "session-test",
  "map": { "type": "straight", "lanes": 2, "lane_width": 3.5, "length": 1000 },
  "origin": { "lat": 41.1, "lon": 29.0, "alt": 60 },
  "vehicles": [
    { "id": "me", "station_id": 1001, "spawn": { "lane": 0, "s": 10 }, "driver": "human" },
    { "id": "tl", "station_id": 1002, "spawn": { "lane": 0, "s": 100 },
      "role": "emergency", "lights": ["light_bar", "siren"],
      "driver": { "type": "timeline", "steps": [ { "t": 0, "throttle": 0.25, "steer": 0.5 } ] } },
    { "id": "lf", "station_id": 1003, "spawn": { "lane": 1, "s": 100 },
      "driver": { "type": "lane_follow", "speed_profile": [ { "t": 0, "speed": 10 } ] } }
  ]
})";

inline wire::sim::Welcome welcome() {
  wire::sim::Welcome w;
  w.server_name = "fake";
  w.step_ns = 10'000'000;
  w.world_start_ns = 1'748'854'800'000'000'000;  // 2025-06-02T09:00:00Z
  const char* ids[] = {"me", "tl", "lf"};
  const char* colours[] = {"#d02020", "#2050d0", "#20a040"};
  const wire::sim::DriverKind kinds[] = {wire::sim::DriverKind::kHuman,
                                         wire::sim::DriverKind::kTimeline,
                                         wire::sim::DriverKind::kLaneFollow};
  for (std::uint16_t i = 0; i < 3; ++i) {
    wire::sim::VehicleInfo v;
    v.index = i;
    v.id = ids[i];
    v.station_id = 1001 + i;
    v.color = colours[i];
    v.driver_kind = kinds[i];
    v.length_m = 4.255f;
    v.width_m = 1.799f;
    v.height_m = 1.452f;
    v.wheelbase_m = 2.637f;
    v.track_m = 1.54f;
    v.wheel_radius_m = 0.316f;
    v.max_steer_rad = 0.628f;
    w.vehicles.push_back(v);
  }
  w.scenario_json = kScenarioJson;
  return w;
}

inline wire::sim::StateFrame frame(std::uint64_t tick) {
  wire::sim::StateFrame f;
  f.tick = tick;
  f.sim_time_ns = static_cast<std::int64_t>(tick) * 10'000'000;
  f.step_wall_ns = 1'700'000'000'000'000'000 + f.sim_time_ns;
  const double xs[] = {10.0, 100.0, 900.0};
  const double ys[] = {-1.75, -1.75, 1.75};
  for (std::uint32_t i = 0; i < 3; ++i) {
    wire::VehicleState s;
    s.station_id = 1001 + i;
    s.tick = tick;
    s.sim_time_ns = f.sim_time_ns;
    s.step_wall_ns = f.step_wall_ns;
    s.position = {xs[i] + 0.1 * static_cast<double>(tick), ys[i], 0.0};
    s.yaw = i == 2 ? 3.14159f : 0.0f;
    s.speed = 5.0f;
    f.vehicles.push_back(s);
  }
  return f;
}

// Splits the client's output into messages.
inline std::vector<wire::sim::ClientMessage> decode_all(const std::vector<std::uint8_t>& bytes) {
  std::vector<wire::sim::ClientMessage> out;
  wire::sim::FrameParser p(wire::sim::Sender::kClient);
  std::span<const std::uint8_t> rest(bytes);
  while (!rest.empty()) {
    auto st = p.parse(rest);
    if (!st || *st != wire::sim::FrameParser::Status::kFrame)
      break;
    auto m = wire::sim::decode_client(p.frame());
    if (!m)
      break;
    out.push_back(*m);
  }
  return out;
}

}  // namespace tb::client::testing
