#include "sim-client/view3d/vehicle_node.hpp"

#include <algorithm>
#include <cmath>

#include <osg/BlendFunc>
#include <osg/Depth>
#include <osg/Geode>
#include <osg/PolygonOffset>

#include "sim-client/view3d/shapes.hpp"

namespace tb::client::view3d {
namespace {

constexpr double kBlinkPeriodNs = 0.7e9;

void unlit(osg::Node& n) {
  n.getOrCreateStateSet()->setMode(GL_LIGHTING,
                                   osg::StateAttribute::OFF | osg::StateAttribute::PROTECTED);
}

}  // namespace

bool indicator_lit(std::int64_t sim_time_ns) {
  const double phase =
      std::fmod(static_cast<double>(std::max<std::int64_t>(0, sim_time_ns)), kBlinkPeriodNs);
  return phase < kBlinkPeriodNs / 2;
}

Lamp::Lamp(osg::Vec4 on, osg::Vec4 off) : on_(on), off_(off) {}

osg::ref_ptr<osg::Geode> Lamp::build(MeshBuilder& shape) {
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(shape.build_overall(colour_, off_));
  unlit(*geode);
  lit_ = false;
  return geode;
}

void Lamp::set(bool lit) {
  if (lit == lit_ || !colour_)
    return;
  lit_ = lit;
  (*colour_)[0] = lit ? on_ : off_;
  colour_->dirty();
}

VehicleNode::VehicleNode(const VehicleLook& look)
    : look_(look),
      root_(new osg::MatrixTransform),
      head_({1.0f, 1.0f, 0.86f, 1}, {0.62f, 0.63f, 0.62f, 1}),
      brake_({1.0f, 0.08f, 0.05f, 1}, {0.38f, 0.03f, 0.03f, 1}),
      reverse_({1.0f, 1.0f, 1.0f, 1}, {0.55f, 0.55f, 0.55f, 1}),
      left_({1.0f, 0.62f, 0.0f, 1}, {0.42f, 0.25f, 0.05f, 1}),
      right_({1.0f, 0.62f, 0.0f, 1}, {0.42f, 0.25f, 0.05f, 1}) {
  root_->setName(look.id);
  root_->setDataVariance(osg::Object::DYNAMIC);
  const float L = std::max(1.0f, look.length_m), W = std::max(0.8f, look.width_m),
              H = std::max(0.8f, look.height_m);
  const float r = std::clamp(look.wheel_radius_m, 0.15f, 0.6f * H);
  const float clearance = std::min(0.55f * r, 0.25f);
  const osg::Vec4 paint(look.colour[0], look.colour[1], look.colour[2], 1.0f);
  const osg::Vec4 glass(0.10f, 0.13f, 0.17f, 1.0f);
  const osg::Vec4 trim(0.06f, 0.06f, 0.07f, 1.0f);

  MeshBuilder body;
  const float belt = 0.55f * H;
  body.box({-L / 2, -W / 2, clearance}, {L / 2, W / 2, belt}, paint);
  // Bumpers: a dark strip low at each end.
  body.box({L / 2 - 0.02f, -W / 2 + 0.02f, clearance},
           {L / 2 + 0.04f, W / 2 - 0.02f, clearance + 0.16f}, trim);
  body.box({-L / 2 - 0.04f, -W / 2 + 0.02f, clearance},
           {-L / 2 + 0.02f, W / 2 - 0.02f, clearance + 0.16f}, trim);
  // Glasshouse a little behind the middle, narrower than the body, with a painted roof.
  const float cab_back = -0.33f * L, cab_front = 0.17f * L, cab_w = 0.44f * W;
  body.box({cab_back, -cab_w, belt}, {cab_front, cab_w, 0.94f * H}, glass);
  body.box({cab_back - 0.01f, -cab_w - 0.01f, 0.94f * H}, {cab_front + 0.01f, cab_w + 0.01f, H},
           paint);
  osg::ref_ptr<osg::Geode> shell = new osg::Geode;
  shell->addDrawable(body.build());
  root_->addChild(shell);

  // Lamps (unlit: their colour is their light).
  const float lamp_z = 0.40f * H;
  auto lamp = [&](Lamp& l, std::initializer_list<std::pair<osg::Vec3, osg::Vec3>> boxes) {
    MeshBuilder m;
    for (const auto& [lo, hi] : boxes)
      m.box(lo, hi, {});
    root_->addChild(l.build(m));
  };
  const float fx = L / 2 + 0.005f, rx = -L / 2 - 0.005f, d = 0.03f;
  lamp(head_, {{{fx - d, -W / 2 + 0.16f, lamp_z - 0.06f}, {fx + d, -W / 2 + 0.46f, lamp_z + 0.06f}},
               {{fx - d, W / 2 - 0.46f, lamp_z - 0.06f}, {fx + d, W / 2 - 0.16f, lamp_z + 0.06f}}});
  lamp(brake_, {{{rx - d, -W / 2 + 0.08f, lamp_z}, {rx + d, -W / 2 + 0.36f, lamp_z + 0.12f}},
                {{rx - d, W / 2 - 0.36f, lamp_z}, {rx + d, W / 2 - 0.08f, lamp_z + 0.12f}}});
  lamp(reverse_, {{{rx - d, -W / 2 + 0.38f, lamp_z}, {rx + d, -W / 2 + 0.50f, lamp_z + 0.10f}},
                  {{rx - d, W / 2 - 0.50f, lamp_z}, {rx + d, W / 2 - 0.38f, lamp_z + 0.10f}}});
  // Indicators at the four corners, wrapping round the side so that they show from behind,
  // ahead and the side.
  auto corner = [&](float x, float y) {
    const float sx = x > 0 ? -1.0f : 1.0f, sy = y > 0 ? -1.0f : 1.0f;
    return std::pair<osg::Vec3, osg::Vec3>{
        {std::min(x, x + sx * 0.14f) - d, std::min(y, y + sy * 0.10f) - d, lamp_z + 0.07f},
        {std::max(x, x + sx * 0.14f) + d, std::max(y, y + sy * 0.10f) + d, lamp_z + 0.15f}};
  };
  lamp(left_, {corner(L / 2, W / 2), corner(-L / 2, W / 2)});
  lamp(right_, {corner(L / 2, -W / 2), corner(-L / 2, -W / 2)});

  // Wheels: axles half a wheelbase either side of the middle.
  const float wb = std::clamp(look.wheelbase_m, 0.5f * L, 0.9f * L) / 2;
  const float tr = std::clamp(look.track_m, 0.5f * W, W) / 2;
  osg::ref_ptr<osg::Node> wheel = make_wheel(r, std::min(0.24f, 0.14f * W));
  const osg::Vec3 at[4] = {{wb, tr, r}, {wb, -tr, r}, {-wb, tr, r}, {-wb, -tr, r}};
  for (int i = 0; i < 4; ++i) {
    auto& w = wheels_[static_cast<std::size_t>(i)];
    w = new osg::MatrixTransform(osg::Matrixd::translate(at[i]));
    w->setDataVariance(osg::Object::DYNAMIC);
    w->addChild(wheel);
    root_->addChild(w);
  }

  // A soft shadow: a dark translucent quad on the road under the car.
  MeshBuilder shadow;
  const float sx = L / 2 + 0.15f, sy = W / 2 + 0.12f;
  shadow.quad({-sx, -sy, 0.03f}, {sx, -sy, 0.03f}, {sx, sy, 0.03f}, {-sx, sy, 0.03f},
              {0.0f, 0.0f, 0.0f, 0.45f});
  osg::ref_ptr<osg::Geode> sg = new osg::Geode;
  sg->addDrawable(shadow.build());
  osg::StateSet* ss = sg->getOrCreateStateSet();
  ss->setMode(GL_BLEND, osg::StateAttribute::ON);
  ss->setAttributeAndModes(new osg::BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA));
  ss->setAttributeAndModes(new osg::Depth(osg::Depth::LEQUAL, 0.0, 1.0, false));
  ss->setAttributeAndModes(new osg::PolygonOffset(-4.0f, -8.0f));
  ss->setRenderingHint(osg::StateSet::TRANSPARENT_BIN);
  unlit(*sg);
  root_->addChild(sg);
  set_own(false);
}

void VehicleNode::set_own(bool own) {
  root_->setNodeMask(own ? kMaskOwnVehicle : kMaskVehicle);
}

void VehicleNode::update(const wire::VehicleState& s) {
  const osg::Quat q(s.roll, osg::X_AXIS, s.pitch, osg::Y_AXIS, s.yaw, osg::Z_AXIS);
  root_->setMatrix(osg::Matrixd::rotate(q) *
                   osg::Matrixd::translate(s.position[0], s.position[1], s.position[2]));

  const double dt = last_sim_ns_ < 0 || s.sim_time_ns < last_sim_ns_
                        ? 0.0
                        : static_cast<double>(s.sim_time_ns - last_sim_ns_) * 1e-9;
  last_sim_ns_ = s.sim_time_ns;
  const float r = std::max(0.15f, look_.wheel_radius_m);
  for (std::size_t i = 0; i < 4; ++i) {
    // Rolling forward turns the top of the wheel forward: positive about the axle (+y).
    spin_[i] = std::remainder(spin_[i] + s.wheel_speeds[i] / r * dt, 2.0 * 3.141592653589793);
    const double steer = i < 2 ? s.steering_angle : 0.0;
    const osg::Vec3d at = wheels_[i]->getMatrix().getTrans();
    wheels_[i]->setMatrix(osg::Matrixd::rotate(spin_[i], osg::Y_AXIS) *
                          osg::Matrixd::rotate(steer, osg::Z_AXIS) * osg::Matrixd::translate(at));
  }

  const auto has = [&](std::uint16_t bit) { return (s.lights & bit) != 0; };
  head_.set(has(wire::kLowBeam) || has(wire::kHighBeam));
  brake_.set(has(wire::kBrakeLights));
  reverse_.set(has(wire::kReverseLight));
  const bool blink = indicator_lit(s.sim_time_ns);
  left_.set(blink && (has(wire::kIndicatorLeft) || has(wire::kHazard)));
  right_.set(blink && (has(wire::kIndicatorRight) || has(wire::kHazard)));
}

}  // namespace tb::client::view3d
