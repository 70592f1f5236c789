#pragma once
/// @file Engine, automatic gearbox and brakes of one vehicle: controls in, forces at the road out.
///
/// Pure logic without Bullet, so that gear choice and torque are tested on their own. The wheels
/// of btRaycastVehicle roll without slip, so the engine speed follows the driven wheels' road
/// speed; below the speed where the engine would stall, a slipping clutch holds it at a launch
/// speed that rises with the throttle (as a driver does when pulling away).

#include <cstdint>

#include "common/scenario/scenario.hpp"
#include "common/wire/vehicle_state.hpp"

namespace tb::server::physics {

struct DriveForces {
  double traction_n = 0.0;   ///< at the driven wheels' contact patches, along the heading
  double brake_n = 0.0;      ///< all wheels together, opposing the rolling direction
  double handbrake_n = 0.0;  ///< rear wheels together
  std::int8_t gear = 0;      ///< -1 reverse, 0 neutral, 1..n
  double engine_rpm = 0.0;
};

class Powertrain {
 public:
  /// Time without drive torque while the gearbox changes gear.
  static constexpr double kShiftTime = 0.4;
  /// Below this speed (m/s) the gearbox may change between forward and reverse.
  static constexpr double kDirectionChangeSpeed = 0.5;

  explicit Powertrain(const scenario::VehicleModel& model);

  /// Advances the gearbox by @p dt and returns the forces for the coming step. @p speed is the
  /// signed road speed along the heading (m/s).
  DriveForces update(const wire::Controls& c, double speed, double dt);

  /// Engine torque at full throttle, linear between the curve's points and flat beyond them.
  double full_load_torque(double rpm) const;
  /// Engine speed for a road speed in @p gear (1..n, or -1).
  double rpm_at(double speed, int gear) const;
  std::int8_t gear() const { return gear_; }

 private:
  double ratio(int gear) const;

  scenario::VehicleModel m_;
  std::int8_t gear_ = 1;
  double shift_left_ = 0.0;
};

}  // namespace tb::server::physics
