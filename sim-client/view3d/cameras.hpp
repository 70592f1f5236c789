#pragma once
/// @file The view's cameras, one small class each (as esmini's viewer has them): chase on a
/// damped spring, the driver's eye (cockpit), top-down (the 2D view's framing), a free orbit
/// for watch mode, and the rear-view mirror. Pure math on OpenSceneGraph's matrix types: a
/// camera turns the followed vehicle's pose into view and projection matrices.

#include <memory>

#include <osg/Matrixd>
#include <osg/Vec3d>

#include "sim-client/view3d/frame_input.hpp"

namespace tb::client::view3d {

/// The followed vehicle: its ground point below the body centre (the state's position) and
/// its attitude, with its size.
struct Subject {
  osg::Vec3d position;
  double yaw = 0.0, pitch = 0.0, roll = 0.0;  ///< rad, the state's Euler ZYX angles
  double length = 4.5, width = 1.8, height = 1.45;
  /// Body axes in the world: forward (x), left (y), up (z).
  osg::Vec3d forward() const;
  osg::Vec3d left() const;
  osg::Vec3d up() const;
  /// A point given in the body frame (x forward, y left, z up, from the ground point).
  osg::Vec3d body_to_world(const osg::Vec3d& p) const;
};

struct Viewport {
  int width = 1280, height = 720;
  double aspect() const { return height > 0 ? static_cast<double>(width) / height : 1.0; }
};

struct CameraPose {
  osg::Matrixd view;
  osg::Matrixd projection;
  osg::Vec3d eye;
};

/// Vertical field of view (degrees) for a horizontal one at an aspect ratio.
double vertical_fov_deg(double hfov_deg, double aspect);
/// A perspective projection with a horizontal field of view.
osg::Matrixd perspective(double hfov_deg, const Viewport& vp, double near_m, double far_m);

/// The far plane of every perspective camera: beyond it the fog has hidden everything.
inline constexpr double kFarPlaneM = 2500.0;

/// A scalar on a critically damped spring (the closed form, stable for any time step):
/// follows its target without overshoot; omega sets how fast (settles in about 5/omega s).
class DampedSpring {
 public:
  explicit DampedSpring(double omega) : omega_(omega) {}
  double update(double target, double dt);
  void snap(double v) {
    value_ = v;
    velocity_ = 0.0;
    primed_ = true;
  }
  bool primed() const { return primed_; }
  double value() const { return value_; }

 private:
  double omega_;
  double value_ = 0.0;
  double velocity_ = 0.0;
  bool primed_ = false;
};

class CameraRig {
 public:
  virtual ~CameraRig() = default;
  /// The pose for this frame; @p dt_s is the time since the last one (0 on the first).
  virtual CameraPose update(const Subject& s, const ViewChoice& choice, const Viewport& vp,
                            double dt_s) = 0;
  /// Forget the motion history (a new target, a camera switched to): the next update starts
  /// at rest in its place rather than swinging in.
  virtual void reset() {}
};

/// Behind and above, looking over the car a little ahead of it. The heading and the height
/// follow the car on damped springs (omega 4/s and 3/s): a swerve turns the view smoothly,
/// a bump does not shake it; the distance is rigid, so speed does not stretch the view.
class ChaseCamera final : public CameraRig {
 public:
  CameraPose update(const Subject& s, const ViewChoice& choice, const Viewport& vp,
                    double dt_s) override;
  void reset() override;
  /// Where the camera rests behind a car of that size (body frame: back, up).
  static double back_distance(double length) { return 0.5 * length + 4.5; }
  static double eye_height(double height) { return height + 1.3; }

 private:
  DampedSpring yaw_{4.0};
  DampedSpring z_{3.0};
};

/// The driver's eye: left of the centre line (left-hand drive), at 85 % of the height, a
/// little behind the middle of the car, rigid with the body.
class CockpitCamera final : public CameraRig {
 public:
  CameraPose update(const Subject& s, const ViewChoice& choice, const Viewport& vp,
                    double dt_s) override;
  static osg::Vec3d eye_in_body(const Subject& s);
};

/// Straight down, heading up, orthographic at 8 px/m (times the zoom), the car 60 % down the
/// screen: the 2D view's framing (view/scene.hpp) in 3D.
class TopDownCamera final : public CameraRig {
 public:
  static constexpr double kPixelsPerMetre = 8.0;
  CameraPose update(const Subject& s, const ViewChoice& choice, const Viewport& vp,
                    double dt_s) override;
};

/// Around the target at the chosen azimuth, elevation and distance (mouse and keys), the
/// target's position followed without lag; north stays where the operator turned it.
class OrbitCamera final : public CameraRig {
 public:
  CameraPose update(const Subject& s, const ViewChoice& choice, const Viewport& vp,
                    double dt_s) override;
};

/// The interior rear-view mirror: from the driver's head height looking back, 50° wide, the
/// image mirrored left to right as a mirror shows it.
class MirrorCamera final : public CameraRig {
 public:
  CameraPose update(const Subject& s, const ViewChoice& choice, const Viewport& vp,
                    double dt_s) override;
};

std::unique_ptr<CameraRig> make_camera(CameraMode m);

}  // namespace tb::client::view3d
