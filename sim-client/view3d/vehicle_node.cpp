#include "sim-client/view3d/vehicle_node.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <osg/BlendFunc>
#include <osg/Depth>
#include <osg/Geode>
#include <osg/Material>
#include <osg/NodeVisitor>
#include <osg/PolygonOffset>
#include <osg/TriangleFunctor>

#include "sim-client/view3d/shapes.hpp"

namespace tb::client::view3d {
namespace {

constexpr double kBlinkPeriodNs = 0.7e9;

void unlit(osg::Node& n) {
  n.getOrCreateStateSet()->setMode(GL_LIGHTING,
                                   osg::StateAttribute::OFF | osg::StateAttribute::PROTECTED);
}

/// The side view of the body, x forward from the middle, z up from the ground.
struct BodyProfile {
  std::vector<osg::Vec2> top;  ///< lower body's top edge, front to back
  float bottom = 0.0f;         ///< underside (ground clearance)
  std::array<float, 2> axle_x{};
  float arch_r = 0.0f, axle_z = 0.0f;
  // Where the glasshouse stands on the lower body, and its roof.
  float screen_x = 0.0f, screen_z = 0.0f;  ///< foot of the windscreen
  float rear_x = 0.0f, rear_z = 0.0f;      ///< foot of the rear window
  float roof_front = 0.0f, roof_back = 0.0f;
};

BodyProfile body_profile(float L, float H, float clearance, float r, float wb) {
  BodyProfile p;
  p.bottom = clearance;
  p.axle_x = {wb, -wb};
  p.axle_z = r;
  p.arch_r = r + 0.05f;
  // Proportions of a saloon: bonnet over the front quarter of the length, boot lid over the
  // rear fifth, both at about 55–60 % of the height; the roof over the middle, so that a car
  // seen from above shows its paint at its centre.
  p.screen_x = 0.24f * L;
  p.screen_z = 0.58f * H;
  p.rear_x = -0.29f * L;
  p.rear_z = 0.60f * H;
  p.roof_front = 0.06f * L;
  p.roof_back = -0.17f * L;
  p.top = {{L / 2, 0.45f * H},   {L / 2 - 0.04f * L, 0.52f * H},  {p.screen_x, p.screen_z},
           {p.rear_x, p.rear_z}, {-L / 2 + 0.03f * L, 0.59f * H}, {-L / 2, 0.50f * H}};
  return p;
}

/// Height of the lower body's top edge at @p x (piecewise linear between the profile's points).
float top_at(const BodyProfile& p, float x) {
  for (std::size_t i = 0; i + 1 < p.top.size(); ++i) {
    const osg::Vec2 a = p.top[i], b = p.top[i + 1];
    if (x <= a.x() && x >= b.x())
      return a.y() + (b.y() - a.y()) * (a.x() - x) / (a.x() - b.x());
  }
  return p.top.back().y();
}

/// Height of the underside at @p x: the clearance, or the arch over a wheel.
float bottom_at(const BodyProfile& p, float x) {
  for (float ax : p.axle_x) {
    const float dx = x - ax;
    if (std::abs(dx) < p.arch_r)
      return p.axle_z + std::sqrt(p.arch_r * p.arch_r - dx * dx);
  }
  return p.bottom;
}

/// The lower body: the profile extruded across the width, in strips along x so that the top
/// follows the bonnet and boot and the underside follows the wheel arches (the wheels show
/// through them from the side; the arch linings are dark).
void extrude_lower_body(MeshBuilder& m, const BodyProfile& p, float W, const osg::Vec4& paint,
                        const osg::Vec4& lining) {
  std::vector<float> xs;
  for (const auto& t : p.top)
    xs.push_back(t.x());
  constexpr int kArchSteps = 6;
  for (float ax : p.axle_x) {
    // A hair inside each end of the arch, so that its sides rise straight from the sill.
    xs.push_back(ax - p.arch_r);
    xs.push_back(ax + p.arch_r);
    for (int i = 0; i <= kArchSteps; ++i)
      xs.push_back(ax - p.arch_r * 0.999f +
                   2 * p.arch_r * 0.999f * static_cast<float>(i) / kArchSteps);
  }
  std::sort(xs.begin(), xs.end(), std::greater<>());
  xs.erase(
      std::unique(xs.begin(), xs.end(), [](float a, float b) { return std::abs(a - b) < 1e-4f; }),
      xs.end());
  const float y = W / 2;
  for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
    const float x0 = xs[i], x1 = xs[i + 1];  // x0 ahead of x1
    const float t0 = top_at(p, x0), t1 = top_at(p, x1);
    const float b0 = bottom_at(p, x0 - 1e-4f), b1 = bottom_at(p, x1 + 1e-4f);
    m.quad({x1, y, b1}, {x1, y, t1}, {x0, y, t0}, {x0, y, b0}, paint);      // left (+y)
    m.quad({x0, -y, b0}, {x0, -y, t0}, {x1, -y, t1}, {x1, -y, b1}, paint);  // right
    m.quad({x0, -y, t0}, {x0, y, t0}, {x1, y, t1}, {x1, -y, t1}, paint);    // top
    const bool arch = b0 > p.bottom + 1e-3f || b1 > p.bottom + 1e-3f;
    m.quad({x1, -y, b1}, {x1, y, b1}, {x0, y, b0}, {x0, -y, b0}, arch ? lining : paint);
  }
  const float xf = xs.front(), xb = xs.back();
  m.quad({xf, -y, p.bottom}, {xf, y, p.bottom}, {xf, y, top_at(p, xf)}, {xf, -y, top_at(p, xf)},
         paint);  // nose
  m.quad({xb, y, p.bottom}, {xb, -y, p.bottom}, {xb, -y, top_at(p, xb)}, {xb, y, top_at(p, xb)},
         paint);  // tail
}

/// The glasshouse: windscreen and rear window raked, side windows narrowing to the roof
/// (tumblehome), painted roof and pillars. The glass is dark with a paler top (the sky it
/// reflects) and has the only specular material of the scene.
osg::ref_ptr<osg::Geode> make_glasshouse(const BodyProfile& p, float W, float H,
                                         const osg::Vec4& paint) {
  const osg::Vec4 dark(0.07f, 0.09f, 0.12f, 1.0f), sheen(0.30f, 0.38f, 0.48f, 1.0f);
  const float yb = 0.45f * W, yr = 0.37f * W;  // half widths at the belt and at the roof
  const osg::Vec3 fl(p.screen_x, yb, p.screen_z), fr(p.screen_x, -yb, p.screen_z);
  const osg::Vec3 bl(p.rear_x, yb, p.rear_z), br(p.rear_x, -yb, p.rear_z);
  const osg::Vec3 rfl(p.roof_front, yr, H), rfr(p.roof_front, -yr, H);
  const osg::Vec3 rbl(p.roof_back, yr, H), rbr(p.roof_back, -yr, H);
  osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array;
  osg::ref_ptr<osg::Vec3Array> n = new osg::Vec3Array;
  osg::ref_ptr<osg::Vec4Array> c = new osg::Vec4Array;
  // A quad with its bottom edge (a, b) dark and its top edge (c, d) in @p top.
  const auto quad = [&](const osg::Vec3& a, const osg::Vec3& b, const osg::Vec3& cc,
                        const osg::Vec3& d, const osg::Vec4& low, const osg::Vec4& top) {
    osg::Vec3 nn = (b - a) ^ (cc - a);
    nn.normalize();
    for (const auto& [pt, col] : {std::pair{a, low}, {b, low}, {cc, top}, {d, top}}) {
      v->push_back(pt);
      n->push_back(nn);
      c->push_back(col);
    }
  };
  quad(fr, fl, rfl, rfr, dark, sheen);  // windscreen
  quad(bl, br, rbr, rbl, dark, sheen);  // rear window
  quad(fl, bl, rbl, rfl, dark, sheen);  // left side window
  quad(br, fr, rfr, rbr, dark, sheen);  // right side window
  // Roof, a little proud of the glass so that it covers the top edges.
  const osg::Vec3 up(0, 0, 0.02f);
  quad(rfr + up, rfl + up, rbl + up, rbr + up, paint, paint);
  // Pillars: painted strips just outside the side glass (A at the windscreen, B in the middle,
  // C at the rear window).
  for (float side : {1.0f, -1.0f}) {
    const osg::Vec3 out(0, side * 0.006f, 0);
    const auto strip = [&](const osg::Vec3& foot, const osg::Vec3& head, float w) {
      const osg::Vec3 dx(w, 0, 0);
      if (side < 0)
        quad(foot + out - dx, foot + out + dx, head + out + dx, head + out - dx, paint, paint);
      else
        quad(foot + out + dx, foot + out - dx, head + out - dx, head + out + dx, paint, paint);
    };
    const float y0 = side * yb, y1 = side * yr;
    const float bx = 0.5f * (p.screen_x + p.rear_x), bz = 0.5f * (p.screen_z + p.rear_z);
    const float rx = 0.5f * (p.roof_front + p.roof_back);
    strip({p.screen_x - 0.05f, y0, p.screen_z}, {p.roof_front - 0.03f, y1, H}, 0.05f);
    strip({bx, y0, bz}, {rx, y1, H}, 0.05f);
    strip({p.rear_x + 0.08f, y0, p.rear_z}, {p.roof_back + 0.06f, y1, H}, 0.08f);
  }
  osg::ref_ptr<osg::Geometry> g = lit_geometry(v, n, c, GL_QUADS);
  osg::ref_ptr<osg::Geode> geode = new osg::Geode;
  geode->addDrawable(g);
  osg::ref_ptr<osg::Material> glass = new osg::Material;
  glass->setColorMode(osg::Material::AMBIENT_AND_DIFFUSE);
  glass->setSpecular(osg::Material::FRONT_AND_BACK, osg::Vec4(0.7f, 0.7f, 0.7f, 1));
  glass->setShininess(osg::Material::FRONT_AND_BACK, 48.0f);
  geode->getOrCreateStateSet()->setAttributeAndModes(glass);
  return geode;
}

}  // namespace

std::size_t count_triangles(osg::Node& node) {
  struct Count {
    std::size_t* n = nullptr;
    void operator()(const osg::Vec3&, const osg::Vec3&, const osg::Vec3&) const { ++*n; }
  };
  class Visitor : public osg::NodeVisitor {
   public:
    Visitor() : osg::NodeVisitor(TRAVERSE_ALL_CHILDREN) {}
    void apply(osg::Drawable& d) override {
      osg::TriangleFunctor<Count> f;
      f.n = &n;
      d.accept(f);
    }
    std::size_t n = 0;
  };
  Visitor v;
  node.accept(v);
  return v.n;
}

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
  const osg::Vec4 trim(0.06f, 0.06f, 0.07f, 1.0f);

  // Wheels: axles half a wheelbase either side of the middle.
  const float wb = std::clamp(look.wheelbase_m, 0.5f * L, 0.9f * L) / 2;
  const float tr = std::clamp(look.track_m, 0.5f * W, W) / 2;

  // The body as a three-box car: a lower body whose top runs from the nose up the bonnet to
  // the windscreen and from the rear window down the boot lid, with wheel arches cut into its
  // sides; on it a glasshouse with a raked windscreen and rear window, a painted roof and
  // pillars. The silhouette is lower at both ends than over the cabin, at 50 m as up close.
  MeshBuilder body;
  const BodyProfile profile = body_profile(L, H, clearance, r, wb);
  extrude_lower_body(body, profile, W, paint, trim);
  // Bumpers: a dark strip low at each end.
  body.box({L / 2 - 0.02f, -W / 2 + 0.02f, clearance},
           {L / 2 + 0.04f, W / 2 - 0.02f, clearance + 0.16f}, trim);
  body.box({-L / 2 - 0.04f, -W / 2 + 0.02f, clearance},
           {-L / 2 + 0.02f, W / 2 - 0.02f, clearance + 0.16f}, trim);
  osg::ref_ptr<osg::Geode> shell = new osg::Geode;
  shell->addDrawable(body.build());
  root_->addChild(shell);
  root_->addChild(make_glasshouse(profile, W, H, paint));
  // Lamps (unlit: their colour is their light).
  // Below the nose (45 % of the height) and the tail (50 %): the lamps sit in the body's ends.
  const float lamp_z = 0.36f * H;
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
        {std::min(x, x + sx * 0.14f) - d, std::min(y, y + sy * 0.10f) - d, lamp_z + 0.06f},
        {std::max(x, x + sx * 0.14f) + d, std::max(y, y + sy * 0.10f) + d, lamp_z + 0.13f}};
  };
  lamp(left_, {corner(L / 2, W / 2), corner(-L / 2, W / 2)});
  lamp(right_, {corner(L / 2, -W / 2), corner(-L / 2, -W / 2)});

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
