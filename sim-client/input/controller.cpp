#include "sim-client/input/controller.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

namespace tb::client {
namespace {

using nlohmann::json;

constexpr int kMaxAxes = 64;
constexpr int kMaxButtons = 256;

constexpr std::array<std::string_view, 6> kAxisNames{"leftx",  "lefty",       "rightx",
                                                     "righty", "triggerleft", "triggerright"};
constexpr std::array<std::string_view, 15> kButtonNames{"a",
                                                        "b",
                                                        "x",
                                                        "y",
                                                        "back",
                                                        "guide",
                                                        "start",
                                                        "leftstick",
                                                        "rightstick",
                                                        "leftshoulder",
                                                        "rightshoulder",
                                                        "dpup",
                                                        "dpdown",
                                                        "dpleft",
                                                        "dpright"};
constexpr std::array<std::string_view, kActionCount> kActionNames{
    "reverse", "handbrake", "indicator_left", "indicator_right",
    "hazard",  "low_beam",  "high_beam",      "fog"};

class Reader {
 public:
  Reader(const std::string& file) : file_(file) {}

  [[noreturn]] void fail(const std::string& field, const std::string& reason) const {
    throw MappingError(file_, field, reason);
  }

  const json& object(const json& j, const std::string& field) const {
    if (!j.is_object())
      fail(field, "must be an object");
    return j;
  }
  void only(const json& j, const std::string& field,
            std::initializer_list<std::string_view> keys) const {
    for (const auto& [k, v] : j.items()) {
      if (std::find(keys.begin(), keys.end(), k) == keys.end())
        fail(field + "/" + k, "unknown field");
    }
  }
  double number(const json& j, const std::string& field, double lo, double hi) const {
    if (!j.is_number())
      fail(field, "must be a number");
    const double v = j.get<double>();
    if (!std::isfinite(v) || v < lo || v > hi) {
      std::ostringstream os;
      os << "value " << j.dump() << " is outside [" << lo << ", " << hi << "]";
      fail(field, os.str());
    }
    return v;
  }
  bool boolean(const json& j, const std::string& field) const {
    if (!j.is_boolean())
      fail(field, "must be true or false");
    return j.get<bool>();
  }
  std::string string(const json& j, const std::string& field) const {
    if (!j.is_string())
      fail(field, "must be a string");
    return j.get<std::string>();
  }
  // An axis or button: a name for the GameController API, an index for the Joystick API.
  int control(const json& j, const std::string& field, ControllerApi api, bool is_axis) const {
    if (api == ControllerApi::kGameController) {
      if (!j.is_string())
        fail(field, std::string("must be a GameController ") + (is_axis ? "axis" : "button") +
                        " name (the mapping's api is \"gamecontroller\")");
      const std::string name = j.get<std::string>();
      const auto v = is_axis ? game_controller_axis(name) : game_controller_button(name);
      if (!v) {
        std::string known;
        if (is_axis) {
          for (auto n : kAxisNames)
            known += (known.empty() ? "" : ", ") + std::string(n);
        } else {
          for (auto n : kButtonNames)
            known += (known.empty() ? "" : ", ") + std::string(n);
        }
        fail(field, "unknown " + std::string(is_axis ? "axis" : "button") + " \"" + name +
                        "\" (one of " + known + ")");
      }
      return *v;
    }
    if (!j.is_number_integer())
      fail(field, std::string("must be an ") + (is_axis ? "axis" : "button") +
                      " index (the mapping's api is \"joystick\")");
    const auto v = j.get<long long>();
    const int limit = is_axis ? kMaxAxes : kMaxButtons;
    if (v < 0 || v >= limit)
      fail(field,
           "index " + std::to_string(v) + " is outside [0, " + std::to_string(limit - 1) + "]");
    return static_cast<int>(v);
  }

 private:
  std::string file_;
};

PedalAxis read_pedal(const Reader& r, const json& root, const std::string& key, ControllerApi api) {
  const std::string f = "/" + key;
  if (!root.contains(key))
    r.fail(f, "missing (every mapping needs steer, throttle and brake)");
  const json& j = r.object(root.at(key), f);
  r.only(j, f, {"axis", "released", "pressed", "dead_zone"});
  PedalAxis p;
  if (!j.contains("axis"))
    r.fail(f + "/axis", "missing");
  p.axis = r.control(j.at("axis"), f + "/axis", api, true);
  if (j.contains("released"))
    p.released = r.number(j.at("released"), f + "/released", -1.0, 1.0);
  if (j.contains("pressed"))
    p.pressed = r.number(j.at("pressed"), f + "/pressed", -1.0, 1.0);
  if (std::abs(p.pressed - p.released) < 0.1)
    r.fail(f + "/pressed", "must differ from \"released\" by at least 0.1 (the pedal's travel)");
  if (j.contains("dead_zone"))
    p.dead_zone = r.number(j.at("dead_zone"), f + "/dead_zone", 0.0, 0.5);
  return p;
}

double apply_dead_zone(double v, double dz) {
  const double a = std::abs(v);
  if (a <= dz)
    return 0.0;
  return std::copysign((a - dz) / (1.0 - dz), v);
}

}  // namespace

MappingError::MappingError(std::string file, std::string field, std::string reason)
    : std::runtime_error(file + ": " + (field.empty() ? std::string("/") : field) + ": " + reason),
      file_(std::move(file)),
      field_(std::move(field)) {}

std::string_view to_string(Action a) {
  return kActionNames[static_cast<std::size_t>(a)];
}

std::optional<int> game_controller_axis(std::string_view name) {
  for (std::size_t i = 0; i < kAxisNames.size(); ++i) {
    if (kAxisNames[i] == name)
      return static_cast<int>(i);
  }
  return std::nullopt;
}

std::optional<int> game_controller_button(std::string_view name) {
  for (std::size_t i = 0; i < kButtonNames.size(); ++i) {
    if (kButtonNames[i] == name)
      return static_cast<int>(i);
  }
  return std::nullopt;
}

ControllerMapping parse_mapping(std::string_view text, const std::string& file) {
  const Reader r(file);
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    r.fail("", std::string("not valid JSON: ") + e.what());
  }
  r.object(root, "");
  r.only(root, "", {"name", "api", "device", "steer", "throttle", "brake", "buttons"});
  ControllerMapping m;
  m.source = file;
  if (root.contains("name"))
    m.name = r.string(root.at("name"), "/name");
  if (!root.contains("api"))
    r.fail("/api", "missing (\"gamecontroller\" or \"joystick\")");
  const std::string api = r.string(root.at("api"), "/api");
  if (api == "gamecontroller") {
    m.api = ControllerApi::kGameController;
  } else if (api == "joystick") {
    m.api = ControllerApi::kJoystick;
  } else {
    r.fail("/api", "\"" + api + "\" is neither \"gamecontroller\" nor \"joystick\"");
  }
  if (root.contains("device"))
    m.device = r.string(root.at("device"), "/device");

  if (!root.contains("steer"))
    r.fail("/steer", "missing (every mapping needs steer, throttle and brake)");
  const json& s = r.object(root.at("steer"), "/steer");
  r.only(s, "/steer", {"axis", "invert", "dead_zone", "curve", "gain"});
  if (!s.contains("axis"))
    r.fail("/steer/axis", "missing");
  m.steer.axis = r.control(s.at("axis"), "/steer/axis", m.api, true);
  if (s.contains("invert"))
    m.steer.invert = r.boolean(s.at("invert"), "/steer/invert");
  if (s.contains("dead_zone"))
    m.steer.dead_zone = r.number(s.at("dead_zone"), "/steer/dead_zone", 0.0, 0.5);
  if (s.contains("curve")) {
    const std::string c = r.string(s.at("curve"), "/steer/curve");
    if (c == "linear") {
      m.steer.curve = SteerAxis::Curve::kLinear;
    } else if (c == "tan") {
      m.steer.curve = SteerAxis::Curve::kTan;
    } else {
      r.fail("/steer/curve", "\"" + c + "\" is neither \"linear\" nor \"tan\"");
    }
  }
  if (s.contains("gain"))
    m.steer.gain = r.number(s.at("gain"), "/steer/gain", 0.01, 10.0);

  m.throttle = read_pedal(r, root, "throttle", m.api);
  m.brake = read_pedal(r, root, "brake", m.api);

  if (root.contains("buttons")) {
    const json& b = r.object(root.at("buttons"), "/buttons");
    for (const auto& [key, value] : b.items()) {
      const auto it = std::find(kActionNames.begin(), kActionNames.end(), key);
      if (it == kActionNames.end()) {
        std::string known;
        for (auto n : kActionNames)
          known += (known.empty() ? "" : ", ") + std::string(n);
        r.fail("/buttons/" + key, "unknown action (one of " + known + ")");
      }
      m.buttons[static_cast<std::size_t>(it - kActionNames.begin())] =
          r.control(value, "/buttons/" + key, m.api, false);
    }
  }
  return m;
}

ControllerMapping load_mapping(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw MappingError(file.string(), "", "cannot open the mapping file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_mapping(text.str(), file.string());
}

ControllerDriver::ControllerDriver(ControllerMapping mapping)
    : mapping_(std::move(mapping)), axes_(kMaxAxes), buttons_(kMaxButtons, false) {}

void ControllerDriver::connect(std::string device_name) {
  connected_ = true;
  device_ = std::move(device_name);
  std::fill(axes_.begin(), axes_.end(), Reading{});
  std::fill(buttons_.begin(), buttons_.end(), false);
}

void ControllerDriver::disconnect() {
  connected_ = false;
  device_.clear();
}

void ControllerDriver::axis(int index, double value) {
  if (index < 0 || index >= kMaxAxes || !std::isfinite(value))
    return;
  axes_[index] = Reading{std::clamp(value, -1.0, 1.0), true};
}

void ControllerDriver::button(int index, bool down) {
  if (index < 0 || index >= kMaxButtons)
    return;
  const bool was = buttons_[index];
  buttons_[index] = down;
  if (!down || was)
    return;
  const auto is = [&](Action a) { return mapping_.buttons[static_cast<std::size_t>(a)] == index; };
  if (is(Action::kReverse))
    reverse_ = !reverse_;
  if (is(Action::kIndicatorLeft))
    toggle_light(lights_, wire::kIndicatorLeft);
  if (is(Action::kIndicatorRight))
    toggle_light(lights_, wire::kIndicatorRight);
  if (is(Action::kHazard))
    toggle_light(lights_, wire::kHazard);
  if (is(Action::kLowBeam))
    toggle_light(lights_, wire::kLowBeam);
  if (is(Action::kHighBeam))
    toggle_light(lights_, wire::kHighBeam);
  if (is(Action::kFog))
    toggle_light(lights_, wire::kFogLight);
}

// Many wheels report 0 on every axis until a pedal first moves, which on pedals whose rest is
// ±1 would read as half throttle: a pedal counts as released until its axis has moved.
double ControllerDriver::pedal(const PedalAxis& p) const {
  const Reading& r = axes_[p.axis];
  if (!r.seen)
    return 0.0;
  const double travel = std::clamp((r.value - p.released) / (p.pressed - p.released), 0.0, 1.0);
  return std::max(apply_dead_zone(travel, p.dead_zone), 0.0);
}

DriverCommand ControllerDriver::command() const {
  DriverCommand c;
  c.lights = lights_;
  c.controls.reverse = reverse_;
  if (!connected_) {
    c.controls.brake = kUnpluggedBrake;
    return c;
  }
  double v = apply_dead_zone(axes_[mapping_.steer.axis].value, mapping_.steer.dead_zone);
  if (mapping_.steer.invert)
    v = -v;
  const double steer = mapping_.steer.curve == SteerAxis::Curve::kTan
                           ? mapping_.steer.gain * std::tan(1.1 * v)
                           : mapping_.steer.gain * v;
  c.controls.steer = static_cast<float>(std::clamp(steer, -1.0, 1.0));
  c.controls.throttle = static_cast<float>(pedal(mapping_.throttle));
  c.controls.brake = static_cast<float>(pedal(mapping_.brake));
  if (const auto hb = mapping_.buttons[static_cast<std::size_t>(Action::kHandbrake)])
    c.controls.handbrake = buttons_[*hb];
  return c;
}

}  // namespace tb::client
