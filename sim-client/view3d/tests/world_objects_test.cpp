// Junction marks and road-side shapes from the OpenDRIVE model: where the marks lie (worked
// out by hand from the shipped four-way junction's geometry) and which shape each type gets.

#include <gtest/gtest.h>

#include <osg/Geode>
#include <osg/Geometry>
#include <osg/LOD>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "common/map/opendrive/reader.hpp"
#include "common/map/opendrive/signal_layout.hpp"
#include "sim-client/view3d/junction_marks.hpp"
#include "sim-client/view3d/road_node.hpp"
#include "sim-client/view3d/road_objects_node.hpp"
#include "sim-client/view3d/signal_heads_node.hpp"

namespace tb::client::view3d {
namespace {

namespace odr = map::odr;

std::filesystem::path maps_dir() {
  const char* root = std::getenv("TESTBED_ROOT");
  return std::filesystem::path(root != nullptr ? root : ".") / "scenarios" / "maps";
}

/// The arms' rise (generate.py smooth_rise: 0 to 3 m over 68 m, level at both ends).
double arm_z(double s) {
  const double f = s / 68.0;
  return 3.0 * (3 * f * f - 2 * f * f * f);
}

TEST(JunctionMarks, FourWayStopLinesAndCrossingsLieWhereTheArmsMeetTheJunction) {
  const odr::RoadNetwork net =
      odr::load_opendrive((maps_dir() / "four_way_junction.xodr").string());
  const auto quads = junction_mark_quads(net);
  int stops = 0, stripes = 0;
  for (const MarkQuad& q : quads) {
    double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
    for (const auto& c : q.corners) {
      x0 = std::min(x0, c[0]);
      x1 = std::max(x1, c[0]);
      y0 = std::min(y0, c[1]);
      y1 = std::max(y1, c[1]);
    }
    if (q.kind == MarkQuad::Kind::kStopLine) {
      ++stops;
      // The east arm (road 1) starts at x 12 heading east; lane 1 (towards the junction) is
      // y 0 to 3.5; the line is 0.5 m deep round s 4.5. The other arms are it turned by 90°.
      if (x0 > 10.0) {
        EXPECT_NEAR(x0, 16.25, 1e-6);
        EXPECT_NEAR(x1, 16.75, 1e-6);
        EXPECT_NEAR(y1, 3.5, 1e-6);
        for (const auto& c : q.corners)
          EXPECT_NEAR(c[2], arm_z(c[0] - 12.0) + kMarkLift, 1e-6);
      }
      // Each lies 16.25 to 16.75 m from the centre, on the lane left of its arm's heading
      // away from the junction (the lane towards it).
      const double near = std::min({std::fabs(x0), std::fabs(x1), std::fabs(y0), std::fabs(y1)});
      const double far = std::max({std::fabs(x0), std::fabs(x1), std::fabs(y0), std::fabs(y1)});
      EXPECT_NEAR(far, 16.75, 1e-6);
      EXPECT_NEAR(near, 0.0, 1e-6);
    } else if (q.kind == MarkQuad::Kind::kCrosswalk) {
      ++stripes;
      if (x0 > 10.0) {  // east arm: 3 m long over x 12.5 to 15.5, 0.5 m wide, within |y| <= 3.5
        EXPECT_NEAR(x0, 12.5, 1e-6);
        EXPECT_NEAR(x1, 15.5, 1e-6);
        EXPECT_NEAR(y1 - y0, 0.5, 1e-6);
        EXPECT_LE(std::fabs(y0), 3.5 + 1e-6);
        EXPECT_LE(std::fabs(y1), 3.5 + 1e-6);
      }
    }
  }
  EXPECT_EQ(stops, 4);
  // 7 m across: stripes at -3, -2, ..., 3 (seven), on each of the four arms.
  EXPECT_EQ(stripes, 4 * 7);
}

TEST(JunctionMarks, ArrowsAndStopLineObjectsAndSignalsWithoutWidth) {
  const std::string xml =
      R"(<?xml version="1.0"?><OpenDRIVE><header revMajor="1" revMinor="7"/>)"
      R"(<road id="1" length="50" junction="-1"><planView><geometry s="0" x="0" y="0" hdg="0" length="50"><line/></geometry></planView>)"
      R"(<lanes><laneSection s="0"><center><lane id="0" type="none"/></center><right><lane id="-1" type="driving"><width sOffset="0" a="3" b="0" c="0" d="0"/></lane></right></laneSection></lanes>)"
      R"(<objects><object id="a" type="roadMark" subtype="arrowStraight" s="20" t="-1.5" hdg="0" length="5" width="1"/>)"
      R"(<object id="b" type="roadMark" name="stopLine" s="30" t="-1.5" hdg="0" length="0.3" width="3"/>)"
      R"(<object id="c" type="roadMark" subtype="zigzag" s="35" t="-1.5" length="3" width="1"/></objects>)"
      R"(<signals><signal id="g" s="45" t="-1.5" orientation="+" country="DE" type="294"/></signals></road></OpenDRIVE>)";
  const auto net = odr::parse_opendrive(xml, "marks.xodr");
  const auto quads = junction_mark_quads(net);
  ASSERT_EQ(quads.size(), 4u);  // the arrow's shaft and head, two stop lines; no zigzag
  EXPECT_EQ(quads[0].kind, MarkQuad::Kind::kStopLine);  // signals first
  // The signal gives no width: the lane's, 3 m, across y -3 to 0.
  EXPECT_NEAR(quads[0].corners[0][1], -3.0, 1e-9);
  EXPECT_NEAR(quads[0].corners[2][1], 0.0, 1e-9);
  EXPECT_EQ(quads[1].kind, MarkQuad::Kind::kArrow);
  EXPECT_EQ(quads[2].kind, MarkQuad::Kind::kArrow);
  // The head's tip at the arrow's far end (s 22.5), on the lane's centre.
  EXPECT_NEAR(quads[2].corners[1][0], 22.5, 1e-9);
  EXPECT_NEAR(quads[2].corners[1][1], -1.5, 1e-9);
  EXPECT_EQ(quads[3].kind, MarkQuad::Kind::kStopLine);
  EXPECT_NEAR(quads[3].corners[0][0], 29.85, 1e-9);
}

TEST(RoadObjectsNode, ShapesByTypeAndTilesWithLevelOfDetail) {
  odr::RoadObject o;
  for (const auto& [type, shape] :
       std::initializer_list<std::pair<const char*, const char*>>{{"building", "building"},
                                                                  {"tree", "tree"},
                                                                  {"barrier", "wall"},
                                                                  {"soundBarrier", "wall"},
                                                                  {"pole", "pole"},
                                                                  {"streetLamp", "pole"},
                                                                  {"crosswalk", "mark"},
                                                                  {"obstacle", "box"},
                                                                  {"none", "box"}}) {
    o.type = type;
    EXPECT_EQ(shape_of(o), shape) << type;
  }
  o.type = "vegetation";
  o.radius = 2.0;
  EXPECT_EQ(shape_of(o), "tree");
  o.radius = 0.0;
  o.length = 20.0;
  o.width = 1.0;
  EXPECT_EQ(shape_of(o), "hedge");
  odr::RoadSignal stop;
  stop.type = "206";
  EXPECT_GT(plate_colour(stop)[0], 0.7f);
  EXPECT_LT(plate_colour(stop)[1], 0.2f);

  // The town: every house, tree, lamp and sign placed; tiles of 100 m over 480 m and the
  // streets' edges: 6 x 6 at most, each with a big and a small class.
  const odr::RoadNetwork net = odr::load_opendrive((maps_dir() / "town.xodr").string());
  ObjectsNodeStats st;
  osg::ref_ptr<osg::Node> node = make_road_objects_node(net, &st);
  EXPECT_GT(st.shapes, 800u);
  EXPECT_LE(st.tiles, 36u);
  EXPECT_GE(st.tiles, 25u);
  const osg::Group* g = node->asGroup();
  ASSERT_NE(g, nullptr);
  EXPECT_EQ(g->getNumChildren(), st.tiles);
  std::size_t small = 0;
  for (unsigned i = 0; i < g->getNumChildren(); ++i) {
    const auto* lod = dynamic_cast<const osg::LOD*>(g->getChild(i));
    ASSERT_NE(lod, nullptr);
    for (unsigned k = 0; k < lod->getNumChildren(); ++k) {
      if (lod->getMaxRange(k) == kSmallRange)
        ++small;
      else
        EXPECT_EQ(lod->getMaxRange(k), kBigRange);
    }
  }
  EXPECT_GE(small, 20u);
}

TEST(SignalHeadsNode, ThreeLampsPerHeadFacingTheTrafficLitByTheGroup) {
  const odr::RoadNetwork net =
      odr::load_opendrive((maps_dir() / "four_way_junction.xodr").string());
  const odr::SignalLayout layout(net);
  SignalHeadsNode heads(net);
  ASSERT_EQ(heads.heads(), layout.heads().size());
  ASSERT_EQ(heads.heads(), 4u);  // one light per arm
  using L = SignalHeadsNode;
  for (std::size_t i = 0; i < heads.heads(); ++i) {
    const odr::SignalHead& h = layout.heads()[i];
    const osg::Vec3d red = heads.lamp_centre(i, L::kRed), amber = heads.lamp_centre(i, L::kAmber),
                     green = heads.lamp_centre(i, L::kGreen);
    // Red over amber over green, within the head's height above its lower edge.
    EXPECT_GT(red.z(), amber.z());
    EXPECT_GT(amber.z(), green.z());
    EXPECT_GT(green.z(), h.pose.z);
    EXPECT_LT(red.z(), h.pose.z + h.height);
    // On the side the traffic comes from: against the traffic's heading from the head.
    const double along = (red.x() - h.pose.x) * std::cos(h.pose.heading) +
                         (red.y() - h.pose.y) * std::sin(h.pose.heading);
    EXPECT_NEAR(along, -0.13, 0.01);
    EXPECT_EQ(heads.lit(i), LampSet{});  // dark until a state comes
  }
  using P = wire::sim::MovementPhaseState;
  const std::uint16_t id = layout.junctions().front().intersection_id;
  const auto group = [&](std::size_t i) {
    return static_cast<std::uint8_t>(layout.heads()[i].signal_group);
  };
  std::vector<wire::sim::SignalGroupState> states = {
      {id, group(0), P::kStopAndRemain, 0, 0},
      {id, group(1), P::kPreMovement, 0, 0},
      {id, group(2), P::kProtectedClearance, 0, 0},
      {id, group(3), P::kProtectedMovementAllowed, 0, 0}};
  heads.update(states, 0);
  EXPECT_EQ(heads.lit(0), (LampSet{true, false, false}));
  EXPECT_EQ(heads.lit(1), (LampSet{true, true, false}));
  EXPECT_EQ(heads.lit(2), (LampSet{false, true, false}));
  EXPECT_EQ(heads.lit(3), (LampSet{false, false, true}));
  // Another intersection's group of the same number does not light them; nor does a message
  // without them.
  for (auto& s : states)
    s.intersection_id = static_cast<std::uint16_t>(id + 1);
  heads.update(states, 0);
  for (std::size_t i = 0; i < heads.heads(); ++i)
    EXPECT_EQ(heads.lit(i), LampSet{});
  // Out of the plan: flashing at 1 Hz; dark and unavailable: all off.
  EXPECT_EQ(lamps_for(P::kStopThenProceed, 200'000'000), (LampSet{true, false, false}));
  EXPECT_EQ(lamps_for(P::kStopThenProceed, 700'000'000), LampSet{});
  EXPECT_EQ(lamps_for(P::kCautionConflictingTraffic, 1'100'000'000), (LampSet{false, true, false}));
  EXPECT_EQ(lamps_for(P::kDark), LampSet{});
  EXPECT_EQ(lamps_for(P::kUnavailable), LampSet{});
  EXPECT_EQ(lamps_for(P::kPermissiveMovementAllowed), (LampSet{false, false, true}));
}

}  // namespace
}  // namespace tb::client::view3d
