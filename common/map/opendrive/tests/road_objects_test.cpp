// Objects and signals read from hand-made files, and placed in the world: positions worked out
// by hand from the road's line and elevation.

#include "common/map/opendrive/road_objects.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "common/map/opendrive/reader.hpp"

namespace tb::map::odr {
namespace {

constexpr double kPi = std::numbers::pi;

/// A 100 m road from (10, 20) heading north (pi/2), rising 2 m + 0.1 per metre, with @p items
/// (the <objects> and <signals> elements) inside.
std::string road_with(const std::string& items) {
  return R"(<?xml version="1.0"?><OpenDRIVE><header revMajor="1" revMinor="7"/>)"
         R"(<road id="r7" length="100" junction="-1"><planView><geometry s="0" x="10" y="20" hdg="1.5707963267948966" length="100"><line/></geometry></planView>)"
         R"(<elevationProfile><elevation s="0" a="2" b="0.1" c="0" d="0"/></elevationProfile>)"
         R"(<lanes><laneSection s="0"><center><lane id="0" type="none"/></center><right><lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></right></laneSection></lanes>)" +
         items + "</road></OpenDRIVE>";
}

void expect_error(const std::string& items, const std::string& path, const std::string& reason) {
  try {
    parse_opendrive(road_with(items), "bad.xodr");
    ADD_FAILURE() << "no error for " << items;
  } catch (const MapError& e) {
    EXPECT_EQ(e.path(), path) << e.what();
    EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("bad.xodr: ", 0), 0u) << e.what();
  }
}

TEST(RoadObjects, ReadWithEveryAttribute) {
  const RoadNetwork net = parse_opendrive(
      road_with(
          R"(<objects><object id="b1" type="building" subtype="house" name="Town hall" s="30" t="-4" zOffset="0.5" hdg="0.25" pitch="0" roll="0" orientation="+" length="12" width="8" height="9"/>)"
          R"(<object id="p1" type="pole" s="40" t="3" radius="0.1" height="4"/>)"
          R"(<objectReference id="b9" s="50" t="-2" orientation="-"/></objects>)"
          R"(<signals><signal id="s1" name="Halt" s="90" t="-1.75" zOffset="0" hOffset="0.1" orientation="-" dynamic="no" country="DE" type="294" subtype="-1" width="3.5" height="0.5"/>)"
          R"(<signal id="s2" s="80" t="-5" zOffset="2" orientation="+" dynamic="yes" country="DE" type="274" subtype="53" value="50" unit="km/h" height="0.6" width="0.6"/>)"
          R"(<signalReference id="x3" s="10" t="2" orientation="+"/></signals>)"),
      "ok.xodr");
  const Road& r = net.roads[0];
  ASSERT_EQ(r.objects.size(), 2u);
  const RoadObject& b = r.objects[0];
  EXPECT_EQ(b.id, "b1");
  EXPECT_EQ(b.type, "building");
  EXPECT_EQ(b.subtype, "house");
  EXPECT_EQ(b.name, "Town hall");
  EXPECT_EQ(b.s, 30.0);
  EXPECT_EQ(b.t, -4.0);
  EXPECT_EQ(b.z_offset, 0.5);
  EXPECT_EQ(b.hdg, 0.25);
  EXPECT_EQ(b.orientation, "+");
  EXPECT_EQ(b.length, 12.0);
  EXPECT_EQ(b.width, 8.0);
  EXPECT_EQ(b.height, 9.0);
  EXPECT_EQ(r.objects[1].radius, 0.1);
  ASSERT_EQ(r.object_references.size(), 1u);
  EXPECT_EQ(r.object_references[0].id, "b9");
  EXPECT_EQ(r.object_references[0].orientation, "-");
  ASSERT_EQ(r.signals.size(), 2u);
  const RoadSignal& g = r.signals[0];
  EXPECT_EQ(g.name, "Halt");
  EXPECT_EQ(g.country, "DE");
  EXPECT_EQ(g.type, "294");
  EXPECT_FALSE(g.dynamic);
  EXPECT_FALSE(g.value.has_value());
  EXPECT_TRUE(is_stop_line(g));
  EXPECT_EQ(g.width, 3.5);
  const RoadSignal& v = r.signals[1];
  EXPECT_TRUE(v.dynamic);
  EXPECT_EQ(v.subtype, "53");
  ASSERT_TRUE(v.value.has_value());
  EXPECT_EQ(*v.value, 50.0);
  EXPECT_EQ(v.unit, "km/h");
  EXPECT_EQ(v.z_offset, 2.0);
  EXPECT_FALSE(is_stop_line(v));
  ASSERT_EQ(r.signal_references.size(), 1u);
  EXPECT_EQ(r.signal_references[0].s, 10.0);
}

TEST(RoadObjects, PosesFromTheReferenceLineAndElevation) {
  const RoadNetwork net = parse_opendrive(
      road_with(
          R"(<objects><object id="b1" type="building" s="30" t="-4" zOffset="0.5" hdg="0.25" length="12" width="8" height="9"/></objects>)"
          R"(<signals><signal id="s1" s="90" t="-1.75" orientation="-" hOffset="0.1" country="DE" type="294"/><signal id="s2" s="80" t="-5" zOffset="2" orientation="+" type="274"/></signals>)"),
      "ok.xodr");
  const Road& r = net.roads[0];
  // Heading north: +t is west (-x). s = 30, t = -4: x = 10 + 4, y = 20 + 30; z = 2 + 3 + 0.5.
  const auto placed = place_object(r, r.objects[0]);
  ASSERT_EQ(placed.size(), 1u);
  EXPECT_NEAR(placed[0].pose.x, 14.0, 1e-9);
  EXPECT_NEAR(placed[0].pose.y, 50.0, 1e-9);
  EXPECT_NEAR(placed[0].pose.z, 5.5, 1e-9);
  EXPECT_NEAR(placed[0].pose.heading, kPi / 2 + 0.25, 1e-9);
  EXPECT_EQ(placed[0].length, 12.0);
  // A "-" signal is for traffic heading south: pi/2 + pi, turned by hOffset 0.1.
  const ItemPose a = signal_pose(r, r.signals[0]);
  EXPECT_NEAR(a.x, 11.75, 1e-9);
  EXPECT_NEAR(a.y, 110.0, 1e-9);
  EXPECT_NEAR(a.z, 11.0, 1e-9);
  EXPECT_NEAR(a.heading, 1.5 * kPi + 0.1, 1e-9);
  const ItemPose b = signal_pose(r, r.signals[1]);
  EXPECT_NEAR(b.x, 15.0, 1e-9);
  EXPECT_NEAR(b.y, 100.0, 1e-9);
  EXPECT_NEAR(b.z, 2.0 + 8.0 + 2.0, 1e-9);
  EXPECT_NEAR(b.heading, kPi / 2, 1e-9);
}

TEST(RoadObjects, RepeatsMakeCopiesOrPieces) {
  const RoadNetwork net = parse_opendrive(
      road_with(
          R"(<objects><object id="t" type="tree" s="0" t="0" radius="1" height="6"><repeat s="10" length="40" distance="10" tStart="-6" tEnd="-6" zOffsetStart="0" zOffsetEnd="0"/></object>)"
          R"(<object id="w" type="barrier" s="0" t="0" width="0.3" height="1"><repeat s="20" length="12" distance="0" tStart="5" tEnd="5" heightStart="1" heightEnd="2" zOffsetStart="0" zOffsetEnd="0"/></object></objects>)"),
      "ok.xodr");
  const Road& r = net.roads[0];
  // Trees at s 10, 20, 30, 40, 50, 6 m right of the line (east: x = 16).
  const auto trees = place_object(r, r.objects[0]);
  ASSERT_EQ(trees.size(), 5u);
  for (std::size_t i = 0; i < trees.size(); ++i) {
    EXPECT_NEAR(trees[i].pose.x, 16.0, 1e-9);
    EXPECT_NEAR(trees[i].pose.y, 20.0 + 10.0 * static_cast<double>(i + 1), 1e-9);
    EXPECT_EQ(trees[i].radius, 1.0);
  }
  // The wall: 12 m in pieces of at most 5 m (3 of 4 m), 5 m left (x = 5), along the road,
  // growing from 1 m to 2 m tall (the middle piece at 1.5 m).
  const auto wall = place_object(r, r.objects[1]);
  ASSERT_EQ(wall.size(), 3u);
  double along = 0.0;
  for (const auto& p : wall) {
    EXPECT_NEAR(p.pose.x, 5.0, 1e-9);
    EXPECT_NEAR(p.pose.heading, kPi / 2, 1e-9);
    EXPECT_NEAR(p.width, 0.3, 1e-12);
    along += p.length;
  }
  EXPECT_NEAR(along, 12.0, 1e-9);
  EXPECT_NEAR(wall[1].pose.y, 20.0 + 20.0 + 6.0, 1e-9);
  EXPECT_NEAR(wall[1].height, 1.5, 1e-9);
}

TEST(RoadObjects, OutlineBoundingBoxGivesCentreAndSize) {
  // The origin at one corner, as crest-curve.xodr's Building1 has it: u 0..20, v 0..-10.
  const RoadNetwork net = parse_opendrive(
      road_with(
          R"(<objects><object id="b" type="building" s="50" t="-10" hdg="0" length="1" width="1" height="1"><outlines><outline id="1" closed="true">)"
          R"(<cornerLocal u="0" v="0" z="0" height="7"/><cornerLocal u="0" v="-10" z="0" height="7"/><cornerLocal u="20" v="-10" z="0" height="7"/><cornerLocal u="20" v="0" z="0" height="7"/></outline></outlines></object></objects>)"),
      "ok.xodr");
  const auto p = place_object(net.roads[0], net.roads[0].objects[0]);
  ASSERT_EQ(p.size(), 1u);
  // Heading north: u is north, v west; the centre is u 10, v -5: 5 m further east, 10 m north.
  EXPECT_NEAR(p[0].pose.x, 10.0 + 10.0 + 5.0, 1e-9);
  EXPECT_NEAR(p[0].pose.y, 20.0 + 50.0 + 10.0, 1e-9);
  EXPECT_EQ(p[0].length, 20.0);
  EXPECT_EQ(p[0].width, 10.0);
  EXPECT_EQ(p[0].height, 7.0);
}

TEST(RoadObjects, BadValuesNameRoadItemAndAttribute) {
  expect_error(R"(<objects><object id="b1" s="30" t="x"/></objects>)",
               "road[@id='r7']/objects/object[@id='b1']",
               "attribute 't' is not a finite number: 'x'");
  expect_error(R"(<objects><object id="b1" s="130" t="1"/></objects>)",
               "road[@id='r7']/objects/object[@id='b1']", "attribute 's' is 130, outside the road");
  expect_error(R"(<objects><object id="b1" s="30" t="1" height="-2"/></objects>)",
               "road[@id='r7']/objects/object[@id='b1']", "attribute 'height' is -2, not a size");
  expect_error(R"(<objects><object s="30" t="1"/></objects>)", "road[@id='r7']/objects/object[1]",
               "attribute 'id' missing");
  expect_error(R"(<objects><object id="b1" s="30" t="1" orientation="up"/></objects>)",
               "road[@id='r7']/objects/object[@id='b1']",
               "attribute 'orientation' must be '+', '-' or 'none', got 'up'");
  expect_error(
      R"(<objects><object id="t" s="0" t="0"><repeat s="10" length="40" distance="0.001" tStart="0" tEnd="0"/></object></objects>)",
      "road[@id='r7']/objects/object[@id='t']/repeat[1]", "more than 10000 copies");
  expect_error(
      R"(<objects><object id="t" s="0" t="0"><repeat s="10" length="95" distance="1" tStart="0" tEnd="0"/></object></objects>)",
      "road[@id='r7']/objects/object[@id='t']/repeat[1]", "the repeat must lie on the road");
  expect_error(R"(<signals><signal id="g" s="3" t="1" dynamic="maybe"/></signals>)",
               "road[@id='r7']/signals/signal[@id='g']",
               "attribute 'dynamic' must be 'yes' or 'no', got 'maybe'");
  expect_error(R"(<signals><signal id="g" s="3" t="1" value="fifty"/></signals>)",
               "road[@id='r7']/signals/signal[@id='g']",
               "attribute 'value' is not a finite number");
  expect_error(R"(<signals><signalReference id="g" s="3"/></signals>)",
               "road[@id='r7']/signals/signalReference[@id='g']", "attribute 't' missing");
}

}  // namespace
}  // namespace tb::map::odr
