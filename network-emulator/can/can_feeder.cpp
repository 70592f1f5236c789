#include "network-emulator/can/can_feeder.hpp"

#include <cmath>
#include <numbers>
#include <utility>

#include <fmt/format.h>

#include "common/can/checksum.hpp"

namespace tb::emu::can {

using tb::wire::VehicleState;

std::string_view to_string(FeederErrc e) {
  switch (e) {
    case FeederErrc::kUnknownSignal:
      return "signal has no source in the vehicle state";
    case FeederErrc::kNoCycleTime:
      return "message has no GenMsgCycleTime";
    case FeederErrc::kBadChecksumSignal:
      return "Checksum must be one whole byte";
    case FeederErrc::kBadRate:
      return "CAN rate must be positive";
  }
  return "unknown feeder error";
}

std::string FeederError::message() const {
  return fmt::format("{}: {}", to_string(code), detail);
}

namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr double kStandstill = 0.05;  // m/s
constexpr std::int64_t kDynamicsBelowNs = 100'000'000;

bool light(const VehicleState& s, std::uint16_t bit) {
  return (s.lights & bit) != 0;
}

struct NamedSource {
  std::string_view name;
  double (*fn)(const VehicleState&, const FeederConfig&);
};

// Signs: the wire state's yaw rate, lateral acceleration and road-wheel angle are positive to
// the left, which is also the DBC's convention (see the CM_ in vehicle.dbc).
constexpr NamedSource kSources[] = {
    {"VehicleSpeed",
     [](const VehicleState& s, const FeederConfig&) { return std::abs(double{s.speed}) * 3.6; }},
    {"DrivingDirection",
     [](const VehicleState& s, const FeederConfig&) {
       return s.speed > kStandstill ? 1.0 : s.speed < -kStandstill ? 2.0 : 0.0;
     }},
    {"WheelSpeedFL", [](const VehicleState& s,
                        const FeederConfig&) { return std::abs(double{s.wheel_speeds[0]}) * 3.6; }},
    {"WheelSpeedFR", [](const VehicleState& s,
                        const FeederConfig&) { return std::abs(double{s.wheel_speeds[1]}) * 3.6; }},
    {"WheelSpeedRL", [](const VehicleState& s,
                        const FeederConfig&) { return std::abs(double{s.wheel_speeds[2]}) * 3.6; }},
    {"WheelSpeedRR", [](const VehicleState& s,
                        const FeederConfig&) { return std::abs(double{s.wheel_speeds[3]}) * 3.6; }},
    {"YawRate",
     [](const VehicleState& s, const FeederConfig&) { return double{s.yaw_rate} * kRadToDeg; }},
    {"LongitudinalAcceleration",
     [](const VehicleState& s, const FeederConfig&) { return double{s.acceleration[0]}; }},
    {"LateralAcceleration",
     [](const VehicleState& s, const FeederConfig&) { return double{s.acceleration[1]}; }},
    {"SteeringWheelAngle",
     [](const VehicleState& s, const FeederConfig& c) {
       return double{s.steering_angle} * c.steering_ratio * kRadToDeg;
     }},
    {"ThrottlePedal", [](const VehicleState& s,
                         const FeederConfig&) { return double{s.controls.throttle} * 100.0; }},
    {"BrakePedal",
     [](const VehicleState& s, const FeederConfig&) { return double{s.controls.brake} * 100.0; }},
    {"Gear",
     [](const VehicleState& s, const FeederConfig&) { return static_cast<double>(s.gear); }},
    {"Handbrake",
     [](const VehicleState& s, const FeederConfig&) { return s.controls.handbrake ? 1.0 : 0.0; }},
    {"EngineSpeed",
     [](const VehicleState& s, const FeederConfig&) { return double{s.engine_rpm}; }},
    // Hazard lights flash both indicators, as the indicator lamps of a real car do.
    {"IndicatorLeft",
     [](const VehicleState& s, const FeederConfig&) {
       return light(s, wire::kIndicatorLeft) || light(s, wire::kHazard) ? 1.0 : 0.0;
     }},
    {"IndicatorRight",
     [](const VehicleState& s, const FeederConfig&) {
       return light(s, wire::kIndicatorRight) || light(s, wire::kHazard) ? 1.0 : 0.0;
     }},
    {"HazardLights", [](const VehicleState& s,
                        const FeederConfig&) { return light(s, wire::kHazard) ? 1.0 : 0.0; }},
    {"BrakeLights", [](const VehicleState& s,
                       const FeederConfig&) { return light(s, wire::kBrakeLights) ? 1.0 : 0.0; }},
    {"LowBeam", [](const VehicleState& s,
                   const FeederConfig&) { return light(s, wire::kLowBeam) ? 1.0 : 0.0; }},
    {"HighBeam", [](const VehicleState& s,
                    const FeederConfig&) { return light(s, wire::kHighBeam) ? 1.0 : 0.0; }},
    {"ReverseLight", [](const VehicleState& s,
                        const FeederConfig&) { return light(s, wire::kReverseLight) ? 1.0 : 0.0; }},
    {"FogLight", [](const VehicleState& s,
                    const FeederConfig&) { return light(s, wire::kFogLight) ? 1.0 : 0.0; }},
};

constexpr std::string_view kAliveCounter = "AliveCounter";
constexpr std::string_view kChecksum = "Checksum";

}  // namespace

std::span<const std::string_view> known_signals() {
  static const std::vector<std::string_view> names = [] {
    std::vector<std::string_view> v;
    for (const auto& s : kSources)
      v.push_back(s.name);
    v.push_back(kAliveCounter);
    v.push_back(kChecksum);
    return v;
  }();
  return names;
}

Expected<CanFeeder, FeederError> CanFeeder::create(const tb::can::Database& db,
                                                   const FeederConfig& config) {
  if (!(config.dynamics_hz > 0) || !(config.body_hz > 0))
    return Unexpected{
        FeederError{FeederErrc::kBadRate,
                    fmt::format("dynamics {} Hz, body {} Hz", config.dynamics_hz, config.body_hz)}};
  CanFeeder f;
  f.config_ = config;
  for (const tb::can::Message& m : db.messages) {
    if (!m.cycle_time_ms || *m.cycle_time_ms == 0)
      return Unexpected{FeederError{FeederErrc::kNoCycleTime, fmt::format("message '{}'", m.name)}};
    Schedule s;
    s.message = &m;
    const bool dynamics = std::int64_t{*m.cycle_time_ms} * 1'000'000 < kDynamicsBelowNs;
    s.period_ns = static_cast<std::int64_t>(
        std::llround(1e9 / (dynamics ? config.dynamics_hz : config.body_hz)));
    for (const tb::can::Signal& sig : m.signals) {
      if (sig.name == kAliveCounter) {
        s.counter = &sig;
      } else if (sig.name == kChecksum) {
        if (sig.length != 8 || sig.start_bit % 8 != 0 ||
            sig.byte_order != tb::can::ByteOrder::kIntel)
          return Unexpected{
              FeederError{FeederErrc::kBadChecksumSignal,
                          fmt::format("message '{}': {}|{}", m.name, sig.start_bit, sig.length)}};
        s.checksum = &sig;
      } else {
        const NamedSource* src = nullptr;
        for (const auto& k : kSources)
          if (k.name == sig.name)
            src = &k;
        if (!src)
          return Unexpected{
              FeederError{FeederErrc::kUnknownSignal,
                          fmt::format("message '{}', signal '{}'", m.name, sig.name)}};
        s.fields.push_back({&sig, src->fn});
      }
    }
    f.schedules_.push_back(std::move(s));
  }
  f.due_.reserve(f.schedules_.size());
  return f;
}

std::int64_t CanFeeder::period_ns(std::string_view message) const {
  for (const Schedule& s : schedules_)
    if (s.message->name == message)
      return s.period_ns;
  return 0;
}

void CanFeeder::encode(Schedule& s, const VehicleState& state, tb::can::CanFrame& out) {
  const tb::can::Message& m = *s.message;
  out = tb::can::CanFrame{};
  out.can_id = m.extended ? (m.id | tb::can::kEffFlag) : m.id;
  out.len = static_cast<std::uint8_t>(m.dlc);
  out.fd = m.dlc > tb::can::kMaxClassicLen;
  const std::span<std::uint8_t> data(out.data.data(), m.dlc);
  for (const Field& f : s.fields)
    f.signal->encode(f.source(state, config_), data);
  if (s.counter) {
    s.counter->insert_raw(s.alive, data);
    s.alive = static_cast<std::uint8_t>((s.alive + 1) % (s.counter->raw_max() + 1));
  }
  if (s.checksum) {
    // CRC over every byte but the checksum's own, in byte order (vehicle.dbc, CM_).
    const unsigned at = s.checksum->start_bit / 8;
    std::array<std::uint8_t, tb::can::kMaxFdLen> rest{};
    std::size_t n = 0;
    for (unsigned i = 0; i < m.dlc; ++i)
      if (i != at)
        rest[n++] = data[i];
    data[at] = tb::can::crc8_sae_j1850({rest.data(), n});
  }
}

std::span<const tb::can::CanFrame> CanFeeder::on_state(const VehicleState& state) {
  due_.clear();
  const std::int64_t t = state.sim_time_ns;
  for (Schedule& s : schedules_) {
    if (s.next_due_ns && t < *s.next_due_ns)
      continue;
    const std::int64_t floor_t =
        (t >= 0 ? t / s.period_ns : (t - s.period_ns + 1) / s.period_ns) * s.period_ns;
    s.next_due_ns = floor_t + s.period_ns;
    encode(s, state, due_.emplace_back());
  }
  frames_total_ += due_.size();
  return due_;
}

}  // namespace tb::emu::can
