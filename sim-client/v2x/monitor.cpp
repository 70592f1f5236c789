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

/// A finite number, or empty when absent; @p bad is set when present but not one.
std::optional<double> number(const json& obj, const char* key, bool& bad) {
  const auto it = obj.find(key);
  if (it == obj.end())
    return std::nullopt;
  if (!it->is_number() || !std::isfinite(it->get<double>())) {
    bad = true;
    return std::nullopt;
  }
  return it->get<double>();
}

/// A number or null (the contract's "number|null"); @p bad when neither or absent.
std::optional<double> number_or_null(const json& obj, const char* key, bool& bad) {
  const auto it = obj.find(key);
  if (it != obj.end() && it->is_null())
    return std::nullopt;
  if (it == obj.end())
    bad = true;
  return number(obj, key, bad);
}

/// An integer in [lo, hi].
std::optional<std::uint32_t> id_in(const json& obj, const char* key, std::int64_t lo,
                                   std::int64_t hi) {
  const auto v = integer(obj, key);
  if (!v || *v < lo || *v > hi)
    return std::nullopt;
  return static_cast<std::uint32_t>(*v);
}

// ISO TS 19091 DSRC MovementPhaseState (0..9), as the contract spells its names.
constexpr std::string_view kMovementPhaseStates[] = {"unavailable",
                                                     "dark",
                                                     "stop-Then-Proceed",
                                                     "stop-And-Remain",
                                                     "pre-Movement",
                                                     "permissive-Movement-Allowed",
                                                     "protected-Movement-Allowed",
                                                     "permissive-clearance",
                                                     "protected-clearance",
                                                     "caution-Conflicting-Traffic"};

// The DSRC ranges (ISO TS 19091): IntersectionID 0..65535, SignalGroupID and LaneID 0..255.
constexpr std::int64_t kMaxIntersectionId = 65535;
constexpr std::int64_t kMaxSignalGroup = 255;
constexpr std::int64_t kMaxLaneId = 255;
// Times of change are within the TimeMark's hour; distances within a MapData's reach.
constexpr double kMaxAbsSeconds = 3600.0;
constexpr double kMaxAbsMetres = 100000.0;
constexpr double kMaxSpeedKmh = 500.0;

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

std::string_view to_string(SignalLight l) {
  switch (l) {
    case SignalLight::kUnavailable:
      return "unavailable";
    case SignalLight::kDark:
      return "dark";
    case SignalLight::kRed:
      return "red";
    case SignalLight::kRedAmber:
      return "red_amber";
    case SignalLight::kAmber:
      return "amber";
    case SignalLight::kGreen:
      return "green";
  }
  return "unavailable";
}

std::optional<SignalLight> parse_signal_light(std::string_view text) {
  for (const SignalLight l : {SignalLight::kUnavailable, SignalLight::kDark, SignalLight::kRed,
                              SignalLight::kRedAmber, SignalLight::kAmber, SignalLight::kGreen})
    if (to_string(l) == text)
      return l;
  return std::nullopt;
}

const LaneSignal* V2xPicture::signal_for(std::uint32_t station) const {
  for (const auto& s : signals)
    if (s.station == station)
      return &s;
  return nullptr;
}

const RlvwAlert* V2xPicture::rlvw_for(std::uint32_t station) const {
  for (const auto& r : rlvw)
    if (r.station == station)
      return &r;
  return nullptr;
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
  // Every station's, as for LCRW: the view shows the followed car's when watching, and [ ]
  // switches cars without a new subscription.
  return {cfg_.prefix + "/+/app/lcrw", cfg_.prefix + "/+/in/cam/+", cfg_.prefix + "/+/in/denm/+",
          cfg_.prefix + "/+/app/signal", cfg_.prefix + "/+/app/rlvw"};
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
  } else if (parts.size() == 4 && parts[2] == "app" && parts[3] == "signal") {
    ok = on_signal(*station, payload, now);
  } else if (parts.size() == 4 && parts[2] == "app" && parts[3] == "rlvw") {
    ok = on_rlvw(*station, payload, now);
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
  const auto found = warnings_.find(key);
  if (event == "cleared") {
    if (found != warnings_.end()) {
      if (now - found->second.shown_since < cfg_.warning_min_display)
        found->second.cleared = true;
      else
        warnings_.erase(found);
    }
    return true;
  }
  if (event != "raised" && event != "updated") {
    last_error_ = fmt::format("message.event: '{}' is not raised, updated or cleared", event);
    return false;
  }
  // A warning raised again while still on screen (even after an early clear) continues its
  // episode: the banner does not restart its minimum display, it simply stays.
  const bool on_screen = found != warnings_.end() && shown(found->second, now);
  const clock::SteadyTime since = on_screen ? found->second.shown_since : now;
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
  warnings_[key] = Warning{std::move(a), now, since, false};
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

bool V2xMonitor::on_signal(std::uint32_t station, std::string_view payload, clock::SteadyTime now) {
  const json doc = json::parse(payload, nullptr, false);
  const json* m = message_of(doc);
  if (m == nullptr) {
    last_error_ = doc.is_discarded() ? "not JSON" : "not a signal envelope (no \"message\" object)";
    return false;
  }
  // The station left the ingress lane: one message with "lane": null (issue 34's contract);
  // a null lane_id is read the same way.
  const auto lane = m->find("lane");
  const auto lane_id_it = m->find("lane_id");
  if ((lane != m->end() && lane->is_null()) || (lane_id_it != m->end() && lane_id_it->is_null())) {
    signals_.erase(station);
    return true;
  }
  LaneSignal s;
  s.station = station;
  const auto ix = id_in(*m, "intersection_id", 0, kMaxIntersectionId);
  const auto group = id_in(*m, "signal_group", 0, kMaxSignalGroup);
  const auto lane_id = id_in(*m, "lane_id", 0, kMaxLaneId);
  if (!ix || !group || !lane_id) {
    last_error_ = fmt::format("message.{}: missing or outside its DSRC range",
                              !ix      ? "intersection_id (0..65535)"
                              : !group ? "signal_group (0..255)"
                                       : "lane_id (0..255)");
    return false;
  }
  s.intersection_id = *ix;
  s.signal_group = *group;
  s.lane_id = *lane_id;
  const std::string state = text(*m, "state");
  const auto light = parse_signal_light(state);
  if (!light) {
    last_error_ = fmt::format(
        "message.state: '{}' is not red, red_amber, amber, green, dark or unavailable", state);
    return false;
  }
  s.light = *light;
  s.event_state = text(*m, "event_state");
  if (std::find(std::begin(kMovementPhaseStates), std::end(kMovementPhaseStates), s.event_state) ==
      std::end(kMovementPhaseStates)) {
    last_error_ =
        fmt::format("message.event_state: '{}' is not a DSRC MovementPhaseState", s.event_state);
    return false;
  }
  bool bad = false;
  s.time_to_change_s = number_or_null(*m, "time_to_change_s", bad);
  if (bad || (s.time_to_change_s && std::abs(*s.time_to_change_s) > kMaxAbsSeconds)) {
    last_error_ = "message.time_to_change_s: not a number of seconds within the hour, nor null";
    return false;
  }
  // Optional in practice: a station without a likelyTime may leave it out.
  if (const auto it = m->find("likely_time_to_change_s"); it != m->end() && !it->is_null())
    s.likely_time_to_change_s = number(*m, "likely_time_to_change_s", bad);
  if (bad || (s.likely_time_to_change_s && std::abs(*s.likely_time_to_change_s) > kMaxAbsSeconds)) {
    last_error_ =
        "message.likely_time_to_change_s: not a number of seconds within the hour, nor null";
    return false;
  }
  bad = false;
  const auto distance = number(*m, "distance_to_stop_line_m", bad);
  if (!distance || std::abs(*distance) > kMaxAbsMetres) {
    last_error_ = "message.distance_to_stop_line_m: missing or not a distance in metres";
    return false;
  }
  s.distance_to_stop_line_m = *distance;
  if (const auto a = m->find("advice"); a != m->end() && !a->is_null()) {
    // -1: missing or not a number, which the range check refuses.
    const double lo = a->is_object() ? number(*a, "min_speed_kmh", bad).value_or(-1.0) : -1.0;
    const double hi = a->is_object() ? number(*a, "max_speed_kmh", bad).value_or(-1.0) : -1.0;
    if (lo < 0.0 || lo > hi || hi > kMaxSpeedKmh) {
      last_error_ =
          "message.advice: not null nor {min_speed_kmh, max_speed_kmh} with 0 <= min <= max";
      return false;
    }
    s.advice = SpeedAdvice{lo, hi};
  }
  if (const auto r = m->find("rlvw"); r != m->end()) {
    if (!r->is_boolean()) {
      last_error_ = "message.rlvw: not true or false";
      return false;
    }
    s.rlvw = r->get<bool>();
  }
  signals_[station] = Signal{std::move(s), now};
  if (signals_.size() > 4096)
    std::erase_if(signals_,
                  [&](const auto& kv) { return now - kv.second.received > cfg_.signal_timeout; });
  return true;
}

bool V2xMonitor::on_rlvw(std::uint32_t station, std::string_view payload, clock::SteadyTime now) {
  const json doc = json::parse(payload, nullptr, false);
  const json* m = message_of(doc);
  if (m == nullptr) {
    last_error_ =
        doc.is_discarded() ? "not JSON" : "not an rlvw_warning envelope (no \"message\" object)";
    return false;
  }
  const std::string event = text(*m, "event");
  if (event != "raised" && event != "updated" && event != "cleared") {
    last_error_ = fmt::format("message.event: '{}' is not raised, updated or cleared", event);
    return false;
  }
  RlvwAlert a;
  a.station = station;
  const auto ix = id_in(*m, "intersection_id", 0, kMaxIntersectionId);
  const auto group = id_in(*m, "signal_group", 0, kMaxSignalGroup);
  if (!ix || !group) {
    last_error_ = fmt::format("message.{}: missing or outside its DSRC range",
                              !ix ? "intersection_id (0..65535)" : "signal_group (0..255)");
    return false;
  }
  a.intersection_id = *ix;
  a.signal_group = *group;
  if (event == "cleared") {
    // Only the warning it names: a late clear of a former lane leaves a newer warning up.
    const auto it = rlvw_.find(station);
    if (it != rlvw_.end() && it->second.alert.intersection_id == a.intersection_id &&
        it->second.alert.signal_group == a.signal_group)
      rlvw_.erase(it);
    return true;
  }
  const auto lane_id = id_in(*m, "lane_id", 0, kMaxLaneId);
  if (!lane_id) {
    last_error_ = "message.lane_id: missing or outside its DSRC range (0..255)";
    return false;
  }
  a.lane_id = *lane_id;
  bool bad = false;
  const auto distance = number(*m, "distance_to_stop_line_m", bad);
  const auto speed = number(*m, "speed_mps", bad);
  const auto stopping = number(*m, "stopping_distance_m", bad);
  a.time_to_red_s = number_or_null(*m, "time_to_red_s", bad);
  if (bad || !distance || !speed || !stopping || std::abs(*distance) > kMaxAbsMetres ||
      *speed < 0.0 || *speed > kMaxSpeedKmh / 3.6 || *stopping < 0.0 || *stopping > kMaxAbsMetres ||
      (a.time_to_red_s && std::abs(*a.time_to_red_s) > kMaxAbsSeconds)) {
    last_error_ =
        "message: distance_to_stop_line_m, speed_mps, stopping_distance_m or time_to_red_s "
        "missing or out of range";
    return false;
  }
  a.distance_to_stop_line_m = *distance;
  a.speed_mps = *speed;
  a.stopping_distance_m = *stopping;
  rlvw_[station] = Rlvw{a, now};
  if (rlvw_.size() > 4096)
    std::erase_if(rlvw_,
                  [&](const auto& kv) { return now - kv.second.received > cfg_.rlvw_timeout; });
  return true;
}

bool V2xMonitor::shown(const Warning& w, clock::SteadyTime now) const {
  if (w.cleared)
    return now - w.shown_since < cfg_.warning_min_display;
  return now - w.received <= cfg_.warning_timeout;
}

V2xPicture V2xMonitor::picture(clock::SteadyTime now) const {
  std::lock_guard lock(mu_);
  V2xPicture p;
  for (const auto& [key, w] : warnings_)
    if (shown(w, now))
      p.alerts.push_back(w.alert);
  std::stable_sort(p.alerts.begin(), p.alerts.end(), more_urgent);
  for (const auto& [key, t] : heard_)
    if (now - t <= cfg_.link_window)
      p.links.push_back(V2xLink{key.first, key.second});
  for (const auto& [key, d] : denms_)
    if (now < d.expires)
      p.denms.push_back(d.event);
  // Times to a change count from the message's receipt: aged to now, so that a countdown
  // runs on between messages (at most 10 a second, maybe far fewer).
  const auto aged = [&](std::optional<double>& t, clock::SteadyTime received) {
    if (t)
      *t -= std::chrono::duration<double>(now - received).count();
  };
  for (const auto& [station, s] : signals_) {
    if (now - s.received > cfg_.signal_timeout)
      continue;
    LaneSignal sig = s.signal;
    aged(sig.time_to_change_s, s.received);
    aged(sig.likely_time_to_change_s, s.received);
    p.signals.push_back(std::move(sig));
  }
  for (const auto& [station, r] : rlvw_) {
    const LaneSignal* lane = p.signal_for(station);
    if (now - r.received <= cfg_.rlvw_timeout || (lane != nullptr && lane->rlvw)) {
      RlvwAlert a = r.alert;
      aged(a.time_to_red_s, r.received);
      p.rlvw.push_back(a);
    }
  }
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
