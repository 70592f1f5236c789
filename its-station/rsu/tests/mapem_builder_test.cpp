// The MAPEM of a hand-made junction, with every expected offset worked out here from the roads
// written below, and of the shipped four-way junction, graded against its geometry.

#include "its-station/rsu/mapem_builder.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "common/geodesy/local_frame.hpp"
#include "common/map/opendrive/reader.hpp"

namespace tb::its::rsu {
namespace {

namespace odr = map::odr;
namespace msg = messages;

std::string lanes(double width) {
  const std::string w =
      "<width sOffset=\"0\" a=\"" + std::to_string(width) + "\" b=\"0\" c=\"0\" d=\"0\"/>";
  return "<lanes><laneSection s=\"0\"><left><lane id=\"1\" type=\"driving\">" + w +
         "</lane></left><center><lane id=\"0\" type=\"none\"/></center><right><lane id=\"-1\" "
         "type=\"driving\">" +
         w + "</lane></right></laneSection></lanes>";
}

/// Road "1" runs east from (0, 0) for 50 m (lanes 3.5 m, 50 km/h) into junction "9", whose
/// connecting road "10" goes on 10 m to road "3" (x 60..100, lanes 3.0 m, 30 km/h). Light L1
/// (controller 1) with stop line at s 46 for eastbound lane -1 of road 1; light L3
/// (controller 2) with stop line at s 4 for westbound lane 1 of road 3. @p stop1: s of S1.
std::string two_arm_junction(double stop1 = 46.0) {
  return std::string(R"(<?xml version="1.0"?><OpenDRIVE><header revMajor="1" revMinor="7"/>)") +
         R"(<road id="1" name="west arm" length="50" junction="-1"><link><successor elementType="junction" elementId="9"/></link>)"
         R"(<type s="0" type="town"><speed max="50" unit="km/h"/></type>)"
         R"(<planView><geometry s="0" x="0" y="0" hdg="0" length="50"><line/></geometry></planView>)" +
         lanes(3.5) +
         R"(<signals><signal id="L1" s="48" t="-5" zOffset="2" orientation="+" dynamic="yes" country="DE" type="1000001" height="0.9"><validity fromLane="-1" toLane="-1"/></signal>)"
         R"(<signal id="S1" s=")" +
         std::to_string(stop1) +
         R"(" t="-1.75" orientation="+" country="DE" type="294" width="3.5"/></signals></road>)"
         R"(<road id="10" length="10" junction="9"><link><predecessor elementType="road" elementId="1" contactPoint="end"/><successor elementType="road" elementId="3" contactPoint="start"/></link>)"
         R"(<planView><geometry s="0" x="50" y="0" hdg="0" length="10"><line/></geometry></planView>)"
         R"(<lanes><laneSection s="0"><left><lane id="1" type="driving"><link><predecessor id="1"/><successor id="1"/></link><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></left><center><lane id="0" type="none"/></center>)"
         R"(<right><lane id="-1" type="driving"><link><predecessor id="-1"/><successor id="-1"/></link><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></right></laneSection></lanes></road>)"
         R"(<road id="3" name="east arm" length="40" junction="-1"><link><predecessor elementType="junction" elementId="9"/></link>)"
         R"(<type s="0" type="town"><speed max="30" unit="km/h"/></type>)"
         R"(<planView><geometry s="0" x="60" y="0" hdg="0" length="40"><line/></geometry></planView>)" +
         lanes(3.0) +
         R"(<signals><signal id="L3" s="2" t="5" zOffset="2" orientation="-" dynamic="yes" country="DE" type="1000001" height="0.9"/>)"
         R"(<signal id="S3" s="4" t="1.5" orientation="-" country="DE" type="294" width="3"/></signals></road>)"
         R"(<controller id="1"><control signalId="L1"/></controller><controller id="2"><control signalId="L3"/></controller>)"
         R"(<junction id="9" name="two arms"><connection id="0" incomingRoad="1" connectingRoad="10" contactPoint="start"><laneLink from="-1" to="-1"/></connection>)"
         R"(<connection id="1" incomingRoad="3" connectingRoad="10" contactPoint="end"><laneLink from="1" to="1"/></connection>)"
         R"(<controller id="1"/><controller id="2"/></junction></OpenDRIVE>)";
}

const geodesy::Geodetic kOrigin{48.0, 11.0, 500.0};

const msg::GenericLane* lane(const msg::IntersectionGeometry& ig, msg::LaneID id) {
  for (const msg::GenericLane& l : ig.laneSet)
    if (l.laneID == id)
      return &l;
  return nullptr;
}

const msg::NodeSetXY& nodes(const msg::GenericLane& l) {
  return std::get<msg::NodeSetXY>(l.nodeList);
}

void expect_node(const msg::NodeXY& n, msg::NodeOffsetPointXY::Choice choice, int x, int y) {
  EXPECT_EQ(n.delta.choice, choice);
  EXPECT_EQ(n.delta.x, x);
  EXPECT_EQ(n.delta.y, y);
}

TEST(MapemBuilder, HandMadeJunctionHasItsLanesNodesAndConnections) {
  const odr::RoadNetwork net = odr::parse_opendrive(two_arm_junction(), "two_arms.xodr");
  const odr::SignalLayout layout(net);
  const geodesy::LocalFrame frame(kOrigin);
  const IntersectionMap m = MapemBuilder(net, layout, frame).build("9");
  ASSERT_TRUE(m.mapem->map.intersections.has_value());
  ASSERT_EQ(m.mapem->map.intersections->size(), 1u);
  const msg::IntersectionGeometry& ig = (*m.mapem->map.intersections)[0];
  EXPECT_EQ(ig.id.id, 9);
  EXPECT_EQ(m.mapem->header.messageID, msg::kMessageIdMapem);
  EXPECT_EQ(m.mapem->map.layerType, msg::LayerType::intersectionData);

  // refPoint: the connecting road's start (50, 0), placed by the origin.
  const geodesy::Enu ref = frame.to_enu({ig.refPoint.lat * 1e-7, ig.refPoint.long_ * 1e-7, 500.0});
  EXPECT_NEAR(ref.east, 50.0, 0.01);
  EXPECT_NEAR(ref.north, 0.0, 0.01);
  ASSERT_TRUE(ig.refPoint.elevation.has_value());
  EXPECT_NEAR(*ig.refPoint.elevation, 5000, 1);  // 500 m in 0.1 m

  EXPECT_EQ(ig.laneWidth, 350);  // the first ingress lane, 3.5 m
  ASSERT_TRUE(ig.speedLimits.has_value());
  ASSERT_EQ(ig.speedLimits->size(), 1u);
  EXPECT_EQ((*ig.speedLimits)[0].type, msg::SpeedLimitType::vehicleMaxSpeed);
  EXPECT_EQ((*ig.speedLimits)[0].speed, 417);  // the lower limit, 30 km/h in 0.02 m/s

  ASSERT_EQ(ig.laneSet.size(), 4u);
  using C = msg::NodeOffsetPointXY::Choice;
  // Lane 1: road 1 lane -1 (eastbound, centre t -1.75), stop line at s 46, up to s 0.
  const msg::GenericLane* l1 = lane(ig, 1);
  ASSERT_NE(l1, nullptr);
  EXPECT_EQ(l1->laneAttributes.directionalUse, msg::lane_direction::kIngressPath);
  ASSERT_EQ(nodes(*l1).size(), 2u);  // straight: two nodes
  expect_node(nodes(*l1)[0], C::node_XY1, (46 - 50) * 100, -175);
  expect_node(nodes(*l1)[1], C::node_XY5, -4600, 0);
  ASSERT_TRUE(nodes(*l1)[0].attributes.has_value());
  ASSERT_TRUE(nodes(*l1)[0].attributes->localNode.has_value());
  EXPECT_EQ((*nodes(*l1)[0].attributes->localNode)[0], msg::NodeAttributeXY::stopLine);
  EXPECT_FALSE(nodes(*l1)[0].attributes->dWidth.has_value());
  // Lane 2: road 3 lane 1 (westbound, 3.0 m: centre t 1.5), stop line at s 4 (x 64), up to s 40.
  const msg::GenericLane* l2 = lane(ig, 2);
  ASSERT_NE(l2, nullptr);
  ASSERT_EQ(nodes(*l2).size(), 2u);
  expect_node(nodes(*l2)[0], C::node_XY3, 1400, 150);  // Offset-B12
  expect_node(nodes(*l2)[1], C::node_XY4, 3600, 0);    // Offset-B13
  EXPECT_EQ(nodes(*l2)[0].attributes->dWidth, -50);    // 3.0 m against the 3.5 m default
  // Lane 3: egress road 1 lane 1 (westbound, t 1.75) from the junction end (x 50) to x 0.
  const msg::GenericLane* l3 = lane(ig, 3);
  ASSERT_NE(l3, nullptr);
  EXPECT_EQ(l3->laneAttributes.directionalUse, msg::lane_direction::kEgressPath);
  ASSERT_EQ(nodes(*l3).size(), 2u);
  expect_node(nodes(*l3)[0], C::node_XY1, 0, 175);
  expect_node(nodes(*l3)[1], C::node_XY5, -5000, 0);
  EXPECT_FALSE(l3->connectsTo.has_value());
  // Lane 4: egress road 3 lane -1 (eastbound, t -1.5) from x 60 to x 100.
  const msg::GenericLane* l4 = lane(ig, 4);
  ASSERT_NE(l4, nullptr);
  expect_node(nodes(*l4)[0], C::node_XY2, 1000, -150);  // Offset-B11
  expect_node(nodes(*l4)[1], C::node_XY4, 4000, 0);

  // Connections: straight on, each under its own controller's signal group.
  ASSERT_TRUE(l1->connectsTo.has_value());
  ASSERT_EQ(l1->connectsTo->size(), 1u);
  EXPECT_EQ((*l1->connectsTo)[0].connectingLane.lane, 4);
  EXPECT_EQ((*l1->connectsTo)[0].connectingLane.maneuver,
            msg::allowed_maneuvers::kManeuverStraightAllowed);
  EXPECT_EQ((*l1->connectsTo)[0].signalGroup, 1);
  ASSERT_TRUE(l2->connectsTo.has_value());
  ASSERT_EQ(l2->connectsTo->size(), 1u);
  EXPECT_EQ((*l2->connectsTo)[0].connectingLane.lane, 3);
  EXPECT_EQ((*l2->connectsTo)[0].signalGroup, 2);
  EXPECT_EQ(l1->ingressApproach, 1);  // road 1 is the first arm in the file
  EXPECT_EQ(l4->egressApproach, 2);

  // What the RSU sends decodes to what was built.
  const auto back = msg::decode_mapem(m.encoded);
  ASSERT_TRUE(back.has_value());
  EXPECT_TRUE(*back == *m.mapem);
}

TEST(MapemBuilder, RevisionStaysWithTheMapAndChangesWithIt) {
  const geodesy::LocalFrame frame(kOrigin);
  const odr::RoadNetwork a = odr::parse_opendrive(two_arm_junction(), "a.xodr");
  const odr::RoadNetwork b = odr::parse_opendrive(two_arm_junction(45.0), "b.xodr");
  const odr::SignalLayout la(a), lb(b);
  const IntersectionMap m1 = MapemBuilder(a, la, frame).build("9");
  const IntersectionMap m2 = MapemBuilder(a, la, frame).build("9");
  const IntersectionMap m3 = MapemBuilder(b, lb, frame).build("9");
  EXPECT_EQ(m1.encoded, m2.encoded);
  EXPECT_EQ(m1.mapem->map.msgIssueRevision, m1.revision);
  EXPECT_EQ((*m1.mapem->map.intersections)[0].revision, m1.revision);
  EXPECT_NE(m1.encoded, m3.encoded);
  EXPECT_NE(m1.revision, m3.revision);  // the stop line moved by 1 m
}

TEST(MapemBuilder, UnknownOrUnsignalisedJunctionIsRefusedByName) {
  const odr::RoadNetwork net = odr::parse_opendrive(two_arm_junction(), "two_arms.xodr");
  const odr::SignalLayout layout(net);
  const geodesy::LocalFrame frame(kOrigin);
  try {
    MapemBuilder(net, layout, frame).build("77");
    FAIL() << "junction 77 accepted";
  } catch (const odr::MapError& e) {
    EXPECT_NE(std::string(e.what()).find("77"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no such junction"), std::string::npos) << e.what();
  }
}

// A curved arm: road 1 an arc of radius 40 m turning left into the junction. Every node lies on
// the lane centre (radius 40 + 1.75 about the arc's centre), the polyline between them keeps
// within the 10 cm tolerance, and a curve takes more than two nodes.
TEST(MapemBuilder, CurvedLaneNodesFollowTheLaneCentre) {
  std::string xodr = two_arm_junction();
  // Replace road 1's straight line by an arc of curvature 1/40 ending heading east at (50, 0).
  const double R = 40.0, len = 50.0, phi = len / R;
  const double x0 = 50.0 - R * std::sin(phi), y0 = R * (1 - std::cos(phi));
  const std::string line = R"(<geometry s="0" x="0" y="0" hdg="0" length="50"><line/></geometry>)";
  const std::string arc = "<geometry s=\"0\" x=\"" + std::to_string(x0) + "\" y=\"" +
                          std::to_string(y0) + "\" hdg=\"" + std::to_string(-phi) +
                          "\" length=\"50\"><arc curvature=\"" + std::to_string(1.0 / R) +
                          "\"/></geometry>";
  xodr.replace(xodr.find(line), line.size(), arc);
  const odr::RoadNetwork net = odr::parse_opendrive(xodr, "curved.xodr");
  const odr::SignalLayout layout(net);
  const geodesy::LocalFrame frame(kOrigin);
  const IntersectionMap m = MapemBuilder(net, layout, frame).build("9");
  const msg::IntersectionGeometry& ig = (*m.mapem->map.intersections)[0];
  const msg::GenericLane* l1 = lane(ig, 1);
  ASSERT_NE(l1, nullptr);
  const msg::NodeSetXY& ns = nodes(*l1);
  EXPECT_GT(ns.size(), 4u);
  // The arc's centre is R to the left of its end (50, 0) heading east: (50, 40). Lane -1 lies
  // on the right of the reference line: radius R + 1.75.
  const double cx = 50.0, cy = R;
  double x = 50.0, y = 0.0;  // the refPoint: the connecting road's start
  double px = 0, py = 0;
  for (std::size_t i = 0; i < ns.size(); ++i) {
    x += ns[i].delta.x / 100.0;
    y += ns[i].delta.y / 100.0;
    EXPECT_NEAR(std::hypot(x - cx, y - cy), R + 1.75, 0.015) << "node " << i;
    if (i > 0) {
      // The chord's midpoint is no further inside the lane centre than the tolerance.
      const double mx = (x + px) / 2, my = (y + py) / 2;
      EXPECT_LT(R + 1.75 - std::hypot(mx - cx, my - cy), 0.10 + 0.015) << "chord " << i;
    }
    px = x;
    py = y;
  }
}

// The shipped four-way junction: every approach of its SignalLayout is an ingress lane with its
// group, starting at its stop line; its three manoeuvres turn the way the egress lanes lie.
TEST(MapemBuilder, ShippedFourWayJunction) {
  const char* root = std::getenv("TESTBED_ROOT");
  const std::string file =
      std::string(root != nullptr ? root : ".") + "/scenarios/maps/four_way_junction.xodr";
  const odr::RoadNetwork net = odr::load_opendrive(file);
  const odr::SignalLayout layout(net);
  const geodesy::LocalFrame frame(kOrigin);
  const IntersectionMap m = MapemBuilder(net, layout, frame).build("100");
  const msg::IntersectionGeometry& ig = (*m.mapem->map.intersections)[0];
  EXPECT_EQ(ig.id.id, 100);
  const geodesy::Enu ref = frame.to_enu(
      {ig.refPoint.lat * 1e-7, ig.refPoint.long_ * 1e-7, ig.refPoint.elevation.value_or(0) / 10.0});
  const geodesy::Enu centre =
      junction_centre(net, static_cast<std::size_t>(net.junction_index("100")));

  int ingress = 0;
  for (const odr::SignalApproach& a : layout.approaches()) {
    if (a.intersection_id != 100)
      continue;
    ++ingress;
    const MappedLane* ml = nullptr;
    for (const MappedLane& x : m.lanes)
      if (x.ingress && x.road == a.road && x.lane == a.lane)
        ml = &x;
    ASSERT_NE(ml, nullptr) << "approach road " << net.roads[a.road].id << " lane " << a.lane;
    const msg::GenericLane* gl = lane(ig, ml->lane_id);
    ASSERT_NE(gl, nullptr);
    // The first node is the stop line (cm from the refPoint, which is the junction's centre).
    const msg::NodeSetXY& ns = nodes(*gl);
    EXPECT_NEAR(ns[0].delta.x / 100.0 + centre.east, a.stop.x, 0.011);
    EXPECT_NEAR(ns[0].delta.y / 100.0 + centre.north, a.stop.y, 0.011);
    // The second node lies upstream: against the direction of travel.
    EXPECT_LT(std::cos(a.stop.heading) * ns[1].delta.x + std::sin(a.stop.heading) * ns[1].delta.y,
              0.0);
    ASSERT_TRUE(gl->connectsTo.has_value());
    EXPECT_EQ(gl->connectsTo->size(), 3u);  // left, straight, right
    msg::AllowedManeuvers seen = 0;
    for (const msg::Connection& c : *gl->connectsTo) {
      EXPECT_EQ(c.signalGroup, a.signal_group);
      const MappedLane* out = nullptr;
      for (const MappedLane& x : m.lanes)
        if (!x.ingress && x.lane_id == c.connectingLane.lane)
          out = &x;
      ASSERT_NE(out, nullptr);
      // Where the egress lane starts, seen from the stop line facing the direction of travel.
      const double dx = out->first_x - a.stop.x, dy = out->first_y - a.stop.y;
      const double ahead = std::cos(a.stop.heading) * dx + std::sin(a.stop.heading) * dy;
      const double left = -std::sin(a.stop.heading) * dx + std::cos(a.stop.heading) * dy;
      const msg::AllowedManeuvers mv = c.connectingLane.maneuver.value_or(0);
      seen |= mv;
      if (mv == msg::allowed_maneuvers::kManeuverStraightAllowed)
        EXPECT_LT(std::fabs(left), 2.0);
      else if (mv == msg::allowed_maneuvers::kManeuverLeftAllowed)
        EXPECT_GT(left, 5.0);
      else if (mv == msg::allowed_maneuvers::kManeuverRightAllowed)
        EXPECT_LT(left, -5.0);
      else
        ADD_FAILURE() << "unexpected manoeuvre " << mv;
      EXPECT_GT(ahead, 0.0);
    }
    EXPECT_EQ(seen, msg::allowed_maneuvers::kManeuverStraightAllowed |
                        msg::allowed_maneuvers::kManeuverLeftAllowed |
                        msg::allowed_maneuvers::kManeuverRightAllowed);
  }
  EXPECT_EQ(ingress, 4);
  EXPECT_EQ(ig.laneSet.size(), 8u);  // and one egress lane per arm
  EXPECT_NEAR(ref.east, centre.east, 0.02);
  EXPECT_NEAR(ref.north, centre.north, 0.02);
  ASSERT_TRUE(ig.speedLimits.has_value());
  EXPECT_EQ((*ig.speedLimits)[0].speed, 694);  // 50 km/h in 0.02 m/s
  const auto back = msg::decode_mapem(m.encoded);
  ASSERT_TRUE(back.has_value());
  EXPECT_TRUE(*back == *m.mapem);
}

}  // namespace
}  // namespace tb::its::rsu
