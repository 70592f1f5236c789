#include "sim-client/view3d/cameras.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace tb::client::view3d {
namespace {

constexpr double kPi = std::numbers::pi;

Subject car(double x, double y, double yaw) {
  Subject s;
  s.position.set(x, y, 0.0);
  s.yaw = yaw;
  return s;
}

/// Where a world point lands in normalised device coordinates.
osg::Vec3d ndc(const CameraPose& p, const osg::Vec3d& w) {
  return w * p.view * p.projection;  // OpenSceneGraph's row vectors
}

TEST(Subject, BodyAxesFollowYawPitchRoll) {
  Subject s = car(0, 0, kPi / 2);
  EXPECT_NEAR(s.forward().y(), 1.0, 1e-12);
  EXPECT_NEAR(s.left().x(), -1.0, 1e-12);
  s.yaw = 0.0;
  s.pitch = 0.1;  // positive pitch about +y: the nose goes down (Euler ZYX, as the server's)
  EXPECT_LT(s.forward().z(), 0.0);
  s.pitch = 0.0;
  s.roll = 0.1;  // positive roll about +x: the left side goes up
  EXPECT_GT(s.left().z(), 0.0);
}

TEST(DampedSpring, SettlesWithoutOvershoot) {
  DampedSpring sp(4.0);
  sp.update(0.0, 0.0);
  double last = 0.0;
  for (int i = 0; i < 200; ++i) {
    const double v = sp.update(1.0, 1.0 / 60);
    EXPECT_LE(v, 1.0 + 1e-12);
    EXPECT_GE(v, last - 1e-12);
    last = v;
  }
  EXPECT_NEAR(last, 1.0, 1e-3);
}

TEST(ChaseCamera, RestsBehindAndAboveLookingAhead) {
  ChaseCamera c;
  const Viewport vp{1280, 720};
  const CameraPose p = c.update(car(10, 20, kPi / 2), ViewChoice{}, vp, 0.0);
  // Heading north: the camera is south of the car, above it.
  EXPECT_NEAR(p.eye.x(), 10.0, 1e-9);
  EXPECT_NEAR(p.eye.y(), 20.0 - ChaseCamera::back_distance(4.5), 1e-9);
  EXPECT_NEAR(p.eye.z(), ChaseCamera::eye_height(1.45), 1e-9);
  // The car is in the lower half of the image, horizontally centred.
  const osg::Vec3d c0 = ndc(p, {10, 20, 0.7});
  EXPECT_NEAR(c0.x(), 0.0, 1e-9);
  EXPECT_LT(c0.y(), 0.0);
  EXPECT_GT(c0.y(), -1.0);
}

TEST(ChaseCamera, FollowsATurnSmoothlyWithoutJitter) {
  ChaseCamera c;
  const Viewport vp{1280, 720};
  c.update(car(0, 0, 0), ViewChoice{}, vp, 0.0);
  // The car turns 90° at once; frames come at an uneven 10..23 ms.
  double last = 0.0;
  double t = 0.0;
  for (int i = 0; i < 300; ++i) {
    const double dt = i % 2 == 0 ? 0.010 : 0.023;
    t += dt;
    const CameraPose p = c.update(car(0, 0, kPi / 2), ViewChoice{}, vp, dt);
    const double bearing = std::atan2(-p.eye.y(), -p.eye.x());  // from camera to car
    EXPECT_GE(bearing, last - 1e-9) << "swung back at frame " << i;
    EXPECT_LE(bearing, kPi / 2 + 1e-9) << "overshot at frame " << i;
    last = bearing;
    if (i == 0) {
      EXPECT_LT(bearing, 0.2);  // it does not snap
    }
  }
  EXPECT_NEAR(last, kPi / 2, 1e-3);
  EXPECT_GT(t, 3.0);
}

TEST(ChaseCamera, TurnsTheShortWayRoundAcrossPi) {
  ChaseCamera c;
  const Viewport vp{1280, 720};
  c.update(car(0, 0, kPi - 0.05), ViewChoice{}, vp, 0.0);
  const CameraPose p = c.update(car(0, 0, -kPi + 0.05), ViewChoice{}, vp, 1.0 / 60);
  // Still behind the car (east of it, heading west), not swinging through north or south.
  EXPECT_GT(p.eye.x(), 5.0);
  EXPECT_LT(std::abs(p.eye.y()), 1.0);
}

TEST(CockpitCamera, EyeLeftOfCentreLookingAlongTheCar) {
  CockpitCamera c;
  Subject s = car(0, 0, 0);
  const CameraPose p = c.update(s, ViewChoice{}, Viewport{}, 0.0);
  EXPECT_GT(p.eye.y(), 0.2);
  EXPECT_NEAR(p.eye.z(), 0.85 * s.height, 1e-9);
  const osg::Vec3d ahead = ndc(p, {50, p.eye.y(), p.eye.z()});
  EXPECT_NEAR(ahead.x(), 0.0, 1e-9);
  EXPECT_NEAR(ahead.y(), 0.0, 1e-9);
}

TEST(TopDownCamera, EightPixelsPerMetreHeadingUpCarSixtyPercentDown) {
  TopDownCamera c;
  const Viewport vp{1000, 800};
  const CameraPose p = c.update(car(100, 50, kPi), ViewChoice{}, vp, 0.0);
  const auto px = [&](const osg::Vec3d& w) {
    const osg::Vec3d n = ndc(p, w);
    return osg::Vec2d((n.x() + 1) / 2 * vp.width, (1 - n.y()) / 2 * vp.height);
  };
  const osg::Vec2d carpx = px({100, 50, 0});
  EXPECT_NEAR(carpx.x(), 500.0, 1e-6);
  EXPECT_NEAR(carpx.y(), 480.0, 1e-6);
  // 10 m ahead (west, heading pi) is 80 px up the screen.
  const osg::Vec2d ahead = px({90, 50, 0});
  EXPECT_NEAR(ahead.x(), 500.0, 1e-6);
  EXPECT_NEAR(ahead.y(), 400.0, 1e-6);
  // The car's left (south when heading west) is to the left on screen.
  EXPECT_LT(px({100, 45, 0}).x(), 500.0);
}

TEST(OrbitCamera, AtTheChosenAzimuthElevationAndDistance) {
  OrbitCamera c;
  ViewChoice ch;
  ch.orbit_azimuth_deg = 90.0;
  ch.orbit_elevation_deg = 30.0;
  ch.orbit_distance_m = 20.0;
  const CameraPose p = c.update(car(5, 5, 1.0), ch, Viewport{}, 0.0);
  EXPECT_NEAR(p.eye.x(), 5.0, 1e-9);
  EXPECT_NEAR(p.eye.y(), 5.0 + 20.0 * std::cos(kPi / 6), 1e-9);
  EXPECT_NEAR(p.eye.z(), 1.0 + 10.0, 1e-9);
}

TEST(MirrorCamera, LooksBackAndShowsLeftOnTheLeft) {
  MirrorCamera c;
  const CameraPose p = c.update(car(0, 0, 0), ViewChoice{}, Viewport{640, 200}, 0.0);
  // A car 20 m behind is in view; one behind and to the car's left (+y) appears on the left
  // of the mirror, as in a real mirror.
  const osg::Vec3d behind = ndc(p, {-20, 0, 1});
  EXPECT_LT(std::abs(behind.x()), 0.1);
  EXPECT_LT(ndc(p, {-20, 3, 1}).x(), behind.x());
}

TEST(Cameras, ParseAndNames) {
  for (int i = 0; i < kCameraModes; ++i) {
    const auto m = static_cast<CameraMode>(i);
    EXPECT_EQ(parse_camera(to_string(m)), m);
  }
  EXPECT_EQ(parse_camera("hood"), CameraMode::kCockpit);
  EXPECT_FALSE(parse_camera("drone").has_value());
}

}  // namespace
}  // namespace tb::client::view3d
