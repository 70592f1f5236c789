#pragma once
/// @file Sample SPATEMs and MAPEMs shared by the unit tests, the tshark interoperability test,
/// the fuzz seed writer and the benchmarks. The large ones are built on the heap (sizeof(Spatem)
/// is about half a megabyte).

#include <memory>
#include <string>

#include "its-station/messages/spatem.hpp"

namespace tb::its::messages::samples {

/// The worked example of signal_golden_test.cpp: one intersection, two signal groups with
/// timing (green until 123.4 s past the hour at the latest 130.0 s, red until 126.4 s, likely
/// 127.0 s).
inline std::unique_ptr<Spatem> spatem_two_groups() {
  auto m = std::make_unique<Spatem>();
  m->header.stationID = 1001;
  IntersectionState& is = m->spat.intersections.emplace_back();
  is.id.id = 34;
  is.revision = 1;
  is.status = intersection_status::kFixedTimeOperation;
  is.moy = 475200;  // 11 Nov, 00:00
  is.timeStamp = 12345;
  MovementState& g1 = is.states.emplace_back();
  g1.signalGroup = 1;
  MovementEvent& e1 = g1.state_time_speed.emplace_back();
  e1.eventState = MovementPhaseState::protected_Movement_Allowed;
  e1.timing.emplace();
  e1.timing->minEndTime = 1234;
  e1.timing->maxEndTime = 1300;
  MovementState& g2 = is.states.emplace_back();
  g2.signalGroup = 2;
  MovementEvent& e2 = g2.state_time_speed.emplace_back();
  e2.eventState = MovementPhaseState::stop_And_Remain;
  e2.timing.emplace();
  e2.timing->minEndTime = 1264;
  e2.timing->likelyTime = 1270;
  e2.timing->confidence = 15;
  return m;
}

/// What the testbed's RSU sends for a four-way junction: one intersection, @p groups signal
/// groups (1..n) each with the current phase and the next one, every time filled in.
inline std::unique_ptr<Spatem> spatem_typical(unsigned groups = 8) {
  auto m = std::make_unique<Spatem>();
  m->header.stationID = 90001;
  m->spat.timeStamp = 475200 + 12 * 60 + 5;
  IntersectionState& is = m->spat.intersections.emplace_back();
  is.id.id = 1;
  is.revision = 3;
  is.status = intersection_status::kFixedTimeOperation;
  is.moy = 475200 + 12 * 60 + 5;
  is.timeStamp = 41250;
  static constexpr MovementPhaseState kCycle[] = {
      MovementPhaseState::stop_And_Remain, MovementPhaseState::pre_Movement,
      MovementPhaseState::protected_Movement_Allowed, MovementPhaseState::protected_clearance};
  for (unsigned g = 0; g < groups; ++g) {
    MovementState& s = is.states.emplace_back();
    s.signalGroup = static_cast<SignalGroupID>(g + 1);
    for (unsigned k = 0; k < 2; ++k) {
      MovementEvent& e = s.state_time_speed.emplace_back();
      e.eventState = kCycle[(g + k) % 4];
      TimeChangeDetails& t = e.timing.emplace();
      t.startTime = static_cast<TimeMark>(7000 + 100 * g + 300 * k);
      t.minEndTime = static_cast<TimeMark>(7300 + 100 * g + 300 * k);
      t.maxEndTime = static_cast<TimeMark>(7400 + 100 * g + 300 * k);
      t.likelyTime = static_cast<TimeMark>(7300 + 100 * g + 300 * k);
      t.confidence = 15;
    }
  }
  return m;
}

/// Every optional component present and every list at the bound held here (or at @p upper
/// false: every value at its lower bound, lists of one).
inline std::unique_ptr<Spatem> spatem_at_bounds(bool upper) {
  auto m = std::make_unique<Spatem>();
  m->header.stationID = upper ? 4294967295u : 0;
  SPAT& s = m->spat;
  s.timeStamp = upper ? 527040 : 0;
  s.name = char_string<63>(upper ? std::string(63, '~').c_str() : "\x01");
  const std::size_t intersections = upper ? kIntersectionStatesMax : 1;
  const std::size_t states = upper ? kMovementStatesMax : 1;
  const std::size_t events = upper ? kMovementEventsMax : 1;
  const std::size_t speeds = upper ? kAdvisorySpeedsMax : 1;
  const std::size_t assists = upper ? kManeuverAssistsMax : 1;
  const TimeMark t = upper ? kTimeMarkMax : 0;
  ConnectionManeuverAssist cma;
  cma.connectionID = upper ? 255 : 0;
  cma.queueLength = upper ? 10000 : 0;
  cma.availableStorageLength = upper ? 10000 : 0;
  cma.waitOnStop = upper;
  cma.pedBicycleDetect = !upper;
  ManeuverAssistList assist;
  for (std::size_t i = 0; i < assists; ++i)
    assist.push_back(cma);
  AdvisorySpeed a;
  a.type = upper ? AdvisorySpeedType::transit : AdvisorySpeedType::none;
  a.speed = upper ? 500 : 0;
  a.confidence = upper ? SpeedConfidenceDSRC::prec0_01ms : SpeedConfidenceDSRC::unavailable;
  a.distance = upper ? 10000 : 0;
  a.class_ = upper ? 255 : 0;
  for (std::size_t i = 0; i < intersections; ++i) {
    IntersectionState& is = s.intersections.emplace_back();
    is.name = s.name;
    is.id.region = upper ? 65535 : 0;
    is.id.id = static_cast<IntersectionID>(upper ? 65535 - i : i);
    is.revision = upper ? 127 : 0;
    is.status = upper ? 0xFFFF : 0;
    is.moy = upper ? 527040 : 0;
    is.timeStamp = upper ? 65535 : 0;
    is.enabledLanes.emplace();
    for (std::size_t l = 0; l < (upper ? 16u : 1u); ++l)
      is.enabledLanes->push_back(static_cast<LaneID>(upper ? 255 - l : l));
    is.maneuverAssistList = assist;
    for (std::size_t g = 0; g < states; ++g) {
      MovementState& ms = is.states.emplace_back();
      ms.movementName = char_string<63>(upper ? "protected left turn" : "x");
      ms.signalGroup = static_cast<SignalGroupID>(upper ? 255 - g : g);
      ms.maneuverAssistList = assist;
      for (std::size_t e = 0; e < events; ++e) {
        MovementEvent& ev = ms.state_time_speed.emplace_back();
        ev.eventState = upper ? MovementPhaseState::caution_Conflicting_Traffic
                              : MovementPhaseState::unavailable;
        ev.timing = TimeChangeDetails{t, t, t, t, upper ? 15 : 0, t};
        ev.speeds.emplace();
        for (std::size_t k = 0; k < speeds; ++k)
          ev.speeds->push_back(a);
      }
    }
  }
  return m;
}

}  // namespace tb::its::messages::samples
