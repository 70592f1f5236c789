#include "sim-server/physics/powertrain.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tb::server::physics {
namespace {

constexpr double kRadPerSecToRpm = 60.0 / (2.0 * std::numbers::pi);
/// Engine braking with the throttle closed: friction and pumping losses grow with speed; a
/// typical 1.4 l petrol engine drags with 15–40 Nm over its range.
constexpr double kDragTorqueBase = 15.0;
constexpr double kDragTorquePerRpm = 0.004;
/// The drag fades in as the throttle closes below this, rather than switching on at it: a car
/// cruising at light load sits at a few per cent of throttle, and a drag that came and went
/// with the controller's every correction jolted it by -0.7 m/s² every few steps (issue 22: the
/// CAN acceleration, and with it LCRW's constant-acceleration TTC, carried the jolts).
constexpr double kDragFadeThrottle = 0.05;
/// How far above idle a slipping clutch lets the engine run at full throttle when pulling away.
constexpr double kLaunchRpmSpan = 2200.0;

}  // namespace

Powertrain::Powertrain(const scenario::VehicleModel& model) : m_(model) {}

double Powertrain::ratio(int gear) const {
  if (gear < 0)
    return -m_.reverse_ratio * m_.final_drive;
  if (gear == 0 || m_.gear_ratios.empty())
    return 0.0;
  const auto i = static_cast<std::size_t>(std::min<int>(gear, m_.gear_ratios.size())) - 1;
  return m_.gear_ratios[i] * m_.final_drive;
}

double Powertrain::rpm_at(double speed, int gear) const {
  return std::abs(speed / m_.wheel_radius_m * ratio(gear)) * kRadPerSecToRpm;
}

double Powertrain::full_load_torque(double rpm) const {
  const auto& c = m_.torque_curve;
  if (c.empty())
    return 0.0;
  if (rpm <= c.front().rpm)
    return c.front().torque_nm;
  for (std::size_t i = 1; i < c.size(); ++i) {
    if (rpm <= c[i].rpm) {
      const double f = (rpm - c[i - 1].rpm) / (c[i].rpm - c[i - 1].rpm);
      return c[i - 1].torque_nm + f * (c[i].torque_nm - c[i - 1].torque_nm);
    }
  }
  return c.back().torque_nm;
}

DriveForces Powertrain::update(const wire::Controls& c, double speed, double dt) {
  const int top = static_cast<int>(m_.gear_ratios.size());
  // Direction changes only near standstill, as an automatic's selector lock does.
  if (c.reverse && gear_ > 0 && std::abs(speed) < kDirectionChangeSpeed) {
    gear_ = -1;
  } else if (!c.reverse && gear_ < 0 && std::abs(speed) < kDirectionChangeSpeed) {
    gear_ = 1;
  }
  if (gear_ > 0 && shift_left_ <= 0.0) {
    const double rpm = rpm_at(speed, gear_);
    if (rpm > m_.shift_up_rpm && gear_ < top) {
      ++gear_;
      shift_left_ = kShiftTime;
    } else if (gear_ > 1 && rpm < m_.shift_down_rpm) {
      // Skip down as far as the lower gear stays below the up-shift speed (kick-down).
      while (gear_ > 1 && rpm_at(speed, gear_ - 1) < m_.shift_up_rpm * 0.9 &&
             rpm_at(speed, gear_) < m_.shift_down_rpm) {
        --gear_;
      }
      shift_left_ = kShiftTime;
    }
  }

  DriveForces f;
  f.gear = gear_;
  const double wheel_rpm = rpm_at(speed, gear_);
  const double launch_rpm = m_.idle_rpm + c.throttle * kLaunchRpmSpan;
  f.engine_rpm =
      std::max(wheel_rpm, gear_ == 0 ? m_.idle_rpm : std::min(launch_rpm, m_.shift_up_rpm));
  if (shift_left_ > 0.0) {
    shift_left_ -= dt;
  } else if (gear_ != 0) {
    // Past the redline the engine management cuts fuel.
    const double redline = m_.torque_curve.empty() ? 0.0 : m_.torque_curve.back().rpm;
    double torque = f.engine_rpm > redline ? 0.0 : c.throttle * full_load_torque(f.engine_rpm);
    if (c.throttle < kDragFadeThrottle)
      torque -= (1.0 - c.throttle / kDragFadeThrottle) *
                (kDragTorqueBase + kDragTorquePerRpm * f.engine_rpm);
    // Engine braking only while the clutch is closed, i.e. above the launch speed.
    if (torque < 0.0 && wheel_rpm < m_.idle_rpm * 1.2)
      torque = 0.0;
    const double r = ratio(gear_);
    f.traction_n = torque * r * m_.drivetrain_efficiency / m_.wheel_radius_m;
    if (torque < 0.0) {
      // Drag opposes the motion in either direction.
      f.traction_n = -std::copysign(std::abs(f.traction_n), speed);
    }
  }
  f.brake_n = std::clamp(c.brake, 0.0f, 1.0f) * m_.brake_torque_nm / m_.wheel_radius_m;
  f.handbrake_n = c.handbrake ? m_.handbrake_torque_nm / m_.wheel_radius_m : 0.0;
  return f;
}

}  // namespace tb::server::physics
