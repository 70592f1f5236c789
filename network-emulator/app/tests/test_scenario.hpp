#pragma once
// A two-station scenario for the emulator's tests.

#include <string>

namespace tb::emu::testing {

inline const std::string kTwoStations = R"({
  "name": "emu-test",
  "map": {"type": "straight"},
  "origin": {"lat": 48.1, "lon": 11.5, "alt": 500},
  "start_time": "2025-01-01T12:00:00Z",
  "vehicles": [
    {"id": "a", "station_id": 1001, "spawn": {"lane": 0, "s": 10}},
    {"id": "b", "station_id": 1002, "spawn": {"lane": 0, "s": 50}}
  ]
})";

}  // namespace tb::emu::testing
