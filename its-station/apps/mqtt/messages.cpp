#include "its-station/apps/mqtt/messages.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace tb::its::apps::mqtt {
namespace {

using nlohmann::json;

std::int64_t scaled(double v, double unit, std::int64_t lo, std::int64_t hi) {
  return std::clamp<std::int64_t>(std::llround(v / unit), lo, hi);
}

// CDD (TS 102 894-2) value encodings. Out-of-range values saturate at the largest valid code
// rather than falling onto the "unavailable" code.
std::int64_t latitude(double deg) {
  return scaled(deg, 1e-7, -900000000, 900000000);
}
std::int64_t longitude(double deg) {
  return scaled(deg, 1e-7, -1800000000, 1800000000);
}
std::int64_t altitude(double m) {
  return scaled(m, 0.01, -100000, 800000);
}
std::int64_t heading(double deg) {
  const double wrapped = geodesy::wrap_360(deg);
  return std::llround(wrapped * 10.0) % 3600;  // 359.96° rounds to 3600, which is 0°
}
std::int64_t speed(double mps) {
  return scaled(mps, 0.01, 0, 16382);
}
std::int64_t longitudinal_acceleration(double mps2) {
  return scaled(mps2, 0.1, -160, 160);
}
std::int64_t vehicle_length(double m) {
  return scaled(m, 0.1, 1, 1022);
}
std::int64_t vehicle_width(double m) {
  return scaled(m, 0.1, 1, 61);
}

// The CDD containers as JSON text, members in nlohmann::json's order (sorted by key, as its
// std::map keeps them), so that received_cam_payload() equals the tree envelope's dump().
void write_reference_position(fmt::memory_buffer& out, const Kinematics& k) {
  auto it = std::back_inserter(out);
  out.push_back('{');
  if (k.altitude_m) {
    fmt::format_to(it, "\"altitude\":{},", altitude(*k.altitude_m));
  }
  fmt::format_to(it, "\"latitude\":{},\"longitude\":{}}}", latitude(k.latitude_deg),
                 longitude(k.longitude_deg));
}

void write_high_frequency(fmt::memory_buffer& out, const Kinematics& k) {
  auto it = std::back_inserter(out);
  // CDD DriveDirection: forward(0), backward(1)
  fmt::format_to(it, "{{\"drive_direction\":{}", k.reversing ? 1 : 0);
  if (k.heading_deg) {
    fmt::format_to(it, ",\"heading\":{}", heading(*k.heading_deg));
  }
  if (k.longitudinal_accel_mps2) {
    fmt::format_to(it, ",\"longitudinal_acceleration\":{}",
                   longitudinal_acceleration(*k.longitudinal_accel_mps2));
  }
  if (k.speed_mps) {
    fmt::format_to(it, ",\"speed\":{}", speed(*k.speed_mps));
  }
  if (k.length_m) {
    fmt::format_to(it, ",\"vehicle_length\":{}", vehicle_length(*k.length_m));
  }
  if (k.width_m) {
    fmt::format_to(it, ",\"vehicle_width\":{}", vehicle_width(*k.width_m));
  }
  out.push_back('}');
}

// The trees of the state message come from the same writers, so that the containers' members
// and units are defined once (at 10 Hz the parse costs nothing that matters).
json reference_position(const Kinematics& k) {
  fmt::memory_buffer out;
  write_reference_position(out, k);
  return json::parse(std::string_view(out.data(), out.size()));
}

json high_frequency(const Kinematics& k) {
  fmt::memory_buffer out;
  write_high_frequency(out, k);
  return json::parse(std::string_view(out.data(), out.size()));
}

json finite_or_null(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}

}  // namespace

Topics::Topics(std::string prefix, std::uint32_t station_id)
    : root_(std::move(prefix) + "/" + std::to_string(station_id)) {}

std::string Topics::cam_in(std::uint32_t source) const {
  return root_ + "/in/cam/" + std::to_string(source);
}
std::string Topics::denm_in(std::uint32_t originating) const {
  return root_ + "/in/denm/" + std::to_string(originating);
}

std::string_view to_string(GnssFix f) {
  switch (f) {
    case GnssFix::kNoFix:
      return "none";
    case GnssFix::k2D:
      return "2d";
    case GnssFix::k3D:
      return "3d";
  }
  return "unknown";
}

json envelope(std::string_view type, std::string_view origin, std::uint32_t source,
              clock::WallTime now, json message) {
  return json{{"type", type},
              {"origin", origin},
              {"version", kEnvelopeVersion},
              {"source_uuid", "station-" + std::to_string(source)},
              {"timestamp", unix_ms(now)},
              {"message", std::move(message)}};
}

json state_message(const StationState& s) {
  json gnss{{"fix", to_string(s.fix)}};
  if (s.satellites_used) {
    gnss["satellites_used"] = *s.satellites_used;
  }
  if (s.hdop) {
    gnss["hdop"] = *s.hdop;
  }
  return json{{"station_id", s.station_id},
              {"timestamp_its", timestamp_its(s.time)},
              {"basic_container",
               {{"station_type", s.station_type},
                {"reference_position", reference_position(s.kinematics)}}},
              {"high_frequency_container", high_frequency(s.kinematics)},
              {"gnss", std::move(gnss)}};
}

json cam_message(const ReceivedCam& c) {
  return json{{"protocol_version", 2},
              {"station_id", c.station_id},
              {"generation_delta_time", c.generation_delta_time},
              {"basic_container",
               {{"station_type", c.station_type},
                {"reference_position", reference_position(c.kinematics)}}},
              {"high_frequency_container", high_frequency(c.kinematics)},
              {"received_at", unix_ms(c.received_at)}};
}

namespace {

// The envelope's members after "message", in the order nlohmann keeps them, and its closing brace.
void write_envelope_rest(fmt::memory_buffer& out, std::string_view origin, std::uint32_t source,
                         clock::WallTime now, std::string_view type) {
  fmt::format_to(std::back_inserter(out),
                 "\"origin\":\"{}\",\"source_uuid\":\"station-{}\",\"timestamp\":{},"
                 "\"type\":\"{}\",\"version\":\"{}\"}}",
                 origin, source, unix_ms(now), type, kEnvelopeVersion);
}

}  // namespace

std::string received_cam_payload(std::uint32_t source, clock::WallTime now, const ReceivedCam& c) {
  fmt::memory_buffer out;
  auto it = std::back_inserter(out);
  fmt::format_to(it, "{{\"message\":{{\"basic_container\":{{\"reference_position\":");
  write_reference_position(out, c.kinematics);
  fmt::format_to(it, ",\"station_type\":{}}},\"generation_delta_time\":{},", c.station_type,
                 c.generation_delta_time);
  fmt::format_to(it, "\"high_frequency_container\":");
  write_high_frequency(out, c.kinematics);
  fmt::format_to(it, ",\"protocol_version\":2,\"received_at\":{},\"station_id\":{}}},",
                 unix_ms(c.received_at), c.station_id);
  write_envelope_rest(out, "remote", source, now, "cam");
  return fmt::to_string(out);
}

std::string state_payload(std::uint32_t source, clock::WallTime now, const StationState& s) {
  fmt::memory_buffer out;
  auto it = std::back_inserter(out);
  fmt::format_to(it, "{{\"message\":{{\"basic_container\":{{\"reference_position\":");
  write_reference_position(out, s.kinematics);
  fmt::format_to(it, ",\"station_type\":{}}},\"gnss\":{{\"fix\":\"{}\"", s.station_type,
                 to_string(s.fix));
  if (s.hdop) {
    // nlohmann's own number text (1.0, not fmt's 1), so that the payload equals the tree's dump.
    fmt::format_to(it, ",\"hdop\":{}", json(*s.hdop).dump());
  }
  if (s.satellites_used) {
    fmt::format_to(it, ",\"satellites_used\":{}", *s.satellites_used);
  }
  fmt::format_to(it, "}},\"high_frequency_container\":");
  write_high_frequency(out, s.kinematics);
  fmt::format_to(it, ",\"station_id\":{},\"timestamp_its\":{}}},", s.station_id,
                 timestamp_its(s.time));
  write_envelope_rest(out, "self", source, now, "state");
  return fmt::to_string(out);
}

json denm_message(const DenmView& d) {
  json mc{{"action_id",
           {{"originating_station_id", d.action_id.originating_station_id},
            {"sequence_number", d.action_id.sequence_number}}},
          {"detection_time", timestamp_its(d.detection_time)},
          {"reference_time", timestamp_its(d.reference_time)},
          {"event_position",
           {{"latitude", latitude(d.event_latitude_deg)},
            {"longitude", longitude(d.event_longitude_deg)}}},
          {"relevance_distance", static_cast<int>(d.relevance_distance)},
          {"relevance_traffic_direction", static_cast<int>(d.relevance_traffic_direction)},
          {"validity_duration", d.validity_duration_s}};
  if (d.termination) {
    mc["termination"] = *d.termination;
  }
  return json{{"protocol_version", 2},
              {"station_id", d.action_id.originating_station_id},
              {"management_container", std::move(mc)},
              {"situation_container",
               {{"event_type", {{"cause", d.cause_code}, {"subcause", d.sub_cause_code}}}}}};
}

json lcrw_message(const LcrwWarning& w) {
  return json{{"station_id", w.station_id},
              {"other_station_id", w.other_station_id},
              {"event", to_string(w.event)},
              {"collision_case", to_string(w.collision_case)},
              {"severity", to_string(w.severity)},
              {"clear_reason", to_string(w.clear_reason)},
              {"ttc_s", finite_or_null(w.ttc_s)},
              {"distance_m", finite_or_null(w.distance_m)},
              {"relative_speed_mps", finite_or_null(w.relative_speed_mps)},
              {"lateral_offset_m", finite_or_null(w.lateral_offset_m)},
              {"raised_at", unix_ms(w.raised_at)},
              {"updated_at", unix_ms(w.updated_at)},
              {"own_state_time", unix_ms(w.own_state_time)},
              {"other_state_time", unix_ms(w.other_state_time)}};
}

namespace {

json optional_number(const std::optional<double>& v) {
  return v && std::isfinite(*v) ? json(*v) : json(nullptr);
}

}  // namespace

json signal_message(const signal::SignalStatus& s) {
  if (!s.on_lane) {
    return json{{"intersection_id", s.intersection_id}, {"lane", nullptr}};
  }
  json advice = nullptr;
  if (s.advice) {
    advice = json{{"min_speed_kmh", s.advice->min_speed_mps * 3.6},
                  {"max_speed_kmh", s.advice->max_speed_mps * 3.6}};
  }
  return json{{"intersection_id", s.intersection_id},
              {"signal_group", s.signal_group},
              {"lane_id", s.lane_id},
              {"state", signal::light_name(s.state)},
              {"event_state", signal::dsrc_name(s.state)},
              {"time_to_change_s", optional_number(s.time_to_change_s)},
              {"likely_time_to_change_s", optional_number(s.likely_time_to_change_s)},
              {"distance_to_stop_line_m", s.distance_to_stop_line_m},
              {"advice", std::move(advice)},
              {"rlvw", s.rlvw}};
}

json rlvw_message(const signal::RlvwWarning& w) {
  return json{{"station_id", w.station_id},
              {"intersection_id", w.intersection_id},
              {"signal_group", w.signal_group},
              {"lane_id", w.lane_id},
              {"event", signal::to_string(w.event)},
              {"severity", "warning"},
              {"distance_to_stop_line_m", w.distance_to_stop_line_m},
              {"speed_mps", w.speed_mps},
              {"time_to_red_s", optional_number(w.time_to_red_s)},
              {"stopping_distance_m", w.stopping_distance_m},
              {"clear_reason", signal::to_string(w.clear_reason)},
              {"raised_at", unix_ms(w.raised_at)},
              {"updated_at", unix_ms(w.updated_at)}};
}

}  // namespace tb::its::apps::mqtt
