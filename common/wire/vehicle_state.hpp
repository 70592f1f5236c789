#pragma once
/// @file Vehicle state datagram, sim-client → network-emulator (and the per-vehicle record of
/// sim-server's state stream). Binary, versioned, fixed size; layout in docs/wire.md.
///
/// Frames: positions in the scenario's local ENU frame (x east, y north, z up), yaw counter-
/// clockwise from east; angular quantities in radians, positive counter-clockwise seen from
/// above (so a left turn has positive yaw rate and positive road-wheel angle). The control
/// input `steer` keeps the drivers' convention: positive = right, as in CARLA.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "common/util/expected.hpp"

namespace tb::wire {

/// Bits of VehicleState::lights.
enum Light : std::uint16_t {
  kIndicatorLeft = 1u << 0,
  kIndicatorRight = 1u << 1,
  kHazard = 1u << 2,
  kLowBeam = 1u << 3,
  kHighBeam = 1u << 4,
  kBrakeLights = 1u << 5,
  kReverseLight = 1u << 6,
  kFogLight = 1u << 7,
  kParkingLights = 1u << 8,
  kDaytimeRunning = 1u << 9,
};

struct Controls {
  float throttle = 0.0f;  ///< [0, 1]
  float brake = 0.0f;     ///< [0, 1]
  float steer = 0.0f;     ///< [-1, 1], positive = right
  bool reverse = false;
  bool handbrake = false;

  bool operator==(const Controls&) const = default;
};

struct VehicleState {
  std::uint32_t station_id = 0;
  std::uint64_t tick = 0;                       ///< physics step number
  std::int64_t sim_time_ns = 0;                 ///< sim time of the step, ns since scenario start
  std::int64_t step_wall_ns = 0;                ///< CLOCK_REALTIME when the step was computed
  std::int64_t send_wall_ns = 0;                ///< CLOCK_REALTIME when this datagram was sent
  std::array<double, 3> position{};             ///< m
  float roll = 0.0f, pitch = 0.0f, yaw = 0.0f;  ///< rad
  std::array<float, 3> velocity{};              ///< world frame, m/s
  std::array<float, 3> angular_velocity{};      ///< world frame, rad/s
  std::array<float, 3> acceleration{};          ///< body frame: longitudinal, lateral (left +), up
  float speed = 0.0f;           ///< signed along the vehicle's heading, m/s (negative reversing)
  float yaw_rate = 0.0f;        ///< rad/s
  float steering_angle = 0.0f;  ///< road-wheel angle, rad
  std::array<float, 4> wheel_speeds{};  ///< FL, FR, RL, RR at the contact patch, m/s
  Controls controls;                    ///< in effect during the step
  std::int8_t gear = 0;                 ///< -1 reverse, 0 neutral, 1..n
  std::uint16_t lights = 0;             ///< Light bits
  float engine_rpm = 0.0f;

  bool operator==(const VehicleState&) const = default;
};

inline constexpr std::uint8_t kVehicleStateVersion = 1;
inline constexpr std::size_t kVehicleStateSize = 160;

enum class DecodeError {
  kWrongSize,
  kBadMagic,
  kUnsupportedVersion,
  kNotFinite,
  kOutOfRange,
};
std::string_view to_string(DecodeError e);

/// Writes exactly kVehicleStateSize bytes into @p out.
void encode(const VehicleState& s, std::span<std::uint8_t, kVehicleStateSize> out);
std::array<std::uint8_t, kVehicleStateSize> encode(const VehicleState& s);
/// Never reads outside @p bytes; rejects wrong sizes, versions, non-finite numbers and control
/// values outside their ranges.
Expected<VehicleState, DecodeError> decode(std::span<const std::uint8_t> bytes);

}  // namespace tb::wire
