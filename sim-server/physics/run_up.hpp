#pragma once
/// @file The run-up: where a vehicle is during the warm-up, the negative sim time before the
/// scenario starts (scenario `warmup_s`, docs/scenario.md).
///
/// During the warm-up the physics does not run: every vehicle is held on the path that brings
/// it to its spawn pose at sim time 0 with its spawn speed — the arc of its spawn lane's
/// curvature at the spawn point (a ring's circle, a straight road's line; on an OpenDRIVE lane
/// whose curvature changes, the arc that fits it there), or the straight line along a pose
/// spawn's heading — moving at the spawn speed, at the spawn's height and attitude. A vehicle
/// spawned at rest stands on its spawn pose. So the GPS agents make consistent fixes (position,
/// course and speed agree), the stations have fixes and send CAMs before sim time 0, and at sim
/// time 0 the physics takes over exactly where the scenario says the vehicles start.

namespace tb::server::physics {

/// Where a vehicle starts (the scenario's spawn, on the ground under the centre of its
/// bounding box).
struct SpawnPose {
  double x = 0.0, y = 0.0;  ///< ground position of the vehicle's reference point, m
  double yaw = 0.0;         ///< rad, counter-clockwise from east
  double speed = 0.0;       ///< m/s along the heading
  double z = 0.0;           ///< height of that ground point, m
  double pitch = 0.0;       ///< rad, ZYX (wire::VehicleState): resting on the road's slope
  double roll = 0.0;        ///< rad, ZYX: resting on its superelevation
  /// Curvature of the path it arrives along, 1/m, positive to the left of its heading: its
  /// spawn lane's there (±1/radius on a ring, 0 on a straight road or for a pose spawn).
  double curvature = 0.0;
};

/// A vehicle's pose and motion on its run-up.
struct RunUpPose {
  double x = 0.0, y = 0.0;
  double yaw = 0.0;            ///< rad, counter-clockwise from east
  double yaw_rate = 0.0;       ///< rad/s, left positive
  double lateral_accel = 0.0;  ///< m/s², left positive (centripetal on an arc)
};

/// The pose at sim time @p t_s ≤ 0 (later times give the spawn pose): @p spawn moved back along
/// its arc by speed × |t|.
RunUpPose run_up(const SpawnPose& spawn, double t_s);

}  // namespace tb::server::physics
