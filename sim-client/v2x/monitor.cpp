#include "sim-client/v2x/monitor.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace tb::client::v2x {
namespace {

using nlohmann::json;

std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> parts;
  std::size_t from = 0;
  while (true) {
    const std::size_t at = s.find(sep, from);
    parts.push_back(
        s.substr(from, at == std::string_view::npos ? std::string_view::npos : at - from));
    if (at == std::string_view::npos)
      return parts;
    from = at + 1;
  }
}

std::optional<std::uint32_t> station_id(std::string_view text) {
  std::uint32_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty())
    return std::nullopt;
  return v;
}

/// The envelope's "message" object (its-station/apps/README.md, "Payloads").
const json* message_of(const json& doc) {
  if (!doc.is_object())
    return nullptr;
  const auto it = doc.find("message");
  return it != doc.end() && it->is_object() ? &*it : nullptr;
}

std::optional<std::int64_t> integer(const json& obj, const char* key) {
  const auto it = obj.find(key);
  if (it == obj.end() || !it->is_number_integer())
    return std::nullopt;
  return it->get<std::int64_t>();
}

std::string text(const json& obj, const char* key) {
  const auto it = obj.find(key);
  return it != obj.end() && it->is_string() ? it->get<std::string>() : std::string();
}

bool more_urgent(const LcrwAlert& a, const LcrwAlert& b) {
  const double inf = std::numeric_limits<double>::infinity();
  return a.ttc_s.value_or(inf) < b.ttc_s.value_or(inf);
}

}  // namespace

std::optional<double> relevance_radius_m(std::int64_t relevance_distance) {
  static constexpr double kRadius[] = {50.0, 100.0, 200.0, 500.0, 1000.0, 5000.0, 10000.0, 20000.0};
  if (relevance_distance < 0 || relevance_distance > 7)
    return std::nullopt;
  return kRadius[relevance_distance];
}

const LcrwAlert* V2xPicture::alert_for(std::uint32_t station) const {
  // alerts are sorted most urgent first.
  for (const auto& a : alerts)
    if (a.station == station)
      return &a;
  return nullptr;
}

V2xMonitor::V2xMonitor(MonitorConfig cfg) : cfg_(std::move(cfg)) {}

std::vector<std::string> V2xMonitor::subscriptions() const {
  return {cfg_.prefix + "/+/app/lcrw", cfg_.prefix + "/+/in/cam/+", cfg_.prefix + "/+/in/denm/+"};
}

bool V2xMonitor::reject(std::string_view topic, std::string why) {
  ++rejected_;
  last_error_ = fmt::format("{}: {}", topic, why);
  return false;
}

bool V2xMonitor::on_message(std::string_view topic, std::string_view payload,
                            clock::SteadyTime now) {
  const auto parts = split(topic, '/');
  if (parts.size() < 4 || parts[0] != cfg_.prefix)
    return false;  // not ours: nothing to count
  std::lock_guard lock(mu_);
  const auto station = station_id(parts[1]);
  if (!station)
    return reject(topic, fmt::format("'{}' is not a station id", parts[1]));
  bool ok = false;
  if (parts.size() == 4 && parts[2] == "app" && parts[3] == "lcrw") {
    ok = on_lcrw(*station, payload, now);
  } else if (parts.size() == 5 && parts[2] == "in" && parts[3] == "cam") {
    const auto source = station_id(parts[4]);
    if (!source)
      return reject(topic, fmt::format("'{}' is not a station id", parts[4]));
    ok = on_cam(*station, *source, now);
  } else if (parts.size() == 5 && parts[2] == "in" && parts[3] == "denm") {
    ok = on_denm(payload, now);
  } else {
    return false;
  }
  if (!ok)
    return reject(topic, last_error_);
  ++accepted_;
  return true;
}

bool V2xMonitor::on_lcrw(std::uint32_t station, std::string_view payload, clock::SteadyTime now) {
  const json doc = json::parse(payload, nullptr, false);
  const json* m = message_of(doc);
  if (m == nullptr) {
    last_error_ = "not an lcrw_warning envelope (no \"message\" object)";
    return false;
  }
  const auto other = integer(*m, "other_station_id");
  const std::string event = text(*m, "event");
  if (!other || *other < 0 || *other > std::numeric_limits<std::uint32_t>::max()) {
    last_error_ = "message.other_station_id: missing or not a station id";
    return false;
  }
  const auto key = std::make_pair(station, static_cast<std::uint32_t>(*other));
  if (event == "cleared") {
    warnings_.erase(key);
    return true;
  }
  if (event != "raised" && event != "updated") {
    last_error_ = fmt::format("message.event: '{}' is not raised, updated or cleared", event);
    return false;
  }
  LcrwAlert a;
  a.station = station;
  a.other = key.second;
  if (const auto it = m->find("ttc_s"); it != m->end() && it->is_number()) {
    const double ttc = it->get<double>();
    if (std::isfinite(ttc))
      a.ttc_s = ttc;
  }
  a.collision_case = text(*m, "collision_case");
  a.severity = text(*m, "severity");
  if (const auto it = m->find("distance_m"); it != m->end() && it->is_number())
    a.distance_m = it->get<double>();
  warnings_[key] = Warning{std::move(a), now};
  if (warnings_.size() > 4096) {
    std::erase_if(warnings_,
                  [&](const auto& kv) { return now - kv.second.received > cfg_.warning_timeout; });
  }
  return true;
}

bool V2xMonitor::on_cam(std::uint32_t station, std::uint32_t source, clock::SteadyTime now) {
  heard_[{source, station}] = now;
  // Keep the table to the pairs that can still be links.
  if (heard_.size() > 4096) {
    std::erase_if(heard_, [&](const auto& kv) { return now - kv.second > cfg_.link_window; });
  }
  return true;
}

bool V2xMonitor::on_denm(std::string_view payload, clock::SteadyTime now) {
  const json doc = json::parse(payload, nullptr, false);
  const json* m = message_of(doc);
  const auto mc_it = m != nullptr ? m->find("management_container") : json::const_iterator();
  if (m == nullptr || mc_it == m->end() || !mc_it->is_object()) {
    last_error_ = "not a denm envelope (no message.management_container)";
    return false;
  }
  const json& mc = *mc_it;
  const auto aid = mc.find("action_id");
  const auto pos = mc.find("event_position");
  if (aid == mc.end() || !aid->is_object() || pos == mc.end() || !pos->is_object()) {
    last_error_ = "management_container: action_id or event_position missing";
    return false;
  }
  const auto origin = integer(*aid, "originating_station_id");
  const auto seq = integer(*aid, "sequence_number");
  const auto lat = integer(*pos, "latitude");
  const auto lon = integer(*pos, "longitude");
  // CDD ranges: StationID 0..2^32-1, SequenceNumber 0..65535, Latitude ±900000000 (+1 n/a),
  // Longitude ±1800000000 (+1 n/a), in 0.1 microdegrees.
  if (!origin || *origin < 0 || *origin > std::numeric_limits<std::uint32_t>::max() || !seq ||
      *seq < 0 || *seq > 65535 || !lat || std::abs(*lat) > 900000000 || !lon ||
      std::abs(*lon) > 1800000000) {
    last_error_ = "action_id or event_position out of the CDD's range";
    return false;
  }
  const auto key =
      std::make_pair(static_cast<std::uint32_t>(*origin), static_cast<std::uint32_t>(*seq));
  if (mc.contains("termination")) {
    denms_.erase(key);
    return true;
  }
  DenmEvent e;
  e.originator = key.first;
  e.sequence = key.second;
  e.latitude_deg = static_cast<double>(*lat) * 1e-7;
  e.longitude_deg = static_cast<double>(*lon) * 1e-7;
  if (const auto sc = m->find("situation_container"); sc != m->end() && sc->is_object()) {
    if (const auto et = sc->find("event_type"); et != sc->end() && et->is_object()) {
      e.cause = static_cast<int>(integer(*et, "cause").value_or(0));
      e.subcause = static_cast<int>(integer(*et, "subcause").value_or(0));
    }
  }
  // Optional in the DENM; when there, inside the CDD's range, else the message is not one a
  // station sends.
  if (mc.contains("relevance_distance")) {
    const auto rd = integer(mc, "relevance_distance");
    e.relevance_radius_m = rd ? relevance_radius_m(*rd) : std::nullopt;
    if (!e.relevance_radius_m) {
      last_error_ = "management_container.relevance_distance: not a CDD RelevanceDistance (0..7)";
      return false;
    }
  }
  if (mc.contains("relevance_traffic_direction")) {
    const auto td = integer(mc, "relevance_traffic_direction");
    if (!td || *td < 0 || *td > 3) {
      last_error_ =
          "management_container.relevance_traffic_direction: not a CDD "
          "RelevanceTrafficDirection (0..3)";
      return false;
    }
    e.relevance_traffic_direction = static_cast<int>(*td);
  }
  clock::Duration validity = cfg_.denm_default_validity;
  if (const auto v = integer(mc, "validity_duration"); v && *v >= 0 && *v <= 86400)
    validity = std::chrono::seconds{*v};
  denms_[key] = Denm{e, now + validity};
  if (denms_.size() > 4096)
    std::erase_if(denms_, [&](const auto& kv) { return now >= kv.second.expires; });
  return true;
}

V2xPicture V2xMonitor::picture(clock::SteadyTime now) const {
  std::lock_guard lock(mu_);
  V2xPicture p;
  for (const auto& [key, w] : warnings_)
    if (now - w.received <= cfg_.warning_timeout)
      p.alerts.push_back(w.alert);
  std::stable_sort(p.alerts.begin(), p.alerts.end(), more_urgent);
  for (const auto& [key, t] : heard_)
    if (now - t <= cfg_.link_window)
      p.links.push_back(V2xLink{key.first, key.second});
  for (const auto& [key, d] : denms_)
    if (now < d.expires)
      p.denms.push_back(d.event);
  return p;
}

std::uint64_t V2xMonitor::accepted() const {
  std::lock_guard lock(mu_);
  return accepted_;
}
std::uint64_t V2xMonitor::rejected() const {
  std::lock_guard lock(mu_);
  return rejected_;
}
std::string V2xMonitor::last_error() const {
  std::lock_guard lock(mu_);
  return last_error_;
}

}  // namespace tb::client::v2x
