#include "network-emulator/can/can_feeder.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <numbers>
#include <stdexcept>
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
    {"LightBar", [](const VehicleState& s,
                    const FeederConfig&) { return light(s, wire::kLightBar) ? 1.0 : 0.0; }},
    {"Siren",
     [](const VehicleState& s, const FeederConfig&) { return light(s, wire::kSiren) ? 1.0 : 0.0; }},
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

SignalPlan::SignalPlan(const tb::can::Signal& signal, std::size_t dlc)
    : clamp_(signal.minimum < signal.maximum),
      minimum_(signal.minimum),
      maximum_(signal.maximum),
      offset_(signal.offset),
      factor_(signal.factor),
      lo_(signal.raw_min()),
      hi_(signal.raw_max()),
      lo_d_(static_cast<double>(lo_)),
      hi_d_(static_cast<double>(hi_)) {
  // Where raw bit i lands: ask the codec itself with a raw value of 1 << i, so that the byte
  // order rules live in one place (common/can/dbc.cpp).
  std::array<std::uint8_t, tb::can::kMaxFdLen> probe{};
  const std::span<std::uint8_t> frame(probe.data(), std::min(dlc, probe.size()));
  for (unsigned i = 0; i < signal.length && i < 64; ++i) {
    std::fill(frame.begin(), frame.end(), std::uint8_t{0});
    signal.insert_raw(static_cast<std::int64_t>(std::uint64_t{1} << i), frame);
    int pos = -1;
    for (std::size_t b = 0; b < frame.size() && pos < 0; ++b)
      if (frame[b] != 0)
        pos = static_cast<int>(b * 8) + std::countr_zero(frame[b]);
    if (pos < 0)
      continue;  // beyond the end of the frame: the codec leaves it out too
    const auto byte = static_cast<std::uint8_t>(pos / 8),
               shift = static_cast<std::uint8_t>(pos % 8);
    if (piece_count_ > 0) {
      Piece& last = pieces_[piece_count_ - 1];
      if (last.byte == byte && last.shift + last.bits == shift && last.raw_shift + last.bits == i) {
        ++last.bits;
        continue;
      }
    }
    // Both byte orders keep a byte's bits contiguous, so this holds for any valid signal.
    if (piece_count_ == pieces_.size())
      throw std::logic_error("signal " + signal.name + " touches more than 9 bytes");
    pieces_[piece_count_++] = {byte, shift, static_cast<std::uint8_t>(i), 1};
  }
}

std::int64_t SignalPlan::to_raw(double physical) const {
  if (!std::isfinite(physical))
    return 0;
  if (clamp_)
    physical = std::clamp(physical, minimum_, maximum_);
  const double raw = std::round((physical - offset_) / factor_);
  if (raw <= lo_d_)
    return lo_;
  if (raw >= hi_d_)
    return hi_;
  return static_cast<std::int64_t>(raw);
}

void SignalPlan::insert_raw(std::int64_t raw, std::span<std::uint8_t> data) const {
  const auto u = static_cast<std::uint64_t>(raw);
  for (std::size_t k = 0; k < piece_count_; ++k) {
    const Piece& p = pieces_[k];
    if (p.byte >= data.size())
      continue;
    const auto mask = static_cast<std::uint8_t>(((1u << p.bits) - 1u) << p.shift);
    const auto bits = static_cast<std::uint8_t>(((u >> p.raw_shift) << p.shift) & mask);
    data[p.byte] = static_cast<std::uint8_t>((data[p.byte] & ~mask) | bits);
  }
}

Expected<CanFeeder, FeederError> CanFeeder::create(const tb::can::Database& db,
                                                   const FeederConfig& config) {
  if (!(config.dynamics_hz > 0) || !(config.body_hz > 0))
    return Unexpected{
        FeederError{FeederErrc::kBadRate,
                    fmt::format("dynamics {} Hz, body {} Hz", config.dynamics_hz, config.body_hz)}};
  CanFeeder f;
  f.config_ = config;
  std::vector<Schedule> schedules;
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
        s.counter.emplace(sig, m.dlc);
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
        s.fields.push_back({SignalPlan(sig, m.dlc), src->fn});
      }
    }
    schedules.push_back(std::move(s));
  }
  f.due_state_.resize(schedules.size());
  f.due_.reserve(schedules.size());
  f.schedules_ = std::make_shared<const std::vector<Schedule>>(std::move(schedules));
  return f;
}

CanFeeder CanFeeder::sibling(const FeederConfig& config) const {
  if (!same_rates(config))
    throw std::invalid_argument("CanFeeder::sibling: other rates");
  CanFeeder f;
  f.config_ = config;
  f.schedules_ = schedules_;
  f.due_state_.resize(schedules_->size());
  f.due_.reserve(schedules_->size());
  return f;
}

std::int64_t CanFeeder::period_ns(std::string_view message) const {
  for (const Schedule& s : *schedules_)
    if (s.message->name == message)
      return s.period_ns;
  return 0;
}

void CanFeeder::encode(const Schedule& s, Due& d, const VehicleState& state,
                       tb::can::CanFrame& out) const {
  const tb::can::Message& m = *s.message;
  out = tb::can::CanFrame{};
  out.can_id = m.extended ? (m.id | tb::can::kEffFlag) : m.id;
  out.len = static_cast<std::uint8_t>(m.dlc);
  out.fd = m.dlc > tb::can::kMaxClassicLen;
  const std::span<std::uint8_t> data(out.data.data(), m.dlc);
  for (const Field& f : s.fields)
    f.plan.encode(f.source(state, config_), data);
  if (s.counter) {
    s.counter->insert_raw(d.alive, data);
    d.alive = static_cast<std::uint8_t>((d.alive + 1) % (s.counter->raw_max() + 1));
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
  const std::vector<Schedule>& schedules = *schedules_;
  for (std::size_t i = 0; i < schedules.size(); ++i) {
    const Schedule& s = schedules[i];
    Due& d = due_state_[i];
    if (d.next_due_ns && t < *d.next_due_ns)
      continue;
    const std::int64_t floor_t =
        (t >= 0 ? t / s.period_ns : (t - s.period_ns + 1) / s.period_ns) * s.period_ns;
    d.next_due_ns = floor_t + s.period_ns;
    encode(s, d, state, due_.emplace_back());
  }
  frames_total_ += due_.size();
  return due_;
}

}  // namespace tb::emu::can
