#pragma once
/// @file A vehicle made in code from the scenario's dimensions and colour: body, glasshouse and
/// roof, four wheels that steer and roll, headlights, brake and reversing lights, indicators
/// that blink, and a soft shadow. Updated from the (interpolated) state every frame.

#include <array>
#include <cstdint>

#include <osg/Geode>
#include <osg/Geometry>
#include <osg/MatrixTransform>
#include <osg/ref_ptr>

#include "common/wire/vehicle_state.hpp"
#include "sim-client/view3d/frame_input.hpp"

namespace tb::client::view3d {

/// Node masks: what each camera draws (the cockpit and the mirror leave out the own car).
inline constexpr unsigned kMaskWorld = 0x1;
inline constexpr unsigned kMaskVehicle = 0x2;
inline constexpr unsigned kMaskOwnVehicle = 0x4;
inline constexpr unsigned kMaskOverlay = 0x8;

/// Indicator cadence: 1.4 Hz, half on (UNECE R48: 90 ± 30 flashes a minute), timed by sim time
/// so that every view of a car blinks alike.
bool indicator_lit(std::int64_t sim_time_ns);

class MeshBuilder;

/// Triangles drawn for @p node (quads count two; a shared child counts once per parent): the
/// cost of one car, which the view draws 20–300 times.
std::size_t count_triangles(osg::Node& node);

/// One lamp group that is either lit or not: an unlit shape whose colour switches.
class Lamp {
 public:
  Lamp(osg::Vec4 on, osg::Vec4 off);
  /// The lamp's shape (boxes of @p shape), unlit, in the "off" colour.
  osg::ref_ptr<osg::Geode> build(MeshBuilder& shape);
  void set(bool lit);
  bool lit() const { return lit_; }

 private:
  osg::ref_ptr<osg::Vec4Array> colour_;
  osg::Vec4 on_, off_;
  bool lit_ = false;
};

class VehicleNode {
 public:
  explicit VehicleNode(const VehicleLook& look);
  osg::MatrixTransform* node() const { return root_.get(); }
  const VehicleLook& look() const { return look_; }

  /// Pose, wheels (steer from the road-wheel angle, spin from the wheel speeds integrated
  /// over sim time) and lamps from @p s.
  void update(const wire::VehicleState& s);
  void set_own(bool own);

  // What the lamps show now (tests).
  const Lamp& headlights() const { return head_; }
  const Lamp& brake_lights() const { return brake_; }
  const Lamp& reversing_lights() const { return reverse_; }
  const Lamp& left_indicators() const { return left_; }
  const Lamp& right_indicators() const { return right_; }
  double wheel_spin(int i) const { return spin_[static_cast<std::size_t>(i)]; }

 private:
  VehicleLook look_;
  osg::ref_ptr<osg::MatrixTransform> root_;
  std::array<osg::ref_ptr<osg::MatrixTransform>, 4> wheels_;  ///< FL, FR, RL, RR
  std::array<double, 4> spin_{};
  std::int64_t last_sim_ns_ = -1;
  Lamp head_, brake_, reverse_, left_, right_;
};

}  // namespace tb::client::view3d
