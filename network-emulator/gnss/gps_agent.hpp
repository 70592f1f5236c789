#pragma once
/// @file GpsAgent: one station's GNSS receiver, turning vehicle states into NMEA epochs.
///
/// Epochs fall on whole multiples of the period in sim time (a real receiver's epochs are
/// aligned to whole 100 ms of GPS time at 10 Hz): the first state at or after an epoch
/// boundary makes an epoch that describes that state, stamped with its sim time (scenario
/// start_time + sim_time_ns). So a fix names the physics step it came from, and no time is
/// lost waiting for a free-running timer. No sockets: the caller sends the datagram.
///
/// AgentConfig::epoch_offset moves the grid: epochs at k × period + offset. The emulator's
/// agents keep 0; station-host gives each pooled station its own offset so that its stations'
/// fixes, and so their CA checks, are not all at one instant (station-host/README.md).

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "common/geodesy/georeferencing.hpp"
#include "common/scenario/scenario.hpp"
#include "common/wire/vehicle_state.hpp"
#include "network-emulator/gnss/error_model.hpp"
#include "network-emulator/gnss/nmea.hpp"

namespace tb::emu::gnss {

struct AgentConfig {
  std::uint32_t station_id = 0;
  double rate_hz = 10.0;
  std::chrono::system_clock::time_point start_time;  ///< UTC of sim time 0
  scenario::GnssErrors errors;
  std::uint64_t seed = 1;
  /// Where the antenna sits on the vehicle: the fix is the antenna's position, as a receiver's.
  scenario::GnssAntenna antenna;
  /// Where the epochs fall within a period (0 ≤ offset < period): k × period + offset.
  std::chrono::nanoseconds epoch_offset{0};
  /// false: an epoch makes its fix (last_fix()) but no NMEA text, for a receiver that reads the
  /// fix in-process (station-host: formatting sentences nobody read was 6 % of its CPU).
  bool write_sentences = true;
};

class GpsAgent {
 public:
  /// @p frame (the scenario map's georeferencing: the ENU frame at the scenario's origin, or
  /// the map's geoReference) must outlive the agent. @throws std::invalid_argument for a
  /// rate ≤ 0.
  GpsAgent(const AgentConfig& config, const geodesy::Georeferencing& frame);

  /// Feeds the station's latest state. Returns one epoch's sentences (valid until the next
  /// call; empty without write_sentences) when an epoch falls due, otherwise nothing.
  std::optional<std::string_view> on_state(const wire::VehicleState& state);

  /// UTC of sim time 0 from now on: the world's start time that sim-server fixed (docs/time.md).
  void set_start_time(std::chrono::system_clock::time_point t) { config_.start_time = t; }
  /// The fix of the last epoch (for tests and traces).
  const Fix& last_fix() const { return fix_; }
  std::uint64_t epochs() const { return epochs_; }
  std::int64_t period_ns() const { return period_ns_; }

 private:
  AgentConfig config_;
  const geodesy::Georeferencing& frame_;
  ErrorModel errors_;
  std::int64_t period_ns_;
  std::optional<std::int64_t> next_epoch_ns_;
  std::optional<double> course_deg_;
  Fix fix_;
  std::vector<SatelliteView> sky_;
  std::string out_;
  std::uint64_t epochs_ = 0;
};

}  // namespace tb::emu::gnss
