#include "sim-client/view3d/interpolation.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tb::client::view3d {
namespace {

double lerp(double a, double b, double t) {
  return a + (b - a) * t;
}
float lerpf(float a, float b, double t) {
  return static_cast<float>(lerp(a, b, t));
}

float lerp_angle(float a, float b, double t) {
  double d = std::remainder(static_cast<double>(b) - a, 2.0 * std::numbers::pi);
  return static_cast<float>(std::remainder(a + d * t, 2.0 * std::numbers::pi));
}

std::int64_t steady_ns(clock::SteadyTime t) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

}  // namespace

wire::VehicleState interpolate(const wire::VehicleState& a, const wire::VehicleState& b,
                               double alpha) {
  const double t = std::clamp(alpha, 0.0, 1.0);
  wire::VehicleState s = b;
  for (int i = 0; i < 3; ++i) {
    s.position[i] = lerp(a.position[i], b.position[i], t);
    s.velocity[i] = lerpf(a.velocity[i], b.velocity[i], t);
    s.angular_velocity[i] = lerpf(a.angular_velocity[i], b.angular_velocity[i], t);
    s.acceleration[i] = lerpf(a.acceleration[i], b.acceleration[i], t);
  }
  for (int i = 0; i < 4; ++i)
    s.wheel_speeds[i] = lerpf(a.wheel_speeds[i], b.wheel_speeds[i], t);
  s.yaw = lerp_angle(a.yaw, b.yaw, t);
  s.pitch = lerp_angle(a.pitch, b.pitch, t);
  s.roll = lerp_angle(a.roll, b.roll, t);
  s.speed = lerpf(a.speed, b.speed, t);
  s.yaw_rate = lerpf(a.yaw_rate, b.yaw_rate, t);
  s.steering_angle = lerpf(a.steering_angle, b.steering_angle, t);
  s.engine_rpm = lerpf(a.engine_rpm, b.engine_rpm, t);
  s.sim_time_ns =
      a.sim_time_ns + static_cast<std::int64_t>(std::llround((b.sim_time_ns - a.sim_time_ns) * t));
  return s;
}

void StateInterpolator::clear() {
  previous_.reset();
  latest_.reset();
  min_.clear();
}

void StateInterpolator::push(const wire::sim::StateFrame& frame, clock::SteadyTime arrival) {
  if (latest_ && frame.sim_time_ns <= latest_->sim_time_ns)
    clear();
  previous_ = std::move(latest_);
  latest_ = frame;
  const std::int64_t off = steady_ns(arrival) - frame.sim_time_ns;
  while (!min_.empty() && min_.back().ns >= off)
    min_.pop_back();
  min_.push_back({arrival, off});
  while (arrival - min_.front().arrival > window_)
    min_.pop_front();
}

std::optional<StateInterpolator::Sample> StateInterpolator::sample(clock::SteadyTime now) const {
  if (!latest_)
    return std::nullopt;
  Sample s;
  s.latest_tick = latest_->tick;
  const bool pair = previous_ && previous_->vehicles.size() == latest_->vehicles.size() &&
                    latest_->sim_time_ns > previous_->sim_time_ns;
  if (!pair) {
    s.sim_time_ns = latest_->sim_time_ns;
    s.vehicles = latest_->vehicles;
    return s;
  }
  const std::int64_t step = latest_->sim_time_ns - previous_->sim_time_ns;
  const std::int64_t want = steady_ns(now) - min_.front().ns - step;
  const std::int64_t at = std::clamp(want, previous_->sim_time_ns, latest_->sim_time_ns);
  s.alpha = static_cast<double>(at - previous_->sim_time_ns) / static_cast<double>(step);
  s.sim_time_ns = at;
  s.vehicles.reserve(latest_->vehicles.size());
  for (std::size_t i = 0; i < latest_->vehicles.size(); ++i)
    s.vehicles.push_back(interpolate(previous_->vehicles[i], latest_->vehicles[i], s.alpha));
  return s;
}

}  // namespace tb::client::view3d
