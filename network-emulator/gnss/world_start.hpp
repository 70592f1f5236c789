#pragma once
/// @file Which UTC instant sim time 0 is for the GPS agents (docs/time.md, "one world clock"):
/// sim-server's start time when the states carry it, else the scenario's pinned start_time,
/// else the host's clock minus the first state's sim time. The network-emulator's agents and a
/// station-host's pooled receivers follow the same rule, so that a pooled station's fix time is
/// the one a full station's agent writes into its NMEA.

#include <cstdint>
#include <optional>
#include <string>

#include "common/clock/clock.hpp"
#include "common/wire/vehicle_state.hpp"

namespace tb::emu {

class WorldStart {
 public:
  explicit WorldStart(std::optional<clock::WallTime> scenario_start)
      : scenario_start_(scenario_start) {}

  /// After a batch of states whose header says @p from_states (wire::kUnknownWorldStart: it
  /// says none) and whose first state is @p first, received at host time @p now: the new start
  /// when it is the first or differs from the one before (a restarted sim-server), else empty.
  /// Says the start and where it came from in the log, once and at every change.
  std::optional<clock::WallTime> update(std::int64_t from_states, const wire::VehicleState& first,
                                        clock::WallTime now);

  std::optional<std::int64_t> unix_ns() const { return unix_ns_; }
  /// Where the current start came from, for the log and tests.
  const std::string& source() const { return source_; }

 private:
  std::optional<clock::WallTime> scenario_start_;
  std::optional<std::int64_t> unix_ns_;
  std::string source_;
};

}  // namespace tb::emu
