#pragma once
/// @file Vehicle states on the wire: the per-vehicle record (sim-server's state stream) and the
/// batch datagram, sim-client → network-emulator, that carries the records of one physics tick.
/// Binary, versioned, fixed-size records; layout in docs/wire.md.
///
/// Frames: positions in the map's frame (x east, y north, z up: an OpenDRIVE map's inertial
/// frame, or East-North-Up at the scenario's origin; common/map/scenario_map.hpp), yaw counter-
/// clockwise from east; angular quantities in radians, positive counter-clockwise seen from
/// above (so a left turn has positive yaw rate and positive road-wheel angle). The control
/// input `steer` keeps the drivers' convention: positive = right, as in CARLA.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

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
  /// A special vehicle's light bar and siren (CDD LightBarSirenInUse).
  kLightBar = 1u << 10,
  kSiren = 1u << 11,
};

struct Controls {
  float throttle = 0.0f;  ///< [0, 1]
  float brake = 0.0f;     ///< [0, 1]
  float steer = 0.0f;     ///< [-1, 1], positive = right
  bool reverse = false;
  bool handbrake = false;

  bool operator==(const Controls&) const = default;
};

/// The earliest sim time a state may carry: the longest warm-up a scenario can ask for (its
/// `warmup_s`, at most 60 s), during which sim time runs negative up to the scenario's start.
inline constexpr std::int64_t kMinSimTimeNs = -60'000'000'000;

struct VehicleState {
  std::uint32_t station_id = 0;
  std::uint64_t tick = 0;  ///< physics step number (warm-up steps included: it never goes back)
  /// Sim time of the step, ns since scenario start; negative during the warm-up (sim-server
  /// holds every car on its run-up to its spawn pose), never below kMinSimTimeNs.
  std::int64_t sim_time_ns = 0;
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

/// Version of the single record (magic, version, reserved, then the body).
inline constexpr std::uint8_t kVehicleStateVersion = 1;
inline constexpr std::size_t kVehicleStateSize = 160;
/// A record without its 4-byte head: what a batch datagram carries per state.
inline constexpr std::size_t kVehicleStateBodySize = kVehicleStateSize - 4;

/// Batch datagram (UDP, sim-client → network-emulator → radio-medium): magic `VS`, version 3,
/// count, then the world's start time (int64, Unix ns of sim time 0: the epoch sim-server fixed
/// when it started, docs/time.md), then count record bodies. Version 1 was one record per
/// datagram, version 2 a batch without the start time; a receiver refuses both
/// (kSingleStateVersion, kUnsupportedVersion) rather than misread them.
inline constexpr std::uint8_t kStateBatchVersion = 3;
inline constexpr std::size_t kStateBatchHeadSize = 12;
/// The start time of a batch that does not know it (a test's, a tool's): the receiver falls
/// back on the scenario's pinned start_time.
inline constexpr std::int64_t kUnknownWorldStart = 0;
/// Up to the u8 count; the sender's datagram size limit usually binds first.
inline constexpr std::size_t kMaxStatesPerBatch = 255;
/// Default datagram size limit: the UDP payload of a 1500-byte Ethernet MTU, so that a batch
/// crossing a real network (Docker bridge, veth) is never fragmented. 9 states.
inline constexpr std::size_t kDefaultBatchDatagramSize = 1472;
constexpr std::size_t batch_datagram_size(std::size_t states) {
  return kStateBatchHeadSize + states * kVehicleStateBodySize;
}
/// How many states fit in a datagram of at most @p max_bytes (at least 1).
constexpr std::size_t states_per_batch(std::size_t max_bytes) {
  const std::size_t n = max_bytes < batch_datagram_size(1)
                            ? 1
                            : (max_bytes - kStateBatchHeadSize) / kVehicleStateBodySize;
  return n > kMaxStatesPerBatch ? kMaxStatesPerBatch : n;
}

enum class DecodeError {
  kWrongSize,
  kBadMagic,
  kUnsupportedVersion,
  kNotFinite,
  kOutOfRange,
  kSingleStateVersion,  ///< a version-1 single-state datagram where a batch was expected
  kBadCount,            ///< a batch whose count is 0 or disagrees with its size
};
inline constexpr std::size_t kDecodeErrorCount = 7;
std::string_view to_string(DecodeError e);

/// Writes exactly kVehicleStateSize bytes into @p out.
void encode(const VehicleState& s, std::span<std::uint8_t, kVehicleStateSize> out);
std::array<std::uint8_t, kVehicleStateSize> encode(const VehicleState& s);
/// Never reads outside @p bytes; rejects wrong sizes, versions, non-finite numbers and control
/// values outside their ranges.
Expected<VehicleState, DecodeError> decode(std::span<const std::uint8_t> bytes);

/// Writes the batch datagram of @p states (1..kMaxStatesPerBatch) into @p out, which must hold
/// batch_datagram_size(states.size()) bytes; returns the bytes written (0 if not).
/// @p world_start_ns: Unix ns of sim time 0, or kUnknownWorldStart.
std::size_t encode_batch(std::span<const VehicleState> states, std::span<std::uint8_t> out,
                         std::int64_t world_start_ns = kUnknownWorldStart);
std::vector<std::uint8_t> encode_batch(std::span<const VehicleState> states,
                                       std::int64_t world_start_ns = kUnknownWorldStart);
/// Decodes a batch datagram into @p out (cleared first; its capacity is reused, so a receiver
/// allocates nothing per datagram). Never reads outside @p bytes. The datagram is one unit: a
/// bad head, count or record refuses all of it (and leaves @p out empty), with the record
/// checks of decode(). A version-1 datagram is kSingleStateVersion. @p world_start_ns, if given,
/// gets the batch's start time (kUnknownWorldStart when the sender did not know it).
Expected<std::size_t, DecodeError> decode_batch(std::span<const std::uint8_t> bytes,
                                                std::vector<VehicleState>& out,
                                                std::int64_t* world_start_ns = nullptr);

}  // namespace tb::wire
