#pragma once
/// @file What a station publishes over MQTT: the topic tree and the JSON payloads.
///
/// Every payload is an envelope as open ITS MQTT clients use it (type, origin, version,
/// source_uuid, timestamp in ms since the Unix epoch, message); ETSI messages carry CDD field
/// names in CDD integer units (TS 102 894-2), the LCRW warning SI values with unit suffixes.
/// The tree is documented in its-station/README.md, "Applications and MQTT".

#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "common/clock/clock.hpp"
#include "its-station/apps/den/den_port.hpp"
#include "its-station/apps/its_time.hpp"
#include "its-station/apps/lcrw/lcrw.hpp"
#include "its-station/apps/signal/rlvw.hpp"
#include "its-station/apps/signal/signal_app.hpp"

namespace tb::its::apps::mqtt {

inline constexpr const char* kEnvelopeVersion = "1.0.0";

/// Topics under <prefix>/<station id>/; a station publishes nothing outside its own prefix
/// (the broker's ACL enforces it).
class Topics {
 public:
  Topics(std::string prefix, std::uint32_t station_id);
  const std::string& root() const { return root_; }
  std::string status() const { return root_ + "/status"; }
  std::string state() const { return root_ + "/state"; }
  std::string cam_in(std::uint32_t source) const;
  std::string denm_in(std::uint32_t originating) const;
  std::string denm_out() const { return root_ + "/out/denm"; }
  std::string lcrw() const { return root_ + "/app/lcrw"; }
  /// The own lane's signal (issue 34), QoS 0, and the red light violation warning, QoS 1.
  std::string signal() const { return root_ + "/app/signal"; }
  std::string rlvw() const { return root_ + "/app/rlvw"; }

 private:
  std::string root_;
};

/// CDD GNSS fix quality as the station's positioning reports it (gpsd's mode).
enum class GnssFix { kNoFix, k2D, k3D };
std::string_view to_string(GnssFix f);

/// Position and motion in SI units; optional fields are omitted from the JSON when empty.
struct Kinematics {
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  std::optional<double> altitude_m;
  std::optional<double> heading_deg;  ///< ETSI, clockwise from north
  std::optional<double> speed_mps;
  bool reversing = false;
  std::optional<double> longitudinal_accel_mps2;
  /// CDD YawRate (positive counter-clockwise) and Curvature (positive left of the orientation);
  /// for LCRW's path prediction, not published.
  std::optional<double> yaw_rate_dps;
  std::optional<double> curvature_per_m;
  std::optional<double> length_m;
  std::optional<double> width_m;
};

struct StationState {
  std::uint32_t station_id = 0;
  int station_type = 5;  ///< CDD StationType, 5 = passengerCar
  Kinematics kinematics;
  GnssFix fix = GnssFix::kNoFix;
  std::optional<int> satellites_used;
  std::optional<double> hdop;
  clock::WallTime time{};  ///< the fix / vehicle data time
};

struct ReceivedCam {
  std::uint32_t station_id = 0;
  int station_type = 5;
  std::uint16_t generation_delta_time = 0;  ///< CDD GenerationDeltaTime
  Kinematics kinematics;
  clock::WallTime received_at{};
};

/// A DENM as the DEN service sent or received it.
struct DenmView {
  ActionId action_id;
  std::uint8_t cause_code = 0;
  std::uint8_t sub_cause_code = 0;
  double event_latitude_deg = 0.0;
  double event_longitude_deg = 0.0;
  clock::WallTime detection_time{};
  clock::WallTime reference_time{};
  std::optional<int> termination;  ///< CDD Termination: 0 isCancellation, 1 isNegation
  RelevanceDistance relevance_distance = RelevanceDistance::kLessThan100m;
  RelevanceTrafficDirection relevance_traffic_direction =
      RelevanceTrafficDirection::kAllTrafficDirections;
  std::uint32_t validity_duration_s = 600;
};

/// ms since the Unix epoch (the envelope's timestamp) and CDD TimestampIts (its_time.hpp).
using apps::timestamp_its;
using apps::unix_ms;

nlohmann::json envelope(std::string_view type, std::string_view origin, std::uint32_t source,
                        clock::WallTime now, nlohmann::json message);

nlohmann::json state_message(const StationState& s);
nlohmann::json cam_message(const ReceivedCam& c);
/// envelope("cam", "remote", source, now, cam_message(c)).dump(), byte for byte, written
/// without building the tree: a station publishes one for every neighbour five times a second,
/// and with 50 stations the tree's allocations were an eighth of its CPU (issue 21).
std::string received_cam_payload(std::uint32_t source, clock::WallTime now, const ReceivedCam& c);
/// envelope("state", "self", source, now, state_message(s)).dump(), byte for byte, written
/// without building the tree (ten times a second; the tree and its parse were 5 % of a full
/// station's CPU at 49 neighbours, docs/latency.md).
std::string state_payload(std::uint32_t source, clock::WallTime now, const StationState& s);
nlohmann::json denm_message(const DenmView& d);
nlohmann::json lcrw_message(const LcrwWarning& w);
/// The `signal` message: the own lane's light, its timing, the stop-line distance and the GLOSA
/// advice in km/h; `{"intersection_id": id, "lane": null}` when the vehicle has left the lane.
nlohmann::json signal_message(const signal::SignalStatus& s);
/// The `rlvw_warning` message (SI units, times in ms since the Unix epoch).
nlohmann::json rlvw_message(const signal::RlvwWarning& w);

}  // namespace tb::its::apps::mqtt
