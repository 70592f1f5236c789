#pragma once
/// @file The vehicle the driver tests drive: a kinematic bicycle with its own longitudinal model.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "common/wire/vehicle_state.hpp"

namespace tb::client::test {

// A kinematic bicycle with a simple longitudinal model, deliberately not the one the driver
// assumes (heavier, weaker engine, steering that lags), so that the test checks the driver's
// feedback and not its own feed-forward.
class Plant {
 public:
  Plant(double x, double y, double yaw, double speed, std::uint32_t station_id = 0)
      : x_(x), y_(y), yaw_(yaw), v_(speed), station_id_(station_id) {}

  void step(const wire::Controls& c, double dt) {
    const double max_steer = 36.0 * std::numbers::pi / 180.0;
    const double wanted = -c.steer * max_steer;
    const double rate = 0.6 * dt;  // rad/s of road-wheel angle
    delta_ += std::clamp(wanted - delta_, -rate, rate);
    const double mass = 1500.0;
    // A gearbox that engages reverse (or forward) only below 0.5 m/s, like the server's.
    if (c.reverse != reverse_ && std::abs(v_) < 0.5)
      reverse_ = c.reverse;
    const double gear = reverse_ ? -1.0 : 1.0;
    const double drive =
        gear * c.throttle * std::min(5000.0, 70000.0 * 0.9 / std::max(std::abs(v_), 1.0));
    const double brake = c.brake * 9000.0;
    const double sign = v_ > 0.0 ? 1.0 : (v_ < 0.0 ? -1.0 : 0.0);
    const double resist =
        sign * (0.5 * 1.2 * 0.33 * 2.3 * v_ * v_ + (std::abs(v_) > 0.01 ? 0.013 * mass * 9.81 : 0));
    double a = (drive - resist) / mass;
    const double v_free = v_ + a * dt;
    // Brakes oppose the motion and hold a standing car.
    const double dv_brake = brake / mass * dt;
    double v_next = v_free;
    if (v_free > dv_brake)
      v_next = v_free - dv_brake;
    else if (v_free < -dv_brake)
      v_next = v_free + dv_brake;
    else
      v_next = 0.0;
    a = (v_next - v_) / dt;
    accel_ = a;
    v_ = v_next;
    // Rear-axle reference point.
    const double rx = x_ - std::cos(yaw_) * kWheelbase / 2,
                 ry = y_ - std::sin(yaw_) * kWheelbase / 2;
    const double nrx = rx + v_ * std::cos(yaw_) * dt, nry = ry + v_ * std::sin(yaw_) * dt;
    yaw_rate_ = v_ * std::tan(delta_) / kWheelbase;
    yaw_ += yaw_rate_ * dt;
    x_ = nrx + std::cos(yaw_) * kWheelbase / 2;
    y_ = nry + std::sin(yaw_) * kWheelbase / 2;
    t_ns_ += static_cast<std::int64_t>(dt * 1e9);
  }

  wire::VehicleState state() const {
    wire::VehicleState s;
    s.station_id = station_id_;
    s.sim_time_ns = t_ns_;
    s.velocity = {static_cast<float>(v_ * std::cos(yaw_)), static_cast<float>(v_ * std::sin(yaw_)),
                  0.0f};
    s.yaw_rate = static_cast<float>(yaw_rate_);
    s.position = {x_, y_, 0.0};
    s.yaw = static_cast<float>(yaw_);
    s.speed = static_cast<float>(v_);
    return s;
  }
  double accel() const { return accel_; }
  double speed() const { return v_; }

  static constexpr double kWheelbase = 2.637;

 private:
  double x_, y_, yaw_, v_;
  double delta_ = 0.0;
  double accel_ = 0.0;
  double yaw_rate_ = 0.0;
  bool reverse_ = false;
  std::uint32_t station_id_ = 0;
  std::int64_t t_ns_ = 0;
};

}  // namespace tb::client::test
