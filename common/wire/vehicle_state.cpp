#include "common/wire/vehicle_state.hpp"

#include <cassert>
#include <cmath>
#include <optional>

#include "common/util/bytes.hpp"

namespace tb::wire {
namespace {

constexpr std::uint8_t kMagic0 = 'V';
constexpr std::uint8_t kMagic1 = 'S';

// Flag bits of the controls byte.
constexpr std::uint8_t kReverseBit = 1u << 0;
constexpr std::uint8_t kHandbrakeBit = 1u << 1;

bool finite(float v) {
  return std::isfinite(v);
}

void write_head(ByteWriter& w, std::uint8_t version, std::uint8_t fourth) {
  w.le<std::uint8_t>(kMagic0);
  w.le<std::uint8_t>(kMagic1);
  w.le<std::uint8_t>(version);
  w.le<std::uint8_t>(fourth);
}

void write_body(ByteWriter& w, const VehicleState& s) {
  w.le(s.station_id);
  w.le(s.tick);
  w.le(s.sim_time_ns);
  w.le(s.step_wall_ns);
  w.le(s.send_wall_ns);
  for (double v : s.position)
    w.le(v);
  w.le(s.roll);
  w.le(s.pitch);
  w.le(s.yaw);
  for (float v : s.velocity)
    w.le(v);
  for (float v : s.angular_velocity)
    w.le(v);
  for (float v : s.acceleration)
    w.le(v);
  w.le(s.speed);
  w.le(s.yaw_rate);
  w.le(s.steering_angle);
  for (float v : s.wheel_speeds)
    w.le(v);
  w.le(s.controls.throttle);
  w.le(s.controls.brake);
  w.le(s.controls.steer);
  w.le<std::uint8_t>((s.controls.reverse ? kReverseBit : 0) |
                     (s.controls.handbrake ? kHandbrakeBit : 0));
  w.le(s.gear);
  w.le(s.lights);
  w.le(s.engine_rpm);
}

VehicleState read_body(ByteReader& r) {
  VehicleState s;
  s.station_id = r.le<std::uint32_t>();
  s.tick = r.le<std::uint64_t>();
  s.sim_time_ns = r.le<std::int64_t>();
  s.step_wall_ns = r.le<std::int64_t>();
  s.send_wall_ns = r.le<std::int64_t>();
  for (double& v : s.position)
    v = r.le<double>();
  s.roll = r.le<float>();
  s.pitch = r.le<float>();
  s.yaw = r.le<float>();
  for (float& v : s.velocity)
    v = r.le<float>();
  for (float& v : s.angular_velocity)
    v = r.le<float>();
  for (float& v : s.acceleration)
    v = r.le<float>();
  s.speed = r.le<float>();
  s.yaw_rate = r.le<float>();
  s.steering_angle = r.le<float>();
  for (float& v : s.wheel_speeds)
    v = r.le<float>();
  s.controls.throttle = r.le<float>();
  s.controls.brake = r.le<float>();
  s.controls.steer = r.le<float>();
  const auto flags = r.le<std::uint8_t>();
  s.controls.reverse = (flags & kReverseBit) != 0;
  s.controls.handbrake = (flags & kHandbrakeBit) != 0;
  s.gear = r.le<std::int8_t>();
  s.lights = r.le<std::uint16_t>();
  s.engine_rpm = r.le<float>();
  return s;
}

// The record checks, shared by the single record and the batch.
std::optional<DecodeError> check(const VehicleState& s) {
  for (double v : s.position) {
    if (!std::isfinite(v))
      return DecodeError::kNotFinite;
  }
  const float floats[] = {s.roll,
                          s.pitch,
                          s.yaw,
                          s.velocity[0],
                          s.velocity[1],
                          s.velocity[2],
                          s.angular_velocity[0],
                          s.angular_velocity[1],
                          s.angular_velocity[2],
                          s.acceleration[0],
                          s.acceleration[1],
                          s.acceleration[2],
                          s.speed,
                          s.yaw_rate,
                          s.steering_angle,
                          s.wheel_speeds[0],
                          s.wheel_speeds[1],
                          s.wheel_speeds[2],
                          s.wheel_speeds[3],
                          s.controls.throttle,
                          s.controls.brake,
                          s.controls.steer,
                          s.engine_rpm};
  for (float v : floats) {
    if (!finite(v))
      return DecodeError::kNotFinite;
  }
  if (s.controls.throttle < 0.0f || s.controls.throttle > 1.0f || s.controls.brake < 0.0f ||
      s.controls.brake > 1.0f || s.controls.steer < -1.0f || s.controls.steer > 1.0f ||
      s.sim_time_ns < kMinSimTimeNs) {
    return DecodeError::kOutOfRange;
  }
  return std::nullopt;
}

}  // namespace

std::string_view to_string(DecodeError e) {
  switch (e) {
    case DecodeError::kWrongSize:
      return "wrong size";
    case DecodeError::kBadMagic:
      return "bad magic";
    case DecodeError::kUnsupportedVersion:
      return "unsupported version";
    case DecodeError::kNotFinite:
      return "non-finite number";
    case DecodeError::kOutOfRange:
      return "value out of range";
    case DecodeError::kSingleStateVersion:
      return "version 1 (a single-state datagram of the old format; this receiver takes only "
             "version-3 batch datagrams, docs/wire.md)";
    case DecodeError::kBadCount:
      return "batch count 0 or not matching the datagram's size";
  }
  return "unknown";
}

void encode(const VehicleState& s, std::span<std::uint8_t, kVehicleStateSize> out) {
  ByteWriter w(out);
  write_head(w, kVehicleStateVersion, 0);  // fourth byte reserved
  write_body(w, s);
  assert(w.ok() && w.position() == kVehicleStateSize);
}

std::array<std::uint8_t, kVehicleStateSize> encode(const VehicleState& s) {
  std::array<std::uint8_t, kVehicleStateSize> out{};
  encode(s, std::span<std::uint8_t, kVehicleStateSize>(out));
  return out;
}

Expected<VehicleState, DecodeError> decode(std::span<const std::uint8_t> bytes) {
  if (bytes.size() != kVehicleStateSize)
    return Unexpected{DecodeError::kWrongSize};
  ByteReader r(bytes);
  if (r.le<std::uint8_t>() != kMagic0 || r.le<std::uint8_t>() != kMagic1) {
    return Unexpected{DecodeError::kBadMagic};
  }
  if (r.le<std::uint8_t>() != kVehicleStateVersion) {
    return Unexpected{DecodeError::kUnsupportedVersion};
  }
  r.skip(1);
  VehicleState s = read_body(r);
  if (!r.ok())
    return Unexpected{DecodeError::kWrongSize};
  if (const auto e = check(s))
    return Unexpected{*e};
  return s;
}

std::size_t encode_batch(std::span<const VehicleState> states, std::span<std::uint8_t> out,
                         std::int64_t world_start_ns) {
  const std::size_t size = batch_datagram_size(states.size());
  if (states.empty() || states.size() > kMaxStatesPerBatch || out.size() < size)
    return 0;
  ByteWriter w(out.first(size));
  write_head(w, kStateBatchVersion, static_cast<std::uint8_t>(states.size()));
  w.le(world_start_ns);
  for (const VehicleState& s : states)
    write_body(w, s);
  assert(w.ok() && w.position() == size);
  return size;
}

std::vector<std::uint8_t> encode_batch(std::span<const VehicleState> states,
                                       std::int64_t world_start_ns) {
  std::vector<std::uint8_t> out(batch_datagram_size(states.size()));
  out.resize(encode_batch(states, out, world_start_ns));
  return out;
}

Expected<std::size_t, DecodeError> decode_batch(std::span<const std::uint8_t> bytes,
                                                std::vector<VehicleState>& out,
                                                std::int64_t* world_start_ns) {
  out.clear();
  if (bytes.size() < kStateBatchHeadSize)
    return Unexpected{DecodeError::kWrongSize};
  ByteReader r(bytes);
  if (r.le<std::uint8_t>() != kMagic0 || r.le<std::uint8_t>() != kMagic1)
    return Unexpected{DecodeError::kBadMagic};
  const auto version = r.le<std::uint8_t>();
  if (version == kVehicleStateVersion)
    return Unexpected{DecodeError::kSingleStateVersion};
  if (version != kStateBatchVersion)
    return Unexpected{DecodeError::kUnsupportedVersion};
  const std::size_t count = r.le<std::uint8_t>();
  if (count == 0 || bytes.size() != batch_datagram_size(count))
    return Unexpected{DecodeError::kBadCount};
  const auto start = r.le<std::int64_t>();
  // A start time whose warm-up fixes fall before the ITS epoch (2004) cannot be dated in a CAM;
  // one past 2200 is no simulation's.
  constexpr std::int64_t kEarliest = 1'072'915'200'000'000'000 - kMinSimTimeNs;
  constexpr std::int64_t kLatest = 7'258'118'400'000'000'000;
  if (start != kUnknownWorldStart && (start < kEarliest || start > kLatest))
    return Unexpected{DecodeError::kOutOfRange};
  for (std::size_t i = 0; i < count; ++i) {
    out.push_back(read_body(r));
    if (const auto e = check(out.back())) {
      out.clear();
      return Unexpected{*e};
    }
  }
  if (!r.ok()) {  // cannot happen after the size check; kept so no path reads on blindly
    out.clear();
    return Unexpected{DecodeError::kWrongSize};
  }
  if (world_start_ns)
    *world_start_ns = start;
  return count;
}

}  // namespace tb::wire
