#pragma once
/// @file What configures one Station: built by one function from the scenario, its vehicle and
/// the command line's overrides, so that its-station and station-host configure their stations
/// alike.

#include <cstdint>
#include <optional>
#include <string>

#include "common/clock/clock.hpp"
#include "common/geodesy/wgs84.hpp"
#include "common/scenario/scenario.hpp"
#include "its-station/apps/mqtt/publisher.hpp"
#include "its-station/facilities/ca_service.hpp"
#include "its-station/facilities/reference_position.hpp"
#include "its-station/security/security_entity.hpp"

namespace tb::its::station {

/// What a command line may set over the scenario (its-station's options of the same names).
struct StationOverrides {
  int station_type = -1;       ///< -1: the vehicle's, else passengerCar
  std::string cam_policy;      ///< "etsi" | "fixed"; empty: the scenario's
  double cam_period_ms = 0.0;  ///< > 0: the fixed policy's period
  bool no_lcrw = false;        ///< do not run LCRW, whatever the scenario says
  bool no_signals = false;     ///< do not run the signal application, whatever the scenario says
  bool no_keep_alive_forwarding = false;
  double denm_repetition_ms = 100.0;
  // While the risk lasts: LCRW cancels its event when the warning clears, and its DENMs are valid
  // for 10 s (LcrwDenmConfig), which ends repetition at the latest (EN 302 637-3,
  // T_RepetitionDuration).
  double denm_repetition_duration_s = 10.0;
  std::string mqtt_prefix = "its";
  int mqtt_cam_interval_ms = 200;
};

struct StationConfig {
  std::uint32_t station_id = 0;
  facilities::CaConfig ca;
  /// Where the GNSS antenna sits on the vehicle (reference_position.hpp).
  facilities::AntennaGeometry antenna;
  bool keep_alive_forwarding = true;
  clock::Duration denm_repetition_interval = std::chrono::milliseconds{100};
  clock::Duration denm_repetition_duration = std::chrono::seconds{10};
  /// Run LCRW (the vehicle's station.lcrw, unless --no-lcrw).
  bool lcrw = true;
  /// Run the signal application: receive MAPEM/SPATEM into the LDM, match the lane, RLVW and
  /// GLOSA (the vehicle's station.signals, issue 34).
  bool signals = true;
  /// Which received packets the security entity verifies (issue 33): on demand for a pooled
  /// station, every one for a full station (security/README.md, "Verification on demand").
  security::VerifyPolicy verify_policy = security::VerifyPolicy::kEvery;
  /// Mirror the station to MQTT (the vehicle's station.mqtt): the caller gives a sink only then.
  bool mqtt = true;
  /// Where LCRW's East-North-Up frame is anchored: the map's (0, 0, 0) (its geoReference or
  /// the scenario's origin); empty without a scenario, when the first fix anchors it.
  std::optional<geodesy::Geodetic> lcrw_origin;
  /// A fix period: an LCRW onset further away is met by the next fix's evaluation.
  double fix_period_s = 0.1;
  apps::mqtt::PublisherConfig publisher;
};

/// The configuration of station @p station_id: from @p scenario and its @p vehicle where given
/// (both may be null: a station without a scenario), then @p overrides.
StationConfig make_station_config(std::uint32_t station_id, const scenario::Scenario* scenario,
                                  const scenario::Vehicle* vehicle,
                                  const StationOverrides& overrides);

}  // namespace tb::its::station
