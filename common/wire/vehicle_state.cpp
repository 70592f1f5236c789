#include "common/wire/vehicle_state.hpp"

#include <cassert>
#include <cmath>

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
  }
  return "unknown";
}

void encode(const VehicleState& s, std::span<std::uint8_t, kVehicleStateSize> out) {
  ByteWriter w(out);
  w.le<std::uint8_t>(kMagic0);
  w.le<std::uint8_t>(kMagic1);
  w.le<std::uint8_t>(kVehicleStateVersion);
  w.le<std::uint8_t>(0);  // reserved
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
  if (!r.ok())
    return Unexpected{DecodeError::kWrongSize};

  for (double v : s.position) {
    if (!std::isfinite(v))
      return Unexpected{DecodeError::kNotFinite};
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
      return Unexpected{DecodeError::kNotFinite};
  }
  if (s.controls.throttle < 0.0f || s.controls.throttle > 1.0f || s.controls.brake < 0.0f ||
      s.controls.brake > 1.0f || s.controls.steer < -1.0f || s.controls.steer > 1.0f ||
      s.sim_time_ns < 0) {
    return Unexpected{DecodeError::kOutOfRange};
  }
  return s;
}

}  // namespace tb::wire
