#pragma once
/// @file The traffic lights as the scripted drivers read them (issue 34): the latest
/// SignalStates of the server, asked for one signal group at one instant of the world clock.

#include <cstdint>
#include <optional>
#include <vector>

#include "common/wire/sim_protocol.hpp"

namespace tb::client {

/// What a driver makes of a light (ISO TS 19091 MovementPhaseState, grouped by what it means
/// to a driver who approaches it).
enum class LightAspect {
  kNone,   ///< no state, a stale one, dark, unavailable or flashing: the junction's own rules
  kGo,     ///< permissive or protected movement allowed (green)
  kAmber,  ///< permissive or protected clearance: stop if it can be done comfortably
  kStop,   ///< stop-And-Remain (red) and pre-Movement (red + amber)
};

/// @p s as a driver reads it. stop-Then-Proceed (a flashing red: a stop sign) and
/// caution-Conflicting-Traffic (flashing amber) hand the junction back to its priority rules,
/// as dark and unavailable do.
LightAspect aspect(wire::sim::MovementPhaseState s);

class TrafficLights {
 public:
  /// States older than this (world time) are not trusted: sim-server sends every junction's
  /// lights on each change and at least once a second, so three seconds without one means the
  /// stream stalled, and a driver then treats the light as out of order.
  static constexpr std::int64_t kMaxAgeMs = 3000;

  /// @p world_start_ns: UTC of sim time 0 (Welcome.world_start_ns), which turns a vehicle
  /// state's sim time into the world time the signal states are dated in.
  explicit TrafficLights(std::int64_t world_start_ns = 0) : world_start_ns_(world_start_ns) {}

  /// Replaces every state with @p s (a SignalStates carries every junction's groups).
  void update(const wire::sim::SignalStates& s);
  void clear() { groups_.clear(); }

  /// World time (UTC, Unix ms) at sim time @p sim_time_ns.
  std::int64_t world_ms(std::int64_t sim_time_ns) const;

  /// The state of @p signal_group at @p intersection_id as known at sim time @p sim_time_ns;
  /// nullopt when there is none or the latest is older than kMaxAgeMs.
  std::optional<wire::sim::SignalGroupState> find(std::uint16_t intersection_id, int signal_group,
                                                  std::int64_t sim_time_ns) const;
  /// The same, as a driver reads it (kNone when unknown).
  LightAspect aspect_of(std::uint16_t intersection_id, int signal_group,
                        std::int64_t sim_time_ns) const;

 private:
  std::int64_t world_start_ns_ = 0;
  std::int64_t world_time_ms_ = 0;
  std::vector<wire::sim::SignalGroupState> groups_;  ///< ascending by (intersection, group)
};

}  // namespace tb::client
