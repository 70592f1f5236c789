#include "sim-server/physics/run_up.hpp"

#include <algorithm>
#include <cmath>

namespace tb::server::physics {
namespace {
/// Below this |κ·d| the arc's closed form loses precision to cancellation; its series is exact
/// there to well below a micrometre at road distances.
constexpr double kStraight = 1e-6;
}  // namespace

RunUpPose run_up(const SpawnPose& spawn, double t_s) {
  const double d = spawn.speed * std::min(t_s, 0.0);  // signed arc length from the spawn, ≤ 0
  const double k = spawn.curvature;
  const double turn = k * d;
  // In the spawn's frame (x along its heading, y to its left) the arc through the origin.
  double along = d, left = 0.0;
  if (std::abs(turn) > kStraight) {
    along = std::sin(turn) / k;
    left = (1.0 - std::cos(turn)) / k;
  } else {
    left = k * d * d / 2.0;
  }
  const double c = std::cos(spawn.yaw), s = std::sin(spawn.yaw);
  RunUpPose p;
  p.x = spawn.x + c * along - s * left;
  p.y = spawn.y + s * along + c * left;
  p.yaw = spawn.yaw + turn;
  p.yaw_rate = spawn.speed * k;
  p.lateral_accel = spawn.speed * spawn.speed * k;
  return p;
}

}  // namespace tb::server::physics
