#include "common/scenario/loader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <system_error>
#include <unordered_map>

#include <fmt/format.h>

#include "common/geodesy/local_frame.hpp"
#include "common/map/builtin_network.hpp"
#include "common/map/opendrive/reader.hpp"
#include "common/map/route_plan.hpp"
#include "common/map/scenario_map.hpp"
#include "common/scenario/json_reader.hpp"
#include "common/scenario/rsus.hpp"
#include "common/scenario/signal_plans.hpp"
#include "common/wire/vehicle_state.hpp"

namespace tb::scenario {

using detail::Node;
using json = nlohmann::json;

ScenarioError::ScenarioError(std::string file, std::string path, std::string reason)
    : std::runtime_error(file + ": " + (path.empty() ? std::string("/") : path) + ": " + reason),
      file_(std::move(file)),
      path_(std::move(path)),
      reason_(std::move(reason)) {}

namespace {

// Limits that keep a scenario physically meaningful; see docs/scenario.md.
constexpr int kMaxVehicles = 5000;
constexpr double kMaxSpeed = 70.0;  // m/s, 252 km/h
/// Fastest reversing a lane_follow profile may ask for (a car's reverse gear tops out near).
constexpr double kMaxReverseSpeed = 15.0;  // m/s
/// Largest |x|, |y| of a pose spawn, and of s: a map's frame spans at most this (the
/// OpenDRIVE reader's cap on coordinates).
constexpr double kMaxCoordinate = map::odr::kMaxCoordinate;

// ---- JSON text → json, rejecting duplicate keys (nlohmann silently keeps the last) ----------

struct Frame {
  bool is_array = false;
  long index = -1;
  std::string key;
  std::set<std::string> keys;
};

std::string frames_path(const std::vector<Frame>& frames) {
  std::string p;
  for (const Frame& f : frames) {
    if (f.is_array) {
      if (f.index >= 0)
        p += "/" + std::to_string(f.index);
    } else if (!f.key.empty()) {
      p += "/" + f.key;
    }
  }
  return p;
}

json parse_text(std::string_view text, const std::string& file) {
  std::vector<Frame> frames;
  std::string duplicate_path, duplicate_key;
  auto element_begins = [&] {
    if (!frames.empty() && frames.back().is_array)
      ++frames.back().index;
  };
  json::parser_callback_t cb = [&](int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
        element_begins();
        frames.emplace_back();
        break;
      case json::parse_event_t::array_start:
        element_begins();
        frames.emplace_back().is_array = true;
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!frames.empty())
          frames.pop_back();
        break;
      case json::parse_event_t::key: {
        Frame& f = frames.back();
        f.key = parsed.get<std::string>();
        if (!f.keys.insert(f.key).second && duplicate_path.empty()) {
          duplicate_path = frames_path(frames);
          duplicate_key = f.key;
        }
        break;
      }
      case json::parse_event_t::value:
        element_begins();
        break;
    }
    return true;
  };
  json doc;
  try {
    doc = json::parse(text.begin(), text.end(), cb);
  } catch (const json::parse_error& e) {
    // Turn the byte offset into a line and column a person can find.
    std::size_t line = 1, col = 1;
    for (std::size_t i = 0; i + 1 < e.byte && i < text.size(); ++i) {
      if (text[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    std::string msg = e.what();
    if (const auto pos = msg.find("syntax error"); pos != std::string::npos)
      msg = msg.substr(pos);
    throw ScenarioError(file, "",
                        fmt::format("invalid JSON at line {}, column {}: {}", line, col, msg));
  }
  if (!duplicate_path.empty()) {
    throw ScenarioError(file, duplicate_path,
                        "duplicate key \"" + duplicate_key + "\" (JSON objects need unique keys)");
  }
  return doc;
}

// ---- start_time ------------------------------------------------------------------------------

/// 2004-01-01T00:00:00Z, the epoch of TimestampIts (TS 102 894-2), in Unix seconds.
constexpr long long kItsEpochUnixS = 1072915200;

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's civil calendar algorithm).
long long days_from_civil(long long y, unsigned m, unsigned d) {
  y -= m <= 2;
  const long long era = (y >= 0 ? y : y - 399) / 400;
  const unsigned yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<long long>(doe) - 719468;
}

std::chrono::system_clock::time_point parse_utc(const Node& n) {
  const std::string s = n.string();
  int y = 0, mo = 0, d = 0, h = 0, mi = 0, sec = 0, consumed = 0;
  const char* bad = "expected a UTC time like \"2025-06-01T10:00:00Z\", found \"";
  if (std::sscanf(s.c_str(), "%4d-%2d-%2dT%2d:%2d:%2d%n", &y, &mo, &d, &h, &mi, &sec, &consumed) !=
          6 ||
      consumed != 19) {
    n.fail(bad + s + "\"");
  }
  std::string rest = s.substr(19);
  long long millis = 0;
  if (!rest.empty() && rest[0] == '.') {
    std::size_t i = 1;
    int digits = 0;
    while (i < rest.size() && std::isdigit(static_cast<unsigned char>(rest[i]))) {
      if (digits < 3)
        millis = millis * 10 + (rest[i] - '0');
      ++digits;
      ++i;
    }
    if (digits == 0)
      n.fail(bad + s + "\"");
    for (int k = digits; k < 3; ++k)
      millis *= 10;
    rest = rest.substr(i);
  }
  if (rest != "Z")
    n.fail(bad + s + "\" (the time must be UTC and end in Z)");
  static constexpr int kDays[] = {31, 29, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
  if (y < 2004 || y > 2100 || mo < 1 || mo > 12 || d < 1 ||
      d > (mo == 2 && !leap ? 28 : kDays[mo - 1]) || h > 23 || mi > 59 || sec > 59) {
    n.fail("\"" + s + "\" is not a valid date and time between 2004 and 2100");
  }
  const long long secs =
      days_from_civil(y, static_cast<unsigned>(mo), static_cast<unsigned>(d)) * 86400LL +
      h * 3600LL + mi * 60LL + sec;
  return std::chrono::system_clock::time_point{std::chrono::seconds{secs} +
                                               std::chrono::milliseconds{millis}};
}

// ---- sections --------------------------------------------------------------------------------

MapSpec read_map(Node n) {
  n.expect_object("the map");
  MapSpec m;
  const std::string type = n.required("type").choice({"straight", "ring", "crossing", "opendrive"});
  if (type == "opendrive") {
    m.type = MapType::kOpenDrive;
    m.file = n.required("file").string();
    if (m.file.empty())
      n.required("file").fail("the OpenDRIVE file name must not be empty");
    const std::string why = "only for the built-in layouts (straight, ring, crossing)";
    n.finish({{"lanes", why},
              {"oncoming_lanes", why},
              {"lane_width", why},
              {"length", why},
              {"radius", why},
              {"arm_length", why}});
    return m;
  }
  m.type = type == "ring"       ? MapType::kRing
           : type == "crossing" ? MapType::kCrossing
                                : MapType::kStraight;
  if (auto l = n.optional("lanes"))
    m.lanes = static_cast<int>(l->integer(1, 8));
  m.lane_width = n.number_or("lane_width", 3.5, 2.0, 6.0);
  const int default_oncoming = m.type == MapType::kRing ? 0 : m.lanes / 2;
  if (auto o = n.optional("oncoming_lanes")) {
    m.oncoming_lanes = static_cast<int>(o->integer(0, m.lanes));
  } else {
    m.oncoming_lanes = default_oncoming;
  }
  std::vector<std::pair<std::string, std::string>> why_not{
      {"file", "only for map type \"opendrive\""}};
  switch (m.type) {
    case MapType::kStraight:
      m.length = n.number_or("length", 1000.0, 10.0, 100000.0);
      why_not.insert(why_not.end(), {{"radius", "only for map type \"ring\""},
                                     {"arm_length", "only for map type \"crossing\""}});
      break;
    case MapType::kRing: {
      const double half_width = m.lanes * m.lane_width / 2.0;
      const double min_radius = half_width + 5.0;
      if (auto r = n.optional("radius")) {
        m.radius = r->number(min_radius, 10000.0);
      } else {
        m.radius = std::max(150.0, min_radius);
      }
      why_not.insert(why_not.end(), {{"length", "only for map type \"straight\""},
                                     {"arm_length", "only for map type \"crossing\""}});
      break;
    }
    case MapType::kCrossing:
      m.arm_length = n.number_or("arm_length", 300.0, 10.0, 10000.0);
      why_not.insert(why_not.end(), {{"length", "only for map type \"straight\""},
                                     {"radius", "only for map type \"ring\""}});
      break;
    case MapType::kOpenDrive:
      break;
  }
  n.finish(why_not);
  return m;
}

geodesy::Geodetic read_origin(Node n) {
  n.expect_object("the geographic origin");
  geodesy::Geodetic g;
  g.latitude_deg = n.required("lat").number(-89.0, 89.0);
  g.longitude_deg = n.required("lon").number(-180.0, 180.0);
  g.altitude_m = n.number_or("alt", 0.0, -500.0, 9000.0);
  n.finish();
  return g;
}

Rates read_rates(Node n) {
  n.expect_object("the rates");
  Rates r;
  r.physics_hz = n.number_or("physics_hz", r.physics_hz, 10.0, 1000.0);
  r.gnss_hz = n.number_or("gnss_hz", r.gnss_hz, 0.5, 100.0);
  r.can_dynamics_hz = n.number_or("can_dynamics_hz", r.can_dynamics_hz, 1.0, 1000.0);
  r.can_body_hz = n.number_or("can_body_hz", r.can_body_hz, 0.5, 1000.0);
  n.finish();
  if (r.gnss_hz > r.physics_hz) {
    n.fail(
        fmt::format("gnss_hz {} exceeds physics_hz {}: a fix cannot be newer than the "
                    "physics it describes",
                    r.gnss_hz, r.physics_hz));
  }
  return r;
}

GnssErrors read_gnss(Node n) {
  n.expect_object("the GNSS error model");
  GnssErrors g;
  const std::string model =
      n.optional("model") ? n.required("model").choice({"ideal", "noisy"}) : "ideal";
  g.ideal = model == "ideal";
  g.hdop = n.number_or("hdop", g.hdop, 0.5, 50.0);
  g.vdop = n.number_or("vdop", g.vdop, 0.5, 50.0);
  if (auto s = n.optional("satellites"))
    g.satellites = static_cast<int>(s->integer(4, 32));
  if (auto windows = n.optional("fix_loss")) {
    for (Node& w : windows->array(0, 1000)) {
      w.expect_object("a fix-loss window");
      FixLossWindow f;
      f.from_s = w.required("from_s").number(0.0, 1e7);
      f.to_s = w.required("to_s").number(0.0, 1e7);
      w.finish();
      if (f.to_s <= f.from_s)
        w.fail("to_s must be later than from_s");
      g.fix_loss.push_back(f);
    }
  }
  if (!g.ideal) {
    g.white_noise_m = n.number_or("white_noise_m", 1.0, 0.0, 100.0);
    g.bias_walk_m = n.number_or("bias_walk_m", 0.1, 0.0, 10.0);
    g.vertical_noise_m = n.number_or("vertical_noise_m", 1.5, 0.0, 100.0);
  }
  const std::string only_noisy = "only with \"model\": \"noisy\"";
  n.finish({{"white_noise_m", only_noisy},
            {"bias_walk_m", only_noisy},
            {"vertical_noise_m", only_noisy}});
  return g;
}

CamPolicy read_cam(Node n) {
  n.expect_object("the CAM policy");
  CamPolicy c;
  const std::string policy = n.required("policy").choice({"etsi", "fixed"});
  c.kind = policy == "fixed" ? CamPolicy::Kind::kFixed : CamPolicy::Kind::kEtsi;
  if (c.kind == CamPolicy::Kind::kFixed) {
    c.period_ms = n.required("period_ms").number(10.0, 10000.0);
  }
  n.finish({{"period_ms", "only with \"policy\": \"fixed\""}});
  return c;
}

/// `security_time_windows`: {"<PSID>": {"past_ms": N, "future_ms": N}, ...}. The bounds are
/// the station's (its-station/security/verifier.hpp kMaxWindowPastMs / kMaxWindowFutureMs).
std::map<std::uint64_t, SecurityTimeWindow> read_security_time_windows(Node n) {
  n.expect_object("the generation-time windows by ITS-AID");
  std::map<std::uint64_t, SecurityTimeWindow> out;
  for (const auto& [key, value] : n.json().items()) {
    Node w = n.required(key);
    std::uint64_t psid = 0;
    const auto [end, ec] = std::from_chars(key.data(), key.data() + key.size(), psid);
    if (ec != std::errc{} || end != key.data() + key.size() || psid > 0xffffffffULL)
      w.fail(
          fmt::format("\"{}\" is not an ITS-AID (a PSID such as \"36\" CAM, \"37\" DENM, "
                      "\"141\" GN-MGMT)",
                      key));
    w.expect_object("a generation-time window");
    SecurityTimeWindow t;
    if (auto p = w.optional("past_ms"))
      t.past_ms = p->integer(0, 600'000);
    if (auto f = w.optional("future_ms"))
      t.future_ms = f->integer(0, 60'000);
    w.finish();
    if (!t.past_ms && !t.future_ms)
      w.fail("give past_ms, future_ms or both");
    out[psid] = t;
  }
  return out;
}

ChannelModel read_channel(Node n) {
  n.expect_object("the channel model");
  ChannelModel c;
  const std::string model =
      n.required("model").choice({"ideal", "range", "log_distance", "two_ray"});
  std::vector<std::pair<std::string, std::string>> why_not;
  auto not_for = [&](std::initializer_list<const char*> keys) {
    for (const char* k : keys)
      why_not.emplace_back(k, "not used by model \"" + model + "\"");
  };
  if (model == "ideal") {
    c.kind = ChannelModel::Kind::kIdeal;
    not_for({"range_m", "tx_power_dbm", "sensitivity_dbm", "reference_loss_db",
             "path_loss_exponent", "antenna_height_m", "frequency_mhz"});
  } else if (model == "range") {
    c.kind = ChannelModel::Kind::kRange;
    c.range_m = n.required("range_m").number(1.0, 100000.0);
    not_for({"tx_power_dbm", "sensitivity_dbm", "reference_loss_db", "path_loss_exponent",
             "antenna_height_m", "frequency_mhz"});
  } else {
    c.tx_power_dbm = n.number_or("tx_power_dbm", c.tx_power_dbm, -30.0, 40.0);
    c.sensitivity_dbm = n.number_or("sensitivity_dbm", c.sensitivity_dbm, -120.0, -30.0);
    c.frequency_mhz = n.number_or("frequency_mhz", c.frequency_mhz, 5000.0, 6000.0);
    if (model == "log_distance") {
      c.kind = ChannelModel::Kind::kLogDistance;
      c.reference_loss_db = n.number_or("reference_loss_db", c.reference_loss_db, 0.0, 120.0);
      c.path_loss_exponent = n.number_or("path_loss_exponent", c.path_loss_exponent, 1.0, 6.0);
      not_for({"range_m", "antenna_height_m"});
    } else {
      c.kind = ChannelModel::Kind::kTwoRay;
      c.antenna_height_m = n.number_or("antenna_height_m", c.antenna_height_m, 0.1, 50.0);
      not_for({"range_m", "reference_loss_db", "path_loss_exponent"});
    }
  }
  c.packet_error_rate = n.number_or("packet_error_rate", 0.0, 0.0, 1.0);
  c.delay_ms = n.number_or("delay_ms", 0.0, 0.0, 1000.0);
  c.jitter_ms = n.number_or("jitter_ms", 0.0, 0.0, 1000.0);
  n.finish(why_not);
  return c;
}

/// `antenna`: the GNSS antenna's place on the vehicle; it must lie within the footprint.
GnssAntenna read_antenna(Node n, const VehicleModel& m) {
  n.expect_object("the GNSS antenna position");
  GnssAntenna a;
  a.forward_m = n.number_or("forward_m", 0.0, -0.5 * m.length_m, 0.5 * m.length_m);
  a.left_m = n.number_or("left_m", 0.0, -0.5 * m.width_m, 0.5 * m.width_m);
  n.finish();
  return a;
}

VehicleModel read_model(Node n) {
  n.expect_object("the vehicle model");
  VehicleModel m;
  m.mass_kg = n.number_or("mass_kg", m.mass_kg, 100.0, 60000.0);
  m.length_m = n.number_or("length_m", m.length_m, 1.0, 25.0);
  m.width_m = n.number_or("width_m", m.width_m, 0.5, 3.0);
  m.height_m = n.number_or("height_m", m.height_m, 0.5, 5.0);
  m.wheelbase_m = n.number_or("wheelbase_m", m.wheelbase_m, 0.5, 20.0);
  m.track_m = n.number_or("track_m", m.track_m, 0.5, 3.0);
  m.wheel_radius_m = n.number_or("wheel_radius_m", m.wheel_radius_m, 0.1, 1.0);
  m.centre_of_mass_height_m =
      n.number_or("centre_of_mass_height_m", m.centre_of_mass_height_m, 0.1, 3.0);
  m.suspension_stiffness = n.number_or("suspension_stiffness", m.suspension_stiffness, 1.0, 500.0);
  m.suspension_damping = n.number_or("suspension_damping", m.suspension_damping, 0.0, 100.0);
  m.suspension_travel_m = n.number_or("suspension_travel_m", m.suspension_travel_m, 0.01, 1.0);
  m.tyre_friction = n.number_or("tyre_friction", m.tyre_friction, 0.05, 3.0);
  if (auto curve = n.optional("torque_curve")) {
    m.torque_curve.clear();
    double last_rpm = -1.0;
    for (Node& p : curve->array(2, 64)) {
      const auto pair = p.array(2, 2);
      TorquePoint t{pair[0].number(0.0, 20000.0), pair[1].number(0.0, 10000.0)};
      if (t.rpm <= last_rpm)
        pair[0].fail("torque curve rpm values must increase");
      last_rpm = t.rpm;
      m.torque_curve.push_back(t);
    }
  }
  if (auto gears = n.optional("gear_ratios")) {
    m.gear_ratios.clear();
    for (Node& g : gears->array(1, 12)) {
      const double r = g.number(0.1, 20.0);
      if (!m.gear_ratios.empty() && r >= m.gear_ratios.back()) {
        g.fail("gear ratios must decrease from first to top gear");
      }
      m.gear_ratios.push_back(r);
    }
  }
  m.reverse_ratio = n.number_or("reverse_ratio", m.reverse_ratio, 0.1, 20.0);
  m.final_drive = n.number_or("final_drive", m.final_drive, 0.5, 20.0);
  m.drivetrain_efficiency = n.number_or("drivetrain_efficiency", m.drivetrain_efficiency, 0.3, 1.0);
  m.idle_rpm = n.number_or("idle_rpm", m.idle_rpm, 100.0, 5000.0);
  m.shift_up_rpm = n.number_or("shift_up_rpm", m.shift_up_rpm, 500.0, 20000.0);
  m.shift_down_rpm = n.number_or("shift_down_rpm", m.shift_down_rpm, 300.0, 20000.0);
  m.brake_torque_nm = n.number_or("brake_torque_nm", m.brake_torque_nm, 0.0, 100000.0);
  m.handbrake_torque_nm = n.number_or("handbrake_torque_nm", m.handbrake_torque_nm, 0.0, 100000.0);
  m.max_steer_deg = n.number_or("max_steer_deg", m.max_steer_deg, 5.0, 60.0);
  m.steering_ratio = n.number_or("steering_ratio", m.steering_ratio, 1.0, 40.0);
  m.drag_coefficient = n.number_or("drag_coefficient", m.drag_coefficient, 0.0, 2.0);
  m.frontal_area_m2 = n.number_or("frontal_area_m2", m.frontal_area_m2, 0.1, 20.0);
  m.rolling_resistance = n.number_or("rolling_resistance", m.rolling_resistance, 0.0, 0.1);
  if (auto a = n.optional("antenna"))
    m.antenna = read_antenna(*a, m);
  n.finish();
  if (m.wheelbase_m >= m.length_m)
    n.fail("wheelbase_m must be shorter than length_m");
  if (m.track_m > m.width_m)
    n.fail("track_m must not exceed width_m");
  if (m.shift_down_rpm >= m.shift_up_rpm)
    n.fail("shift_down_rpm must be below shift_up_rpm");
  return m;
}

/// What spawns are checked against: the scenario's map, and how messages name it.
struct MapContext {
  const MapSpec& spec;
  const map::ScenarioMap& map;
  std::string name;  ///< the OpenDRIVE file as the scenario names it, or "the built-in map"
};

bool on_drivable_lane(const map::ScenarioMap& m, double x, double y) {
  const auto at = m.locator().locate(x, y);
  if (!at)
    return false;
  const auto& road = m.network().roads[static_cast<std::size_t>(at->ref.road)];
  const auto* lane = road.sections[at->section].lane(at->ref.lane);
  return lane != nullptr && lane->drivable;
}

RoadSpawn read_road_spawn(Node& n, const MapContext& m) {
  RoadSpawn r;
  Node road = n.required("road");
  // OpenDRIVE ids are strings; "road": 12 is read as "12".
  r.road = road.json().is_number_integer() ? road.json().dump() : road.string();
  const int index = m.map.network().road_index(r.road);
  if (index < 0)
    road.fail(fmt::format("road \"{}\" does not exist in {}", r.road, m.name));
  const auto& rd = m.map.network().roads[static_cast<std::size_t>(index)];
  Node lane = n.required("lane");
  r.lane = static_cast<int>(lane.integer(-1000, 1000));
  if (r.lane == 0)
    lane.fail(
        "lane 0 is the centre line, not a lane: right lanes are -1, -2, ..., left lanes 1, 2, ...");
  Node s = n.required("s");
  r.s = s.number(0.0, kMaxCoordinate);
  if (r.s > rd.length) {
    s.fail(fmt::format("s {} is past the end of road \"{}\" (length {:.3f} m) in {}", r.s, r.road,
                       rd.length, m.name));
  }
  r.offset = n.number_or("offset", 0.0, -10.0, 10.0);
  if (auto d = n.optional("direction"))
    r.against = d->choice({"with", "against"}) == "against";
  n.finish();
  try {
    m.map.place(r);
  } catch (const map::odr::MapError& e) {
    // The lane is missing at s, or not drivable there (its type, or too narrow).
    lane.fail(e.what());
  }
  return r;
}

Spawn read_spawn(Node n, const MapContext& m) {
  n.expect_object("the spawn point");
  Spawn s;
  s.speed = n.number_or("speed", 0.0, 0.0, kMaxSpeed);
  const bool by_pose = n.has("x") || n.has("y") || n.has("heading_deg");
  if (by_pose) {
    PoseSpawn p;
    p.x = n.required("x").number(-kMaxCoordinate, kMaxCoordinate);
    p.y = n.required("y").number(-kMaxCoordinate, kMaxCoordinate);
    p.heading_deg = n.required("heading_deg").number(0.0, 360.0);
    const std::string why =
        "give either a lane (road, lane, s, ...) or a pose (x, y, heading_deg), not both";
    n.finish({{"lane", why}, {"s", why}, {"road", why}, {"direction", why}, {"offset", why}});
    if (!on_drivable_lane(m.map, p.x, p.y)) {
      n.fail(fmt::format("spawn point ({}, {}) is off the road (on no drivable lane of {})", p.x,
                         p.y, m.name));
    }
    s.where = p;
    return s;
  }
  if (m.spec.type == MapType::kOpenDrive) {
    s.where = read_road_spawn(n, m);
    return s;
  }
  LaneSpawn l;
  const int roads = m.spec.type == MapType::kCrossing ? 2 : 1;
  if (auto r = n.optional("road"))
    l.road = static_cast<int>(r->integer(0, roads - 1));
  l.lane = static_cast<int>(n.required("lane").integer(0, m.spec.lanes - 1));
  // Rings are closed: s wraps. Open roads: the lane's length.
  const double len = m.spec.type == MapType::kRing       ? 1e6
                     : m.spec.type == MapType::kCrossing ? 2.0 * m.spec.arm_length
                                                         : m.spec.length;
  l.s = n.required("s").number(0.0, len);
  if (auto d = n.optional("direction"))
    l.against = d->choice({"with", "against"}) == "against";
  n.finish({{"offset", "only on OpenDRIVE maps (the built-in lanes take lane and s)"}});
  s.where = l;
  return s;
}

// Whether two vehicles' footprints (rectangles of length × width centred on their poses)
// overlap: separating-axis test over the four edge directions. Cars abreast in adjacent lanes,
// or nose to tail with a gap, do not; a centre-distance test refused the first.
bool footprints_overlap(const map::Placement& a, const VehicleModel& ma, const map::Placement& b,
                        const VehicleModel& mb) {
  // Vehicles on different levels (a bridge over a road) do not meet.
  if (std::abs(a.z - b.z) > 3.0)
    return false;
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double ca = std::cos(a.yaw), sa = std::sin(a.yaw);
  const double cb = std::cos(b.yaw), sb = std::sin(b.yaw);
  // Each axis: unit vector (ux, uy); the half extent of a rectangle on it is the sum of its
  // half length and half width projected.
  const double axes[4][2] = {{ca, sa}, {-sa, ca}, {cb, sb}, {-sb, cb}};
  for (const auto& u : axes) {
    const double extent_a = 0.5 * ma.length_m * std::abs(ca * u[0] + sa * u[1]) +
                            0.5 * ma.width_m * std::abs(-sa * u[0] + ca * u[1]);
    const double extent_b = 0.5 * mb.length_m * std::abs(cb * u[0] + sb * u[1]) +
                            0.5 * mb.width_m * std::abs(-sb * u[0] + cb * u[1]);
    if (std::abs(dx * u[0] + dy * u[1]) >= extent_a + extent_b)
      return false;
  }
  return true;
}

// OpenDRIVE road ids are strings; an integer is taken as its decimal text.
std::string road_id(const Node& n) {
  if (n.json().is_number_integer())
    return std::to_string(n.integer(-(1LL << 53), 1LL << 53));
  const std::string id = n.string();
  if (id.empty())
    n.fail("a road id must not be empty");
  return id;
}

DriveRoute read_route(const Node& n) {
  DriveRoute r;
  if (n.is_string()) {
    n.choice({"random"});
    r.kind = DriveRoute::Kind::kRandom;
    return r;
  }
  if (!n.json().is_array())
    n.fail("a route is \"random\" or a list of road ids");
  r.kind = DriveRoute::Kind::kRoads;
  for (const Node& id : n.array(1, 10000))
    r.roads.push_back(road_id(id));
  return r;
}

Driver read_driver(Node n) {
  if (n.is_string()) {
    n.choice({"human"});
    return HumanDriver{};
  }
  n.expect_object("the driver (\"human\" or an object with a \"type\")");
  const std::string type = n.required("type").choice({"human", "timeline", "lane_follow"});
  if (type == "human") {
    n.finish();
    return HumanDriver{};
  }
  if (type == "timeline") {
    TimelineDriver t;
    double last = -1.0;
    for (Node& step : n.required("steps").array(1, 100000)) {
      step.expect_object("a control step");
      ControlStep c;
      c.t = step.required("t").number(0.0, 1e7);
      if (c.t < last)
        step.fail("steps must be in time order (t decreases here)");
      last = c.t;
      c.throttle = step.number_or("throttle", 0.0, 0.0, 1.0);
      c.brake = step.number_or("brake", 0.0, 0.0, 1.0);
      c.steer = step.number_or("steer", 0.0, -1.0, 1.0);
      if (auto r = step.optional("reverse"))
        c.reverse = r->boolean();
      if (auto h = step.optional("handbrake"))
        c.handbrake = h->boolean();
      step.finish();
      t.steps.push_back(c);
    }
    n.finish();
    return t;
  }
  LaneFollowDriver f;
  f.max_accel = n.number_or("max_accel", f.max_accel, 0.1, 10.0);
  f.max_decel = n.number_or("max_decel", f.max_decel, 0.1, 10.0);
  double last = -1.0;
  bool first = true;
  for (Node& p : n.required("speed_profile").array(1, 10000)) {
    p.expect_object("a speed profile point");
    SpeedPoint sp;
    const bool has_t = p.has("t"), has_s = p.has("s");
    if (has_t == has_s)
      p.fail("give exactly one of \"t\" (seconds) or \"s\" (metres)");
    if (first) {
      f.by_distance = has_s;
    } else if (has_s != f.by_distance) {
      p.fail("all points of a speed profile must use the same key, \"t\" or \"s\"");
    }
    sp.at = p.required(has_s ? "s" : "t").number(0.0, 1e7);
    // Negative: reversing along the lane (issue 22).
    sp.speed = p.required("speed").number(-kMaxReverseSpeed, kMaxSpeed);
    p.finish();
    if (sp.at <= last)
      p.fail("speed profile points must be in increasing order");
    last = sp.at;
    first = false;
    f.profile.push_back(sp);
  }
  f.max_lateral_accel = n.number_or("max_lateral_accel", f.max_lateral_accel, 0.5, 10.0);
  if (auto r = n.optional("route"))
    f.route = read_route(*r);
  if (auto t = n.optional("to")) {
    if (f.route.kind != DriveRoute::Kind::kLane)
      t->fail("give either \"route\" or \"to\", not both");
    t->expect_object("a goal (\"road\", \"lane\", \"s\")");
    f.route.kind = DriveRoute::Kind::kTo;
    f.route.to.road = road_id(t->required("road"));
    f.route.to.lane = static_cast<int>(t->required("lane").integer(-100, 100));
    if (f.route.to.lane == 0)
      t->required("lane").fail("lane 0 is the centre line; give a lane id (negative: right)");
    f.route.to.s = t->required("s").number(0.0, 1e7);
    t->finish();
  }
  f.yield_to_traffic = f.route.kind != DriveRoute::Kind::kLane;
  if (auto t = n.optional("traffic"))
    f.yield_to_traffic = t->choice({"yield", "ignore"}) == "yield";
  if (auto o = n.optional("obey_signals"))
    f.obey_signals = o->boolean();
  n.finish();
  return f;
}

/// The "station" object's kind, mqtt, lcrw (issue 33) and signals (issue 34). Pooled stations are
/// station-host's: scripted vehicles on its-station's stack; a human driver needs a full station
/// (its own process beside the driver's window), and a "command" is a stack of its own.
void read_station_kind(Node& st, const Node& vehicle, Vehicle& v) {
  if (auto k = st.optional("kind")) {
    v.station_kind =
        k->choice({"full", "pooled"}) == "pooled" ? StationKind::kPooled : StationKind::kFull;
    if (v.station_kind == StationKind::kPooled) {
      if (std::holds_alternative<HumanDriver>(v.driver)) {
        k->fail(vehicle.has("driver")
                    ? "a vehicle with a \"human\" driver cannot have a \"pooled\" station "
                      "(human-driven vehicles get full stations)"
                    : "a vehicle without a driver is driven by a human and cannot have a "
                      "\"pooled\" station (human-driven vehicles get full stations)");
      }
      if (!v.station_command.empty())
        k->fail("a \"pooled\" station runs its-station's stack, not a \"command\"");
    }
  }
  const bool full = v.station_kind == StationKind::kFull;
  v.station_mqtt = full;
  v.station_lcrw = full;
  v.station_signals = full;
  if (auto mq = st.optional("mqtt"))
    v.station_mqtt = mq->boolean();
  if (auto l = st.optional("lcrw"))
    v.station_lcrw = l->boolean();
  if (auto sg = st.optional("signals"))
    v.station_signals = sg->boolean();
}

Vehicle read_vehicle(Node n, const MapContext& m) {
  n.expect_object("a vehicle");
  Vehicle v;
  v.id = n.required("id").string();
  if (v.id.empty() || v.id.size() > 64 ||
      v.id.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") !=
          std::string::npos) {
    n.required("id").fail("vehicle id \"" + v.id +
                          "\" must be 1 to 64 letters, digits, '_' or '-'");
  }
  v.station_id = static_cast<std::uint32_t>(n.required("station_id").integer(0, 4294967295LL));
  if (auto t = n.optional("station_type"))
    v.station_type = static_cast<int>(t->integer(0, 255));
  if (auto c = n.optional("color")) {
    v.color = c->string();
    if (v.color.size() != 7 || v.color[0] != '#' ||
        v.color.find_first_not_of("0123456789abcdefABCDEF", 1) != std::string::npos) {
      c->fail("colour \"" + v.color + "\" must look like \"#rrggbb\"");
    }
  }
  if (auto m = n.optional("model"))
    v.model = read_model(*m);
  v.spawn = read_spawn(n.required("spawn"), m);
  v.driver = n.optional("driver") ? read_driver(n.required("driver")) : Driver{HumanDriver{}};
  if (auto r = n.optional("role")) {
    // CDD VehicleRole names, in the order of their values (reserved1..3 are not roles).
    static constexpr std::string_view kRoles[] = {
        "default",     "publicTransport", "specialTransport", "dangerousGoods",
        "roadWork",    "rescue",          "emergency",        "safetyCar",
        "agriculture", "commercial",      "military",         "roadOperator",
        "taxi"};
    const std::string name =
        r->choice({kRoles[0], kRoles[1], kRoles[2], kRoles[3], kRoles[4], kRoles[5], kRoles[6],
                   kRoles[7], kRoles[8], kRoles[9], kRoles[10], kRoles[11], kRoles[12]});
    v.role = static_cast<VehicleRole>(std::find(std::begin(kRoles), std::end(kRoles), name) -
                                      std::begin(kRoles));
  }
  if (auto g = n.optional("dangerous_goods")) {
    if (v.role != VehicleRole::kDangerousGoods)
      g->fail("\"dangerous_goods\" is only for a vehicle with \"role\": \"dangerousGoods\"");
    static constexpr std::string_view kGoods[] = {
        "explosives1",
        "explosives2",
        "explosives3",
        "explosives4",
        "explosives5",
        "explosives6",
        "flammableGases",
        "nonFlammableGases",
        "toxicGases",
        "flammableLiquids",
        "flammableSolids",
        "substancesLiableToSpontaneousCombustion",
        "substancesEmittingFlammableGasesUponContactWithWater",
        "oxidizingSubstances",
        "organicPeroxides",
        "toxicSubstances",
        "infectiousSubstances",
        "radioactiveMaterial",
        "corrosiveSubstances",
        "miscellaneousDangerousSubstances"};
    const std::string name = g->string();
    const auto* it = std::find(std::begin(kGoods), std::end(kGoods), name);
    if (it == std::end(kGoods))
      g->fail(
          "\"" + name +
          "\" is not a CDD DangerousGoodsBasic (explosives1 … miscellaneousDangerousSubstances, "
          "docs/scenario.md)");
    v.dangerous_goods = static_cast<int>(it - std::begin(kGoods));
  } else if (v.role == VehicleRole::kDangerousGoods) {
    n.required("dangerous_goods");  // names the missing field
  }
  if (auto l = n.optional("lights")) {
    for (const Node& e : l->array(0, 16)) {
      const std::string name = e.choice({"low_beam", "high_beam", "fog", "parking",
                                         "daytime_running", "hazard", "light_bar", "siren"});
      const std::uint16_t bit = name == "low_beam"          ? wire::kLowBeam
                                : name == "high_beam"       ? wire::kHighBeam
                                : name == "fog"             ? wire::kFogLight
                                : name == "parking"         ? wire::kParkingLights
                                : name == "daytime_running" ? wire::kDaytimeRunning
                                : name == "hazard"          ? wire::kHazard
                                : name == "light_bar"       ? wire::kLightBar
                                                            : wire::kSiren;
      if (v.lights & bit)
        e.fail("\"" + name + "\" is listed twice");
      v.lights |= bit;
    }
  }
  if (auto st = n.optional("station")) {
    st->expect_object(
        "a station (\"command\": the program and its arguments, \"pki\": a test PKI's name, "
        "\"kind\": \"full\" or \"pooled\", \"mqtt\", \"lcrw\", \"signals\")");
    if (auto cmd = st->optional("command")) {
      for (const Node& a : cmd->array(1, 256)) {
        v.station_command.push_back(a.string());
        if (v.station_command.size() == 1 && v.station_command[0].empty())
          a.fail("the program to run must not be empty");
      }
    }
    if (auto pki = st->optional("pki")) {
      v.station_pki = pki->string();
      if (v.station_pki.empty() || v.station_pki.size() > 64 ||
          v.station_pki.find_first_not_of(
              "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") !=
              std::string::npos)
        pki->fail("PKI name \"" + v.station_pki + "\" must be 1 to 64 letters, digits, '_' or '-'");
    }
    read_station_kind(*st, n, v);
    st->finish();
  }
  n.finish();
  return v;
}

// Every route must be drivable from its vehicle's spawn lane: the plan is made as the driver
// will make it, and its errors name the driver's field.
void check_routes(const Scenario& s, const map::ScenarioMap& m, const std::vector<Node>& nodes) {
  for (std::size_t i = 0; i < s.vehicles.size(); ++i) {
    const Vehicle& v = s.vehicles[i];
    const auto* f = std::get_if<LaneFollowDriver>(&v.driver);
    if (f == nullptr || f->route.kind == DriveRoute::Kind::kLane)
      continue;
    const std::string driver = nodes[i].path() + "/driver";
    const auto start = map::vehicle_start(v, m);
    if (!start) {
      throw ScenarioError(s.source, nodes[i].path() + "/spawn",
                          "a vehicle with a route must spawn on a drivable lane");
    }
    try {
      map::RoutePlan plan(m.network(), m.graph(), f->route, *start,
                          map::vehicle_seed(s.seed, v.station_id));
    } catch (const map::RouteError& e) {
      throw ScenarioError(s.source, e.field().empty() ? driver : driver + "/" + e.field(),
                          e.what());
    }
  }
}

/// The scenario's road network: the OpenDRIVE file (or @p map_text in its place) read and
/// checked, or the built-in layout generated.
void load_network(Scenario& s, Node& root, const std::string& file_name,
                  std::optional<std::string_view> map_text) {
  if (s.map.type != MapType::kOpenDrive) {
    s.network = std::make_shared<const map::odr::RoadNetwork>(map::generate_network(s.map));
    return;
  }
  Node file = root.required("map").required("file");
  const std::filesystem::path path =
      (std::filesystem::path(file_name).parent_path() / s.map.file).lexically_normal();
  std::string text;
  if (map_text) {
    text = *map_text;
  } else {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) {
      file.fail(fmt::format("{}: {} (looked for {})", s.map.file,
                            std::filesystem::exists(path) ? "cannot be read" : "no such file",
                            path.string()));
    }
    if (size > kMaxMapBytes) {
      file.fail(fmt::format("{}: {} bytes, more than the {} MiB a map may have", s.map.file, size,
                            kMaxMapBytes >> 20));
    }
    std::ifstream in(path, std::ios::binary);
    std::ostringstream buf;
    buf << in.rdbuf();
    if (!in)
      file.fail(fmt::format("{}: cannot be read (looked for {})", s.map.file, path.string()));
    text = buf.str();
  }
  if (text.size() > kMaxMapBytes) {
    file.fail(fmt::format("{}: {} bytes, more than the {} MiB a map may have", s.map.file,
                          text.size(), kMaxMapBytes >> 20));
  }
  try {
    s.network = std::make_shared<const map::odr::RoadNetwork>(
        map::odr::parse_opendrive(text, map_text ? s.map.file : path.string()));
  } catch (const map::odr::MapError& e) {
    file.fail(e.what());
  }
  s.map_text = std::make_shared<const std::string>(std::move(text));
}

}  // namespace

Scenario parse(std::string_view json_text, const std::string& file_name,
               std::optional<std::string_view> map_text) {
  const json doc = parse_text(json_text, file_name);
  Node root(doc, "", file_name);
  root.expect_object("a scenario");
  Scenario s;
  s.source = file_name;
  s.name = root.required("name").string();
  if (s.name.empty())
    root.required("name").fail("the name must not be empty");
  if (auto d = root.optional("description"))
    s.description = d->string();
  s.map = read_map(root.required("map"));
  load_network(s, root, file_name, map_text);
  const bool georeferenced = !s.network->header.geo_reference.empty();
  if (root.has("origin") || !georeferenced) {
    if (!root.has("origin") && s.map.type == MapType::kOpenDrive) {
      throw ScenarioError(file_name, "/origin",
                          fmt::format("missing required field \"origin\": the map {} has no "
                                      "geoReference, so the origin must place its (0, 0, 0) on "
                                      "the Earth",
                                      s.map.file));
    }
    s.origin = read_origin(root.required("origin"));
  }
  if (root.optional("start_time"))
    s.start_time = parse_utc(root.required("start_time"));
  if (auto d = root.optional("duration_s"))
    s.duration_s = d->number(0.1, 7 * 86400.0);
  if (auto w = root.optional("warmup_s"))
    s.warmup_s = w->number(0.0, kMaxWarmupS);
  // The warm-up's fixes are dated start_time + a negative sim time: they must not fall before
  // the ITS epoch, which TimestampIts (and a CAM's generationDeltaTime) cannot express.
  if (s.start_time &&
      *s.start_time - std::chrono::duration_cast<std::chrono::system_clock::duration>(
                          std::chrono::duration<double>(s.warmup_s)) <
          std::chrono::system_clock::time_point{std::chrono::seconds{kItsEpochUnixS}}) {
    root.required("start_time")
        .fail(fmt::format("sim time -{} s (the warm-up, warmup_s) falls before the ITS epoch "
                          "2004-01-01T00:00:00Z: start later",
                          s.warmup_s));
  }
  if (auto r = root.optional("rates"))
    s.rates = read_rates(*r);
  if (auto g = root.optional("gnss"))
    s.gnss = read_gnss(*g);
  if (auto c = root.optional("cam"))
    s.cam = read_cam(*c);
  if (auto c = root.optional("channel"))
    s.channel = read_channel(*c);
  if (auto sec = root.optional("security")) {
    const std::string m = sec->string();
    if (m == "none")
      s.security = SecurityMode::kNone;
    else if (m == "signed")
      s.security = SecurityMode::kSigned;
    else if (m == "signed-permissive")
      s.security = SecurityMode::kSignedPermissive;
    else
      sec->fail(fmt::format("\"{}\" is not one of \"none\", \"signed\", \"signed-permissive\"", m));
  }

  if (auto w = root.optional("security_time_windows"))
    s.security_time_windows = read_security_time_windows(*w);

  if (auto seed = root.optional("seed"))
    s.seed = static_cast<std::uint64_t>(seed->integer(0, (1LL << 53) - 1));

  std::unique_ptr<map::ScenarioMap> scenario_map;
  try {
    scenario_map = std::make_unique<map::ScenarioMap>(s);
  } catch (const map::odr::MapError& e) {
    // The geoReference PROJ cannot read.
    throw ScenarioError(file_name, "/map/file", e.what());
  }
  const MapContext context{
      s.map, *scenario_map,
      s.map.type == MapType::kOpenDrive ? s.map.file : std::string("the built-in map")};
  std::unordered_map<std::string, std::size_t> ids;
  std::unordered_map<std::uint32_t, std::size_t> stations;
  std::vector<map::Placement> poses;
  const auto vehicles = root.required("vehicles").array(1, kMaxVehicles);
  for (std::size_t i = 0; i < vehicles.size(); ++i) {
    Vehicle v = read_vehicle(vehicles[i], context);
    if (const auto [it, fresh] = ids.emplace(v.id, i); !fresh) {
      Node(vehicles[i].json()["id"], vehicles[i].path() + "/id", file_name)
          .fail(fmt::format("duplicate vehicle id \"{}\" (also /vehicles/{})", v.id, it->second));
    }
    if (const auto [it, fresh] = stations.emplace(v.station_id, i); !fresh) {
      Node(vehicles[i].json()["station_id"], vehicles[i].path() + "/station_id", file_name)
          .fail(
              fmt::format("duplicate station_id {} (also /vehicles/{})", v.station_id, it->second));
    }
    const map::Placement pose = scenario_map->place(v.spawn);
    for (std::size_t j = 0; j < poses.size(); ++j) {
      if (footprints_overlap(pose, v.model, poses[j], s.vehicles[j].model)) {
        const double gap = std::hypot(pose.x - poses[j].x, pose.y - poses[j].y);
        Node(vehicles[i].json()["spawn"], vehicles[i].path() + "/spawn", file_name)
            .fail(fmt::format("vehicle \"{}\" would spawn {:.1f} m from \"{}\", its footprint "
                              "overlapping that one's",
                              v.id, gap, s.vehicles[j].id));
      }
    }
    poses.push_back(pose);
    s.vehicles.push_back(std::move(v));
  }
  check_routes(s, *scenario_map, vehicles);
  s.signals =
      detail::read_signal_plans(root.optional("signals"), *scenario_map, context.name, file_name);
  s.rsus = detail::read_rsus(root.optional("rsus"), s, *scenario_map, context.name, vehicles);
  root.finish();
  return s;
}

Scenario load_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    const bool exists = std::filesystem::exists(file);
    throw ScenarioError(file.string(), "",
                        exists ? "cannot be read (permissions?)" : "no such file");
  }
  std::ostringstream text;
  text << in.rdbuf();
  return parse(text.str(), file.string());
}

}  // namespace tb::scenario
