#pragma once
/// @file The state stream of a station-host: decodes the emulator's state batches and feeds
/// each pooled station's GNSS receiver and vehicle signals.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "common/clock/runtime.hpp"
#include "common/geodesy/georeferencing.hpp"
#include "common/scenario/scenario.hpp"
#include "common/wire/vehicle_state.hpp"
#include "network-emulator/gnss/world_start.hpp"
#include "station-host/feed/state_gnss.hpp"
#include "station-host/feed/state_vehicle_data.hpp"

namespace tb::host {

/// One pooled station's inputs from the state stream.
struct StationSources {
  std::uint32_t station_id = 0;
  std::unique_ptr<StateGnssReceiver> gnss;
  std::unique_ptr<StateVehicleData> vehicle;
};

class StateFeed {
 public:
  struct Counters {
    std::uint64_t datagrams = 0;
    std::uint64_t malformed = 0;
    std::uint64_t states = 0;
    std::uint64_t other_station = 0;  ///< states of stations this host does not run
  };

  /// @p scenario and @p frame (its map's georeferencing) must outlive the feed. @p seed is the
  /// run's GNSS seed, the network-emulator's --seed: each station's error model is seeded from
  /// it and the station id as the emulator seeds its GPS agents, so a pooled station's errors
  /// are those its agent would give.
  StateFeed(const scenario::Scenario& scenario, const geodesy::Georeferencing& frame,
            clock::Runtime& runtime, std::uint64_t seed);

  /// Adds the sources of vehicle @p station_id. @throws std::invalid_argument when the
  /// scenario has no vehicle with that id or it is already added.
  StationSources& add(std::uint32_t station_id);

  /// One datagram of the state stream. @returns false (and counts it) when it is malformed.
  bool handle_datagram(std::span<const std::uint8_t> bytes);

  const Counters& counters() const { return counters_; }
  /// UTC of sim time 0 once the first batch came.
  std::optional<std::int64_t> world_start_ns() const { return world_start_.unix_ns(); }

 private:
  const scenario::Scenario& scenario_;
  const geodesy::Georeferencing& frame_;
  clock::Runtime& runtime_;
  std::uint64_t seed_;
  std::unordered_map<std::uint32_t, StationSources> stations_;
  std::vector<wire::VehicleState> batch_;
  emu::WorldStart world_start_;
  std::array<bool, wire::kDecodeErrorCount> logged_malformed_{};
  Counters counters_;
};

}  // namespace tb::host
