#pragma once
/// @file What the stations publish on MQTT (its-station/apps/README.md, "Topic tree"), as the
/// driver's view needs it: LCRW warnings per station, which station heard whose CAM in the
/// last second (the V2X links), the DENM events in force, and (issue 34) the signal of each
/// station's own lane and its red-light violation warning (RLVW). Pure logic: messages and time
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

/// A signal head's state as the `its/<id>/app/signal` message names it: the DSRC
/// MovementPhaseState (ISO TS 19091) folded into what a driver sees.
enum class SignalLight : std::uint8_t { kUnavailable, kDark, kRed, kRedAmber, kAmber, kGreen };
/// "unavailable", "dark", "red", "red_amber", "amber", "green" (the MQTT contract's names).
std::string_view to_string(SignalLight l);
std::optional<SignalLight> parse_signal_light(std::string_view text);

/// GLOSA: a speed range that reaches the stop line on green (km/h).
struct SpeedAdvice {
  double min_kmh = 0.0;
  double max_kmh = 0.0;
};

/// The signal for a station's own ingress lane (`its/<id>/app/signal`, issue 34).
struct LaneSignal {
  std::uint32_t station = 0;
  std::uint32_t intersection_id = 0;  ///< DSRC IntersectionReferenceID.id
  std::uint32_t signal_group = 0;     ///< DSRC SignalGroupID
  std::uint32_t lane_id = 0;          ///< DSRC LaneID
  SignalLight light = SignalLight::kUnavailable;
  std::string event_state;  ///< the DSRC MovementPhaseState name, e.g. "stop-And-Remain"
  /// minEndTime − now and likelyTime − now; in a picture, aged by the time since receipt.
  std::optional<double> time_to_change_s;
  std::optional<double> likely_time_to_change_s;
  double distance_to_stop_line_m = 0.0;
  std::optional<SpeedAdvice> advice;
  bool rlvw = false;  ///< the station's RLVW is active (the message's own flag)
};

/// An active red-light violation warning (`its/<id>/app/rlvw`, TS 103 301's RLVW use case).
struct RlvwAlert {
  std::uint32_t station = 0;
  std::uint32_t intersection_id = 0;
  std::uint32_t signal_group = 0;
  std::uint32_t lane_id = 0;
  double distance_to_stop_line_m = 0.0;
  double speed_mps = 0.0;
  /// Empty: the payload's null (red already, or unknown); in a picture, aged since receipt.
  std::optional<double> time_to_red_s;
  double stopping_distance_m = 0.0;
};

struct V2xPicture {
  std::vector<LcrwAlert> alerts;  ///< every station's, most urgent first
  std::vector<V2xLink> links;
  std::vector<DenmEvent> denms;
  std::vector<LaneSignal> signals;  ///< fresh ones only, by station
  std::vector<RlvwAlert> rlvw;      ///< active ones, by station
  /// The most urgent warning of @p station (smallest TTC), if it has one.
  const LcrwAlert* alert_for(std::uint32_t station) const;
  /// The own lane's signal of @p station, while fresh.
  const LaneSignal* signal_for(std::uint32_t station) const;
  /// The red-light warning of @p station, while active.
  const RlvwAlert* rlvw_for(std::uint32_t station) const;
};

struct MonitorConfig {
  std::string prefix = "its";
  /// A CAM heard this recently makes a link (the operator view's "last second").
  clock::Duration link_window = std::chrono::seconds{1};
  /// A warning that is neither updated nor cleared for this long is dropped (a station that
  /// died mid-warning), as the web HMI does (hmi/src/model.js, WARNING_TIMEOUT_MS).
  clock::Duration warning_timeout = std::chrono::seconds{2};
  /// A warning stays on screen at least this long after it was raised, even when its clear
  /// comes sooner: LCRW can raise and clear within 30 ms as a gap closes and opens, shorter
  /// than a frame of a slow view and than a driver's glance; the banner must not flicker
  /// past unseen. A clear after this long takes it down at once.
  clock::Duration warning_min_display = std::chrono::seconds{1};
  /// Upper bound for a DENM's validityDuration when it gives none (CDD default 600 s).
  clock::Duration denm_default_validity = std::chrono::seconds{600};
  /// A lane signal shows while its last message is at most this old (the station publishes
  /// it at up to 10 Hz while on an ingress lane, issue 34).
  clock::Duration signal_timeout = std::chrono::seconds{1};
  /// An RLVW warning neither updated nor cleared for this long is dropped, as LCRW's; a fresh
  /// lane signal whose `rlvw` flag is set keeps it up meanwhile.
  clock::Duration rlvw_timeout = std::chrono::seconds{2};
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
    clock::SteadyTime shown_since{};  ///< raised (this episode), for warning_min_display
    bool cleared = false;             ///< cleared early: kept until its minimum display ends
  };
  /// Whether @p w is on screen at @p now.
  bool shown(const Warning& w, clock::SteadyTime now) const;
  struct Denm {
    DenmEvent event;
    clock::SteadyTime expires{};
  };
  bool on_lcrw(std::uint32_t station, std::string_view payload, clock::SteadyTime now);
  bool on_cam(std::uint32_t station, std::uint32_t source, clock::SteadyTime now);
  bool on_denm(std::string_view payload, clock::SteadyTime now);
  bool on_signal(std::uint32_t station, std::string_view payload, clock::SteadyTime now);
  bool on_rlvw(std::uint32_t station, std::string_view payload, clock::SteadyTime now);
  bool reject(std::string_view topic, std::string why);

  MonitorConfig cfg_;
  mutable std::mutex mu_;
  std::map<std::pair<std::uint32_t, std::uint32_t>, Warning> warnings_;  ///< (station, other)
  std::map<std::pair<std::uint32_t, std::uint32_t>, clock::SteadyTime> heard_;  ///< (from, to)
  std::map<std::pair<std::uint32_t, std::uint32_t>, Denm> denms_;  ///< (originator, sequence)
  struct Signal {
    LaneSignal signal;
    clock::SteadyTime received{};
  };
  std::map<std::uint32_t, Signal> signals_;  ///< by station
  struct Rlvw {
    RlvwAlert alert;
    clock::SteadyTime received{};
  };
  std::map<std::uint32_t, Rlvw> rlvw_;  ///< by station: one own lane, one warning
  std::uint64_t accepted_ = 0;
  std::uint64_t rejected_ = 0;
  std::string last_error_;
};

}  // namespace tb::client::v2x
