#include "sim-client/view3d/signal_heads_node.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <spdlog/spdlog.h>
#include <osg/Geode>
#include <osg/MatrixTransform>

#include "common/map/opendrive/signal_layout.hpp"
#include "sim-client/view3d/shapes.hpp"

namespace tb::client::view3d {
namespace {

namespace odr = map::odr;
using P = wire::sim::MovementPhaseState;

// A vehicle signal head of 200 mm lamps (EN 12368's smaller size) in a housing of the file's
// width and height (defaults: 0.3 m by 0.9 m, what the shipped maps give), 0.25 m deep.
constexpr double kDepth = 0.25;
constexpr double kDefaultWidth = 0.3;
constexpr double kDefaultHeight = 0.9;
constexpr double kLampRadius = 0.1;
constexpr float kFaceGap = 0.005f;  // m in front of the housing: no depth fight with it
const osg::Vec4 kHousing(0.08f, 0.08f, 0.08f, 1.0f);

// Lit: the colours of the lights (unlit by the scene's sun, so as bright by day as a real
// lamp); dark: the lens without light.
const std::array<osg::Vec4, 3> kOn = {osg::Vec4(1.0f, 0.1f, 0.06f, 1.0f),
                                      osg::Vec4(1.0f, 0.68f, 0.0f, 1.0f),
                                      osg::Vec4(0.1f, 1.0f, 0.45f, 1.0f)};
const std::array<osg::Vec4, 3> kOff = {osg::Vec4(0.2f, 0.05f, 0.04f, 1.0f),
                                       osg::Vec4(0.2f, 0.14f, 0.03f, 1.0f),
                                       osg::Vec4(0.04f, 0.18f, 0.1f, 1.0f)};

bool flash_on(std::int64_t sim_time_ns) {
  // 1 Hz, half on: the flashing of a signal out of its plan.
  const std::int64_t ms = (sim_time_ns / 1'000'000) % 1000;
  return (ms < 0 ? ms + 1000 : ms) < 500;
}

}  // namespace

LampSet lamps_for(P s, std::int64_t sim_time_ns) {
  LampSet l;
  switch (s) {
    case P::kStopAndRemain:
      l.red = true;
      break;
    case P::kPreMovement:
      l.red = l.amber = true;
      break;
    case P::kPermissiveClearance:
    case P::kProtectedClearance:
      l.amber = true;
      break;
    case P::kPermissiveMovementAllowed:
    case P::kProtectedMovementAllowed:
      l.green = true;
      break;
    case P::kStopThenProceed:
      l.red = flash_on(sim_time_ns);
      break;
    case P::kCautionConflictingTraffic:
      l.amber = flash_on(sim_time_ns);
      break;
    case P::kUnavailable:
    case P::kDark:
      break;
  }
  return l;
}

SignalHeadsNode::SignalHeadsNode(const odr::RoadNetwork& net) : root_(new osg::Group) {
  root_->setName("signal heads");
  std::unique_ptr<odr::SignalLayout> layout;
  try {
    layout = std::make_unique<odr::SignalLayout>(net);
  } catch (const std::exception& e) {
    spdlog::warn("traffic lights not drawn: {}", e.what());
    return;
  }
  for (const odr::SignalHead& h : layout->heads()) {
    Head head;
    head.signal_group = h.signal_group;
    if (const odr::SignalGroup* g = layout->group(h.signal_group); g != nullptr) {
      for (const odr::SignalisedJunction& j : layout->junctions())
        if (g->junction >= 0 && j.junction == static_cast<std::size_t>(g->junction))
          head.intersection_id = j.intersection_id;
    }
    const double w = h.signal != nullptr && h.signal->width > 0 ? h.signal->width : kDefaultWidth;
    const double ht = h.height > 0 ? h.height : kDefaultHeight;
    // Local frame: x along the traffic's direction, z up; the lamps face the oncoming traffic
    // (-x), red at the top (EN 12368 / Vienna Convention order).
    osg::ref_ptr<osg::MatrixTransform> xf = new osg::MatrixTransform;
    const osg::Vec3d at(h.pose.x, h.pose.y, h.pose.z);
    const osg::Matrixd m =
        osg::Matrixd::rotate(h.pose.heading, osg::Vec3d(0, 0, 1)) * osg::Matrixd::translate(at);
    xf->setMatrix(m);
    MeshBuilder housing;
    housing.box(osg::Vec3(static_cast<float>(-kDepth / 2), static_cast<float>(-w / 2), 0.0f),
                osg::Vec3(static_cast<float>(kDepth / 2), static_cast<float>(w / 2),
                          static_cast<float>(ht)),
                kHousing);
    osg::ref_ptr<osg::Geode> body = new osg::Geode;
    body->addDrawable(housing.build());
    xf->addChild(body);
    const double r = std::min(kLampRadius, std::min(w, ht / 3.0) * 0.4);
    const float x = static_cast<float>(-kDepth / 2) - kFaceGap;
    for (int i = 0; i < 3; ++i) {
      const double zc = ht * (5 - 2 * i) / 6.0;  // red, amber, green from the top
      MeshBuilder disc;
      // An octagon in three quads, counter-clockwise seen from the traffic (-x, where +y is to
      // the viewer's left): angle a at (y, z) = (-r cos a, zc + r sin a).
      std::array<osg::Vec3, 8> p;
      for (int k = 0; k < 8; ++k) {
        const double a = std::numbers::pi / 8 + k * std::numbers::pi / 4;
        p[static_cast<std::size_t>(k)] = osg::Vec3(x, static_cast<float>(-r * std::cos(a)),
                                                   static_cast<float>(zc + r * std::sin(a)));
      }
      disc.quad(p[0], p[1], p[2], p[3], kOff[i]);
      disc.quad(p[0], p[3], p[4], p[7], kOff[i]);
      disc.quad(p[7], p[4], p[5], p[6], kOff[i]);
      head.lamps[static_cast<std::size_t>(i)] = std::make_unique<Lamp>(kOn[i], kOff[i]);
      xf->addChild(head.lamps[static_cast<std::size_t>(i)]->build(disc));
      head.centres[static_cast<std::size_t>(i)] = osg::Vec3d(x, 0.0, zc) * m;
    }
    root_->addChild(xf);
    heads_.push_back(std::move(head));
  }
}

void SignalHeadsNode::update(std::span<const wire::sim::SignalGroupState> states,
                             std::int64_t sim_time_ns) {
  for (Head& h : heads_) {
    LampSet on;
    if (h.signal_group > 0) {
      for (const wire::sim::SignalGroupState& g : states) {
        if (g.intersection_id == h.intersection_id && g.signal_group == h.signal_group) {
          on = lamps_for(g.state, sim_time_ns);
          break;
        }
      }
    }
    h.lamps[kRed]->set(on.red);
    h.lamps[kAmber]->set(on.amber);
    h.lamps[kGreen]->set(on.green);
  }
}

osg::Vec3d SignalHeadsNode::lamp_centre(std::size_t head, LampIndex lamp) const {
  return heads_.at(head).centres[static_cast<std::size_t>(lamp)];
}

LampSet SignalHeadsNode::lit(std::size_t head) const {
  const Head& h = heads_.at(head);
  return {h.lamps[kRed]->lit(), h.lamps[kAmber]->lit(), h.lamps[kGreen]->lit()};
}

}  // namespace tb::client::view3d
