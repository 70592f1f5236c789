#include "station-host/feed/state_vehicle_data.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace tb::host {

namespace {
constexpr double kRadToDeg = 180.0 / std::numbers::pi;
/// The feeder's DrivingDirection says standstill below this speed (can_feeder.cpp).
constexpr double kStandstillMps = 0.05;

bool lit(const wire::VehicleState& s, std::uint16_t bit) {
  return (s.lights & bit) != 0;
}
}  // namespace

its::facilities::VehicleData vehicle_data_of(const wire::VehicleState& s, double steering_ratio,
                                             clock::SteadyTime received) {
  namespace lights = its::facilities::lights;
  its::facilities::VehicleData d;
  d.received = received;
  const bool reverse = s.speed < -kStandstillMps;
  d.speed_mps = (reverse ? -1.0 : 1.0) * std::abs(double{s.speed});
  d.reversing = reverse;
  d.yaw_rate_dps = double{s.yaw_rate} * kRadToDeg;
  d.longitudinal_acceleration_mps2 = double{s.acceleration[0]};
  d.lateral_acceleration_mps2 = double{s.acceleration[1]};
  d.steering_wheel_angle_deg = double{s.steering_angle} * steering_ratio * kRadToDeg;
  // Any pedal travel counts, as the decoder's "engaged" does.
  d.gas_pedal = s.controls.throttle > 0.0f;
  d.brake_pedal = s.controls.brake > 0.0f;
  // Hazard lights flash both indicators (the feeder's IndicatorLeft/Right).
  const bool hazard = lit(s, wire::kHazard);
  std::uint8_t l = 0;
  if (lit(s, wire::kIndicatorLeft) || hazard)
    l |= lights::kLeftTurnSignal;
  if (lit(s, wire::kIndicatorRight) || hazard)
    l |= lights::kRightTurnSignal;
  if (lit(s, wire::kLowBeam))
    l |= lights::kLowBeam;
  if (lit(s, wire::kHighBeam))
    l |= lights::kHighBeam;
  if (lit(s, wire::kReverseLight))
    l |= lights::kReverse;
  if (lit(s, wire::kFogLight))
    l |= lights::kFog;
  d.exterior_lights = l;
  d.light_bar = lit(s, wire::kLightBar);
  d.siren = lit(s, wire::kSiren);
  return d;
}

StateVehicleData::StateVehicleData(double rate_hz, double steering_ratio, const clock::Clock& clock)
    : period_ns_(rate_hz > 0 ? static_cast<std::int64_t>(std::llround(1e9 / rate_hz)) : 0),
      steering_ratio_(steering_ratio),
      clock_(clock) {
  if (period_ns_ <= 0)
    throw std::invalid_argument("CAN dynamics rate must be positive");
}

void StateVehicleData::on_state(const wire::VehicleState& s) {
  if (next_ns_ && s.sim_time_ns < *next_ns_)
    return;
  const std::int64_t t = s.sim_time_ns;
  const std::int64_t floor_t =
      (t >= 0 ? t / period_ns_ : (t - period_ns_ + 1) / period_ns_) * period_ns_;
  next_ns_ = floor_t + period_ns_;
  ++updates_;
  publish(vehicle_data_of(s, steering_ratio_, clock_.steady_now()));
}

}  // namespace tb::host
