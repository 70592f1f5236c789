#include "sim-client/view3d/cameras.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <osg/Quat>

namespace tb::client::view3d {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

osg::Quat attitude(const Subject& s) {
  // Roll about x first, then pitch about y, then yaw about z (R = Rz·Ry·Rx); OpenSceneGraph
  // composes quaternions in the order they are applied.
  return osg::Quat(s.roll, osg::X_AXIS, s.pitch, osg::Y_AXIS, s.yaw, osg::Z_AXIS);
}

}  // namespace

std::string_view to_string(CameraMode m) {
  switch (m) {
    case CameraMode::kChase:
      return "chase";
    case CameraMode::kCockpit:
      return "cockpit";
    case CameraMode::kTop:
      return "top";
    case CameraMode::kOrbit:
      return "orbit";
  }
  return "?";
}

std::optional<CameraMode> parse_camera(std::string_view text) {
  if (text == "chase")
    return CameraMode::kChase;
  if (text == "cockpit" || text == "hood")
    return CameraMode::kCockpit;
  if (text == "top")
    return CameraMode::kTop;
  if (text == "orbit")
    return CameraMode::kOrbit;
  return std::nullopt;
}

osg::Vec3d Subject::forward() const {
  return attitude(*this) * osg::Vec3d(1, 0, 0);
}
osg::Vec3d Subject::left() const {
  return attitude(*this) * osg::Vec3d(0, 1, 0);
}
osg::Vec3d Subject::up() const {
  return attitude(*this) * osg::Vec3d(0, 0, 1);
}
osg::Vec3d Subject::body_to_world(const osg::Vec3d& p) const {
  return position + attitude(*this) * p;
}

double vertical_fov_deg(double hfov_deg, double aspect) {
  const double h = std::clamp(hfov_deg, 10.0, 170.0) * kDeg;
  return 2.0 * std::atan(std::tan(h / 2.0) / aspect) / kDeg;
}

osg::Matrixd perspective(double hfov_deg, const Viewport& vp, double near_m, double far_m) {
  return osg::Matrixd::perspective(vertical_fov_deg(hfov_deg, vp.aspect()), vp.aspect(), near_m,
                                   far_m);
}

double DampedSpring::update(double target, double dt) {
  if (!primed_) {
    snap(target);
    return value_;
  }
  // Critically damped spring, exact for a target held over dt.
  const double delta = value_ - target;
  const double temp = (velocity_ + omega_ * delta) * dt;
  const double decay = std::exp(-omega_ * dt);
  velocity_ = (velocity_ - omega_ * temp) * decay;
  value_ = target + (delta + temp) * decay;
  return value_;
}

CameraPose ChaseCamera::update(const Subject& s, const ViewChoice& choice, const Viewport& vp,
                               double dt_s) {
  // The spring runs on the unwrapped angle: keep the target within half a turn of it.
  double target_yaw = s.yaw;
  if (yaw_.primed()) {
    target_yaw = yaw_.value() + std::remainder(s.yaw - yaw_.value(), 2.0 * std::numbers::pi);
  }
  const double yaw = yaw_.update(target_yaw, dt_s);
  const double ground = z_.update(s.position.z(), dt_s);
  const osg::Vec3d dir(std::cos(yaw), std::sin(yaw), 0.0);
  CameraPose p;
  p.eye = osg::Vec3d(s.position.x(), s.position.y(), ground) - dir * back_distance(s.length) +
          osg::Vec3d(0, 0, eye_height(s.height));
  const osg::Vec3d look = osg::Vec3d(s.position.x(), s.position.y(), ground) +
                          dir * (0.5 * s.length + 4.0) + osg::Vec3d(0, 0, 1.0);
  p.view = osg::Matrixd::lookAt(p.eye, look, osg::Vec3d(0, 0, 1));
  p.projection = perspective(choice.hfov_deg, vp, 0.5, kFarPlaneM);
  return p;
}

void ChaseCamera::reset() {
  yaw_ = DampedSpring(4.0);
  z_ = DampedSpring(3.0);
}

osg::Vec3d CockpitCamera::eye_in_body(const Subject& s) {
  return {-0.05 * s.length, 0.2 * s.width, 0.85 * s.height};
}

CameraPose CockpitCamera::update(const Subject& s, const ViewChoice& choice, const Viewport& vp,
                                 double) {
  CameraPose p;
  p.eye = s.body_to_world(eye_in_body(s));
  p.view = osg::Matrixd::lookAt(p.eye, p.eye + s.forward(), s.up());
  p.projection = perspective(choice.hfov_deg, vp, 0.2, kFarPlaneM);
  return p;
}

CameraPose TopDownCamera::update(const Subject& s, const ViewChoice& choice, const Viewport& vp,
                                 double) {
  const double ppm = kPixelsPerMetre * std::clamp(choice.top_zoom, 0.05, 20.0);
  const double half_w = vp.width / 2.0 / ppm;
  const double half_h = vp.height / 2.0 / ppm;
  const osg::Vec3d dir(std::cos(s.yaw), std::sin(s.yaw), 0.0);
  // The car 60 % down the screen: the centre of the view 10 % of the height ahead of it.
  const osg::Vec3d centre = s.position + dir * (0.1 * vp.height / ppm);
  CameraPose p;
  p.eye = centre + osg::Vec3d(0, 0, 200.0);  // inside the fog's start: no haze from above
  p.view = osg::Matrixd::lookAt(p.eye, centre, dir);
  p.projection = osg::Matrixd::ortho(-half_w, half_w, -half_h, half_h, 1.0, 600.0);
  return p;
}

CameraPose OrbitCamera::update(const Subject& s, const ViewChoice& choice, const Viewport& vp,
                               double) {
  const double az = choice.orbit_azimuth_deg * kDeg;
  const double el = std::clamp(choice.orbit_elevation_deg, 2.0, 89.0) * kDeg;
  const double d = std::clamp(choice.orbit_distance_m, 3.0, 2000.0);
  const osg::Vec3d target = s.position + osg::Vec3d(0, 0, 1.0);
  CameraPose p;
  p.eye = target +
          osg::Vec3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)) * d;
  p.view = osg::Matrixd::lookAt(p.eye, target, osg::Vec3d(0, 0, 1));
  p.projection = perspective(choice.hfov_deg, vp, std::max(0.5, d / 200.0), kFarPlaneM);
  return p;
}

CameraPose MirrorCamera::update(const Subject& s, const ViewChoice&, const Viewport& vp, double) {
  CameraPose p;
  p.eye = s.body_to_world({0.0, 0.0, 0.85 * s.height + 0.1});
  // Looking back and 2° down, over the boot.
  const osg::Vec3d back = -s.forward() * std::cos(2 * kDeg) - s.up() * std::sin(2 * kDeg);
  p.view = osg::Matrixd::lookAt(p.eye, p.eye + back, s.up());
  p.projection = perspective(50.0, vp, 0.5, kFarPlaneM) * osg::Matrixd::scale(-1.0, 1.0, 1.0);
  return p;
}

std::unique_ptr<CameraRig> make_camera(CameraMode m) {
  switch (m) {
    case CameraMode::kCockpit:
      return std::make_unique<CockpitCamera>();
    case CameraMode::kTop:
      return std::make_unique<TopDownCamera>();
    case CameraMode::kOrbit:
      return std::make_unique<OrbitCamera>();
    case CameraMode::kChase:
      break;
  }
  return std::make_unique<ChaseCamera>();
}

}  // namespace tb::client::view3d
