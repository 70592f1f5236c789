#pragma once
/// @file A pooled station's GNSS receiver: the emulator's GPS agent fed from the state stream,
/// its epochs turned into fixes without NMEA or gpsd.
///
/// A full station hears the agent through NMEA and gpsd; a pooled one gets the agent's epoch
/// as the report gpsd would have made of it (gpsd_report_of) and hands that to the same
/// FixAssembler, so both kinds of station see the same fix: time, position, altitude,
/// course, speed and every confidence.

#include <cstdint>

#include "common/clock/runtime.hpp"
#include "common/geodesy/georeferencing.hpp"
#include "common/wire/vehicle_state.hpp"
#include "its-station/facilities/gpsd_report.hpp"
#include "its-station/facilities/position.hpp"
#include "network-emulator/gnss/gps_agent.hpp"

namespace tb::host {

/// gpsd 3.22's vertical UERE for receivers without DGPS (gpsd.h V_UERE_NO_DGPS): epv = VDOP ×
/// this, checked against a real gpsd in emu_gnss_gpsd_it.
inline constexpr double kGpsdVerticalUereM = 23.0;

/// What gpsd reports (TPV with SKY's DOPs and the GST) after reading the NMEA epoch of @p fix:
/// a 3-D fix with four or more satellites used, 2-D with fewer, no fix when the agent has none.
its::facilities::GpsdReport gpsd_report_of(const emu::gnss::Fix& fix);

/// PositionProvider of one pooled station. Fixes come at the scenario's GNSS rate, on the
/// states' sim-time epochs as the GPS agent makes them; a fix that gets no newer epoch within
/// stale_after counts as lost, as GpsdPositionProvider does with a silent gpsd.
class StateGnssReceiver final : public its::facilities::PositionProvider {
 public:
  /// @p frame must outlive the receiver. @throws std::invalid_argument for a rate ≤ 0.
  StateGnssReceiver(const emu::gnss::AgentConfig& config, const geodesy::Georeferencing& frame,
                    clock::Runtime& runtime, clock::Duration stale_after = std::chrono::seconds{2});
  ~StateGnssReceiver() override;
  StateGnssReceiver(const StateGnssReceiver&) = delete;
  StateGnssReceiver& operator=(const StateGnssReceiver&) = delete;

  /// Feeds the vehicle's newest state; publishes a fix (or a loss) when an epoch falls due.
  void on_state(const wire::VehicleState& state);
  /// UTC of sim time 0 (docs/time.md): the world's start time that came with the states.
  void set_start_time(clock::WallTime t) { agent_.set_start_time(t); }

  std::uint64_t epochs() const { return agent_.epochs(); }

 private:
  void rearm_stale_timer();

  emu::gnss::GpsAgent agent_;
  clock::Runtime& runtime_;
  clock::Duration stale_after_;
  its::facilities::FixAssembler assembler_;
  clock::TimerId stale_timer_ = 0;
};

}  // namespace tb::host
