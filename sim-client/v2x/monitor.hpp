#pragma once
/// @file What the stations publish on MQTT (its-station/apps/README.md, "Topic tree"), as the
/// driver's view needs it: LCRW warnings per station, which station heard whose CAM in the
/// last second (the V2X links), and the DENM events in force. Pure logic: messages and time
/// come from outside; thread-safe, because the MQTT network thread writes while the view's
/// threads read.

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/clock/clock.hpp"

namespace tb::client::v2x {

/// One active LCRW warning (TS 101 539-3): @p station is warned about @p other.
struct LcrwAlert {
  std::uint32_t station = 0;
  std::uint32_t other = 0;
  std::optional<double> ttc_s;  ///< empty: infinite (the payload's null)
  std::string collision_case;   ///< frontal, rear_end, ...
  std::string severity;         ///< warning, critical
  double distance_m = 0.0;
};

/// @p to received a CAM from @p from within the link window.
struct V2xLink {
  std::uint32_t from = 0;
  std::uint32_t to = 0;
  bool operator==(const V2xLink&) const = default;
};

/// A DENM event in force (EN 302 637-3), keyed by its action id.
struct DenmEvent {
  std::uint32_t originator = 0;
  std::uint32_t sequence = 0;
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  int cause = 0;
  int subcause = 0;
  /// The relevance area (EN 302 637-3, 7.1.2): a circle around the event position as wide as
  /// the upper bound of the DENM's relevanceDistance class (CDD RelevanceDistance: lessThan50m
  /// → 50 m … over10km → 20 km, the GeoBroadcast area the DEN service sends it to); empty when
  /// the DENM names none.
  std::optional<double> relevance_radius_m;
  /// CDD RelevanceTrafficDirection: 0 all, 1 upstream, 2 downstream, 3 opposite; empty: none.
  std::optional<int> relevance_traffic_direction;
};

/// The radius of a CDD RelevanceDistance class (0 … 7), as the station's DEN service draws its
/// GeoBroadcast area (its-station/facilities/cdd_convert.cpp, relevance_radius_m); empty for a
/// value outside the CDD.
std::optional<double> relevance_radius_m(std::int64_t relevance_distance);

struct V2xPicture {
  std::vector<LcrwAlert> alerts;  ///< every station's, most urgent first
  std::vector<V2xLink> links;
  std::vector<DenmEvent> denms;
  /// The most urgent warning of @p station (smallest TTC), if it has one.
  const LcrwAlert* alert_for(std::uint32_t station) const;
};

struct MonitorConfig {
  std::string prefix = "its";
  /// A CAM heard this recently makes a link (the operator view's "last second").
  clock::Duration link_window = std::chrono::seconds{1};
  /// A warning that is neither updated nor cleared for this long is dropped (a station that
  /// died mid-warning), as the web HMI does (hmi/src/model.js, WARNING_TIMEOUT_MS).
  clock::Duration warning_timeout = std::chrono::seconds{2};
  /// Upper bound for a DENM's validityDuration when it gives none (CDD default 600 s).
  clock::Duration denm_default_validity = std::chrono::seconds{600};
};

class V2xMonitor {
 public:
  explicit V2xMonitor(MonitorConfig cfg = {});

  /// The MQTT topic filters that feed this monitor.
  std::vector<std::string> subscriptions() const;
  /// One MQTT message received at @p now. Returns false (and counts it) when the topic is one
  /// of ours but the payload is not what the station publishes; never throws.
  bool on_message(std::string_view topic, std::string_view payload, clock::SteadyTime now);
  /// What is in force at @p now.
  V2xPicture picture(clock::SteadyTime now) const;

  std::uint64_t accepted() const;
  std::uint64_t rejected() const;
  /// Why the last message was rejected (topic and reason), for logs.
  std::string last_error() const;

 private:
  struct Warning {
    LcrwAlert alert;
    clock::SteadyTime received{};
  };
  struct Denm {
    DenmEvent event;
    clock::SteadyTime expires{};
  };
  bool on_lcrw(std::uint32_t station, std::string_view payload, clock::SteadyTime now);
  bool on_cam(std::uint32_t station, std::uint32_t source, clock::SteadyTime now);
  bool on_denm(std::string_view payload, clock::SteadyTime now);
  bool reject(std::string_view topic, std::string why);

  MonitorConfig cfg_;
  mutable std::mutex mu_;
  std::map<std::pair<std::uint32_t, std::uint32_t>, Warning> warnings_;  ///< (station, other)
  std::map<std::pair<std::uint32_t, std::uint32_t>, clock::SteadyTime> heard_;  ///< (from, to)
  std::map<std::pair<std::uint32_t, std::uint32_t>, Denm> denms_;  ///< (originator, sequence)
  std::uint64_t accepted_ = 0;
  std::uint64_t rejected_ = 0;
  std::string last_error_;
};

}  // namespace tb::client::v2x
