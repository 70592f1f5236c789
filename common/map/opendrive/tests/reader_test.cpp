// The importer on the shared esmini maps and on every bad-input case the issue lists.

#include "common/map/opendrive/reader.hpp"
#include "common/map/opendrive/tests/shared_maps.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace tb::map::odr {
namespace {

namespace fs = std::filesystem;

using test::shared_maps;

std::vector<fs::path> all_shared_maps() {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(shared_maps())) {
    if (e.path().extension() == ".xodr")
      files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(SharedMaps, EveryFileLoads) {
  const auto files = all_shared_maps();
  ASSERT_EQ(files.size(), 13u) << "the README lists 13 maps under " << shared_maps();
  for (const auto& f : files) {
    SCOPED_TRACE(f.string());
    const RoadNetwork net = load_opendrive(f.string());
    EXPECT_FALSE(net.roads.empty());
    for (const Road& r : net.roads) {
      EXPECT_FALSE(r.geometries.empty());
      EXPECT_FALSE(r.sections.empty());
    }
  }
}

TEST(SharedMaps, ConsecutiveGeometriesMeetWithinAMillimetre) {
  for (const auto& f : all_shared_maps()) {
    const RoadNetwork net = load_opendrive(f.string());
    for (const Road& r : net.roads) {
      for (std::size_t i = 0; i + 1 < r.geometries.size(); ++i) {
        const Geometry& g = *r.geometries[i];
        const Geometry& next = *r.geometries[i + 1];
        const RefPoint end = g.at(next.s0() - g.s0());
        EXPECT_LT(std::hypot(end.x - next.start().x, end.y - next.start().y), 1e-3)
            << f.filename() << " road " << r.id << " geometry " << i + 1;
        EXPECT_LT(std::fabs(std::remainder(end.hdg - next.start().hdg, 2 * M_PI)), 1e-3)
            << f.filename() << " road " << r.id << " geometry " << i + 1;
      }
    }
  }
}

TEST(SharedMaps, LaneBordersAreContinuousAcrossLaneSections) {
  int checked = 0;
  for (const auto& f : all_shared_maps()) {
    const RoadNetwork net = load_opendrive(f.string());
    for (const Road& r : net.roads) {
      for (std::size_t k = 0; k + 1 < r.sections.size(); ++k) {
        const double s = r.sections[k + 1].s;
        const LaneBorders before = r.borders(k, s);
        const LaneBorders after = r.borders(k + 1, s);
        EXPECT_NEAR(before.center, after.center, 1e-3);
        for (const auto* side : {&r.sections[k].left, &r.sections[k].right}) {
          for (const Lane& lane : *side) {
            if (!lane.successor || r.sections[k + 1].lane(*lane.successor) == nullptr)
              continue;
            if (lane.width.value(s - r.sections[k].s) < 1e-3)
              continue;  // ends here
            const int next = *lane.successor;
            EXPECT_NEAR(before.outer(lane.id), after.outer(next), 1e-3)
                << f.filename() << " road " << r.id << " section " << k + 1 << " lane " << lane.id;
            EXPECT_NEAR(before.inner(lane.id), after.inner(next), 1e-3)
                << f.filename() << " road " << r.id << " section " << k + 1 << " lane " << lane.id;
            ++checked;
          }
        }
      }
    }
  }
  EXPECT_GT(checked, 10);
}

TEST(SharedMaps, FourWayIntersectionModel) {
  const RoadNetwork net =
      load_opendrive((shared_maps() / "simple_4way_intersection.xodr").string());
  EXPECT_EQ(net.header.rev_major, 1);
  EXPECT_EQ(net.header.rev_minor, 5);
  ASSERT_EQ(net.junctions.size(), 1u);
  EXPECT_EQ(net.junctions[0].connections.size(), 12u);
  const Road& r0 = net.roads[static_cast<std::size_t>(net.road_index("0"))];
  ASSERT_TRUE(r0.successor);
  EXPECT_TRUE(r0.successor->to_junction);
  EXPECT_EQ(r0.successor->index, 0);
  EXPECT_NEAR(*r0.speed_limit(50), 10.0, 1e-12);
  const Road& c = net.roads[static_cast<std::size_t>(net.road_index("100"))];
  EXPECT_EQ(c.junction_index, 0);
  EXPECT_EQ(c.sections[0].right[0].marks[0].type, "solid");
  EXPECT_NEAR(c.sections[0].right[0].marks[0].width, 0.2, 1e-12);
  // The connecting road ends where road 1 starts.
  const Road& r1 = net.roads[static_cast<std::size_t>(net.road_index("1"))];
  const RefPoint end = c.reference(c.length);
  const RefPoint start = r1.reference(0);
  EXPECT_LT(std::hypot(end.x - start.x, end.y - start.y), 1e-3);
}

TEST(SharedMaps, ElevationAndSuperelevationAreRead) {
  // The file's records, each a + b*ds + c*ds^2 + d*ds^3 with ds = s - record s:
  //   elevation s=250: 0 + 0.006 ds^2 - 4.0e-5 ds^3; s=350: 20 - 0.006 ds^2 + 4.0e-5 ds^3;
  //   s=450: 0.
  //   superelevation s=50: 0.00015 ds^2 - 1.0e-6 ds^3; s=150: 0.5 - 0.00015 ds^2 + 1.0e-6 ds^3;
  //   s=250: 0.
  const RoadNetwork net =
      load_opendrive((shared_maps() / "straight_500_superelevation_elevation_curve.xodr").string());
  ASSERT_EQ(net.roads.size(), 1u);
  const Road& r = net.roads[0];
  struct Expected {
    double s, height, roll;
  };
  const Expected expected[] = {
      {100, 0.0, 0.00015 * 50 * 50 - 1.0e-6 * 50 * 50 * 50},        // 0.375 - 0.125 = 0.25
      {150, 0.0, 0.5},                                              // the s=150 record's a
      {200, 0.0, 0.5 - 0.00015 * 50 * 50 + 1.0e-6 * 50 * 50 * 50},  // 0.25
      {275, 0.006 * 25 * 25 - 4.0e-5 * 25 * 25 * 25, 0.0},          // 3.75 - 0.625 = 3.125
      {300, 0.006 * 50 * 50 - 4.0e-5 * 50 * 50 * 50, 0.0},          // 15 - 5 = 10
      {350, 20.0, 0.0},                                             // the s=350 record's a
      {400, 20 - 0.006 * 50 * 50 + 4.0e-5 * 50 * 50 * 50, 0.0},     // 20 - 15 + 5 = 10
      {475, 0.0, 0.0},
  };
  EXPECT_DOUBLE_EQ(expected[0].roll, 0.25);
  EXPECT_DOUBLE_EQ(expected[4].height, 10.0);
  for (const Expected& e : expected) {
    SCOPED_TRACE("s = " + std::to_string(e.s));
    EXPECT_NEAR(r.elevation.value(e.s), e.height, 1e-9);
    EXPECT_NEAR(r.superelevation.value(e.s), e.roll, 1e-9);
    // 3 m left of the reference line a roll of `roll` (positive raises the left) lifts the
    // surface by 3 tan(roll): 3 tan(0.25) = 0.76603 m, 3 tan(0.5) = 1.63891 m.
    EXPECT_NEAR(r.surface(e.s, 3.0).z, e.height + 3.0 * std::tan(e.roll), 1e-9);
    EXPECT_NEAR(r.surface(e.s, -3.0).z, e.height - 3.0 * std::tan(e.roll), 1e-9);
  }
  EXPECT_NEAR(r.surface(150, 3.0).z, 1.63891, 1e-5);
}

TEST(SharedMaps, LeftHandTrafficAndParamPoly3) {
  const RoadNetwork net = load_opendrive((shared_maps() / "e6mini-lht.xodr").string());
  bool lht = false;
  for (const Road& r : net.roads)
    lht |= r.left_hand_traffic;
  EXPECT_TRUE(lht);
  bool param = false;
  for (const Road& r : net.roads) {
    for (const auto& g : r.geometries)
      param |= dynamic_cast<const ParamPoly3*>(g.get()) != nullptr;
  }
  EXPECT_TRUE(param);
}

TEST(SharedMaps, ObjectsAreReadByType) {
  // crest-curve.xodr's <object>s by type, counted in the file by hand (and by
  // `xmllint --xpath 'count(//object[@type="obstacle"])'`): 2 vegetation, 3 obstacle,
  // 1 building, 1 none, 2 barrier; two barriers and one hedge repeat.
  const RoadNetwork net = load_opendrive((shared_maps() / "crest-curve.xodr").string());
  std::map<std::string, int> by_type;
  int repeated = 0;
  for (const RoadObject& o : net.roads[0].objects) {
    ++by_type[o.type];
    repeated += o.repeats.empty() ? 0 : 1;
  }
  EXPECT_EQ(by_type,
            (std::map<std::string, int>{
                {"vegetation", 2}, {"obstacle", 3}, {"building", 1}, {"none", 1}, {"barrier", 2}}));
  EXPECT_EQ(repeated, 3);
  const RoadObject& b = net.roads[0].objects[2];
  EXPECT_EQ(b.name, "Building1");
  EXPECT_EQ(b.s, 250.0);
  EXPECT_EQ(b.t, -5.0);
  EXPECT_EQ(b.length, 25.0);
  EXPECT_EQ(b.width, 10.0);
  EXPECT_EQ(b.height, 10.0);
  EXPECT_EQ(b.hdg, -0.15);
  ASSERT_EQ(b.outline.size(), 4u);
  EXPECT_EQ(net.roads[0].signals.size(), 0u);
}

TEST(SharedMaps, LaneLinksWrittenFromTheConnectingRoadAreReadSwapped) {
  // highway_merge's connection 2 gives from = the connecting road's lane, to = the incoming
  // road's: read the other way round, with one warning naming it.
  const RoadNetwork net = load_opendrive((shared_maps() / "highway_merge.xodr").string());
  const Connection& c = net.junctions[0].connections[2];
  ASSERT_EQ(c.lane_links.size(), 1u);
  EXPECT_EQ(c.lane_links[0].from, -3);
  EXPECT_EQ(c.lane_links[0].to, -1);
  ASSERT_EQ(net.warnings.size(), 1u);
  EXPECT_NE(net.warnings[0].find("junction[@id='1']/connection[@id='2']"), std::string::npos);
}

// ---- bad input: each case names the file, the element and the reason ----------------------

std::string road_xml(const std::string& id, const std::string& body_override = "",
                     const std::string& link = "", const std::string& lanes = "") {
  const std::string plan =
      body_override.empty()
          ? R"(<planView><geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry></planView>)"
          : body_override;
  const std::string lane_xml =
      lanes.empty()
          ? R"(<lanes><laneSection s="0"><center><lane id="0" type="none"/></center><right><lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></right></laneSection></lanes>)"
          : lanes;
  return "<road id=\"" + id + "\" length=\"100\" junction=\"-1\">" + link + plan + lane_xml +
         "</road>";
}

std::string doc(const std::string& body) {
  return "<?xml version=\"1.0\"?><OpenDRIVE><header revMajor=\"1\" revMinor=\"6\"/>" + body +
         "</OpenDRIVE>";
}

void expect_error(const std::string& xml, const std::string& path, const std::string& reason) {
  try {
    parse_opendrive(xml, "bad.xodr");
    ADD_FAILURE() << "no error for: " << reason;
  } catch (const MapError& e) {
    EXPECT_EQ(e.file(), "bad.xodr");
    EXPECT_EQ(e.path(), path) << e.what();
    EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("bad.xodr: ", 0), 0u) << e.what();
  }
}

// ---- OpenDRIVE 1.6/1.7 elements the geometry does not apply: one warning each ---------------

std::vector<std::string> warnings_naming(const RoadNetwork& net, const std::string& what) {
  std::vector<std::string> out;
  for (const std::string& w : net.warnings) {
    if (w.find(what) != std::string::npos)
      out.push_back(w);
  }
  return out;
}

TEST(NotApplied, HeaderOffsetIsNamedWithItsValues) {
  const std::string xml =
      R"(<?xml version="1.0"?><OpenDRIVE><header revMajor="1" revMinor="6"><offset x="100.5" y="-20" z="3" hdg="0.1"/></header>)" +
      road_xml("7") + "</OpenDRIVE>";
  const RoadNetwork net = parse_opendrive(xml, "shifted.xodr");
  const auto w = warnings_naming(net, "<offset");
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0],
            "shifted.xodr: header/offset: <offset x=\"100.5\" y=\"-20\" z=\"3\" hdg=\"0.1\"> "
            "(the inertial frame's shift; coordinates are the file's) not applied");
  // The coordinates stay the file's: the road starts at (0, 0), heading 0, height 0.
  const SurfacePose p = net.roads[0].surface(0, 0);
  EXPECT_NEAR(p.x, 0.0, 1e-12);
  EXPECT_NEAR(p.y, 0.0, 1e-12);
  EXPECT_NEAR(p.z, 0.0, 1e-12);
  EXPECT_NEAR(p.heading, 0.0, 1e-12);
  // A zero offset changes nothing and is not worth a warning.
  const std::string zero =
      R"(<?xml version="1.0"?><OpenDRIVE><header><offset x="0" y="0" z="0" hdg="0"/></header>)" +
      road_xml("7") + "</OpenDRIVE>";
  EXPECT_TRUE(warnings_naming(parse_opendrive(zero, "zero.xodr"), "offset").empty());
}

TEST(NotApplied, LaneHeightIsNamedWithRoadLaneAndValues) {
  const std::string lanes =
      R"(<lanes><laneSection s="0"><right><lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane><lane id="-2" type="sidewalk"><width sOffset="0" a="2" b="0" c="0" d="0"/><height sOffset="0" inner="0.15" outer="0.12"/><height sOffset="40" inner="0" outer="0"/></lane></right></laneSection></lanes>)";
  const RoadNetwork net = parse_opendrive(doc(road_xml("9", "", "", lanes)), "kerb.xodr");
  const auto w = warnings_naming(net, "<height");
  ASSERT_EQ(w.size(), 1u);  // the second record raises nothing
  EXPECT_EQ(w[0],
            "kerb.xodr: road[@id='9']/lanes/laneSection[1]/right/lane[@id='-2']/height[1]: "
            "<height inner=\"0.15\" outer=\"0.12\"> (the lane lies on the road surface) "
            "not applied");
  // The sidewalk lies on the road surface (a flat road: height 0), its outer border at
  // t = -(3.5 + 2) = -5.5.
  const Road& r = net.roads[0];
  EXPECT_NEAR(r.borders(0, 10).outer(-2), -5.5, 1e-12);
  EXPECT_NEAR(r.surface(10, -5.5).z, 0.0, 1e-12);
}

TEST(NotApplied, LevelLaneOnABankedRoadIsNamed) {
  const std::string plan =
      R"(<planView><geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry></planView><lateralProfile><superelevation s="0" a="0.05" b="0" c="0" d="0"/></lateralProfile>)";
  const std::string lanes =
      R"(<lanes><laneSection s="0"><right><lane id="-1" type="driving" level="true"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></right></laneSection></lanes>)";
  const RoadNetwork net = parse_opendrive(doc(road_xml("4", plan, "", lanes)), "level.xodr");
  const auto w = warnings_naming(net, "level=");
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0],
            "level.xodr: road[@id='4']/lanes/laneSection[1]/right/lane[@id='-1']: level=\"true\" "
            "(the lane is tilted with the road's superelevation) not applied");
  EXPECT_TRUE(net.roads[0].sections[0].right[0].level);
  // Tilted as the rest of the road: 3.5 m right of the reference line, 3.5 tan(0.05) lower.
  EXPECT_NEAR(net.roads[0].surface(50, -3.5).z, -3.5 * std::tan(0.05), 1e-12);
  EXPECT_NEAR(-3.5 * std::tan(0.05), -0.17515, 1e-5);
  // On a road that does not bank, level="true" changes nothing and is not named.
  const RoadNetwork flat = parse_opendrive(doc(road_xml("4", "", "", lanes)), "flat.xodr");
  EXPECT_TRUE(warnings_naming(flat, "level=").empty());
}

TEST(BadInput, MalformedXml) {
  expect_error("<OpenDRIVE><road id=\"1\"></OpenDRIVE>", "", "malformed XML");
  expect_error("", "", "malformed XML");
  expect_error("<Foo/>", "", "no <OpenDRIVE> root element");
}

TEST(BadInput, AbsurdNumbersAreRefusedBeforeTheyReachTheLaneIndex) {
  // A coordinate of 1e300 (what the fuzzer found), a lane 1e9 m wide, a road of 1000 km, a
  // curve of a 1 mm radius, a lane width that grows to kilometres within its section.
  expect_error(
      doc(road_xml(
          "5",
          R"(<planView><geometry s="0" x="1e300" y="0" hdg="0" length="100"><line/></geometry></planView>)")),
      "road[@id='5']/planView/geometry[1]",
      "attribute 'x' is 1e300, beyond the largest magnitude a map may give");
  expect_error(
      doc(road_xml(
          "5", "", "",
          R"(<lanes><laneSection s="0"><right><lane id="-1" type="driving"><width sOffset="0" a="1e9" b="0" c="0" d="0"/></lane></right></laneSection></lanes>)")),
      "road[@id='5']/lanes/laneSection[1]/right/lane[@id='-1']/width[1]", "attribute 'a' is 1e9");
  expect_error(
      doc(road_xml(
          "5", "", "",
          R"(<lanes><laneSection s="0"><right><lane id="-1" type="driving"><width sOffset="0" a="3" b="0" c="0" d="1"/></lane></right></laneSection></lanes>)")),
      "road[@id='5']/lanes/laneSection[1]", "more than a map may have (1000 m)");
  std::string long_road = road_xml("5");
  long_road.replace(long_road.find("length=\"100\""), 12, "length=\"1e6\"");
  expect_error(doc(long_road), "road[@id='5']", "longer than a road may be (100 km)");
  expect_error(
      doc(road_xml(
          "5",
          R"(<planView><geometry s="0" x="0" y="0" hdg="0" length="100"><arc curvature="1000"/></geometry></planView>)")),
      "road[@id='5']/planView", "tighter than a road may turn");
}

TEST(BadInput, MissingPlanView) {
  expect_error(doc(R"(<road id="5" length="10"><lanes/></road>)"), "road[@id='5']",
               "no <planView>");
  expect_error(doc(road_xml("5", "<planView/>")), "road[@id='5']/planView",
               "planView has no <geometry>");
}

TEST(BadInput, GeometryOfZeroOrNegativeLength) {
  const std::string two =
      R"(<planView><geometry s="0" x="0" y="0" hdg="0" length="50"><line/></geometry><geometry s="50" x="50" y="0" hdg="0" length="LEN"><line/></geometry></planView>)";
  for (const std::string len : {"0", "-3", "nan"}) {
    std::string pv = two;
    pv.replace(pv.find("LEN"), 3, len);
    expect_error(doc(road_xml("5", pv)), "road[@id='5']/planView/geometry[2]",
                 len == "nan" ? "not a finite number" : "length must be > 0");
  }
}

TEST(BadInput, UnknownGeometryElement) {
  expect_error(
      doc(road_xml(
          "a b",
          R"(<planView><geometry s="0" x="0" y="0" hdg="0" length="5"><bezier/></geometry></planView>)")),
      "road[@id='a b']/planView/geometry[1]", "unknown geometry element <bezier>");
}

TEST(BadInput, LaneWithoutWidth) {
  expect_error(
      doc(road_xml(
          "7", "", "",
          R"(<lanes><laneSection s="0"><right><lane id="-1" type="driving"/></right></laneSection></lanes>)")),
      "road[@id='7']/lanes/laneSection[1]/right/lane[@id='-1']", "lane has no <width> or <border>");
}

TEST(BadInput, LinkToMissingRoadOrJunction) {
  expect_error(
      doc(road_xml(
          "1", "",
          R"(<link><successor elementType="road" elementId="9" contactPoint="start"/></link>)")),
      "road[@id='1']/link/successor", "road '9' does not exist");
  expect_error(
      doc(road_xml("1", "", R"(<link><predecessor elementType="junction" elementId="J"/></link>)")),
      "road[@id='1']/link/predecessor", "junction 'J' does not exist");
  expect_error(
      doc(road_xml("1") +
          R"(<junction id="3"><connection id="0" incomingRoad="1" connectingRoad="44" contactPoint="start"/></junction>)"),
      "junction[@id='3']/connection[@id='0']", "connectingRoad '44' does not exist");
}

TEST(BadInput, ConnectionToMissingLane) {
  const std::string roads =
      road_xml("1", "", R"(<link><successor elementType="junction" elementId="3"/></link>)") +
      road_xml("2");
  expect_error(
      doc(roads +
          R"(<junction id="3"><connection id="0" incomingRoad="1" connectingRoad="2" contactPoint="start"><laneLink from="-1" to="-2"/></connection></junction>)"),
      "junction[@id='3']/connection[@id='0']/laneLink[1]",
      "lane -2 does not exist on road '2' at its start");
  expect_error(
      doc(roads +
          R"(<junction id="3"><connection id="0" incomingRoad="1" connectingRoad="2" contactPoint="start"><laneLink from="4" to="-1"/></connection></junction>)"),
      "junction[@id='3']/connection[@id='0']/laneLink[1]",
      "lane 4 does not exist on incoming road '1' at its end");
}

TEST(BadInput, LaneLinkToMissingLane) {
  const std::string lanes =
      R"(<lanes><laneSection s="0"><right><lane id="-1" type="driving"><link><successor id="-3"/></link><width sOffset="0" a="3"/></lane></right></laneSection>)"
      R"(<laneSection s="50"><right><lane id="-1" type="driving"><width sOffset="0" a="3"/></lane></right></laneSection></lanes>)";
  expect_error(doc(road_xml("1", "", "", lanes)),
               "road[@id='1']/lanes/laneSection[1]/right/lane[@id='-1']/link/successor",
               "lane -3 does not exist in the next lane section of road '1'");
}

TEST(BadInput, DuplicateIdsAndBadNumbers) {
  expect_error(doc(road_xml("1") + road_xml("1")), "road[@id='1']", "duplicate road id '1'");
  expect_error(
      doc(road_xml(
          "1",
          R"(<planView><geometry s="0" x="1e999" y="0" hdg="0" length="5"><line/></geometry></planView>)")),
      "road[@id='1']/planView/geometry[1]", "attribute 'x' is not a finite number: '1e999'");
  expect_error(
      doc(road_xml(
          "1",
          R"(<planView><geometry s="0" y="0" hdg="0" length="5"><line/></geometry></planView>)")),
      "road[@id='1']/planView/geometry[1]", "attribute 'x' missing");
}

TEST(Reader, StringIdsSpeedUnitsAndSkippedElements) {
  const std::string road =
      R"(<road id="main street" length="100" junction="-1"><type s="0" type="town"><speed max="50" unit="km/h"/></type>)"
      R"(<planView><geometry s="0" x="0" y="0" hdg="0" length="100"><paramPoly3 aU="0" bU="100" cU="0" dU="0" aV="0" bV="0" cV="0" dV="0"/></geometry></planView>)"
      R"(<lateralProfile><superelevation s="0" a="0.05"/><crossfall side="both" s="0" a="0.02"/></lateralProfile>)"
      R"(<lanes><laneOffset s="0" a="1.5"/><laneSection s="0"><left><lane id="1" type="sidewalk"><border sOffset="0" a="2"/></lane></left><right><lane id="-1" type="driving"><width sOffset="0" a="3.5"/><roadMark sOffset="0" type="broken" color="white" width="0.15"/><speed sOffset="0" max="30" unit="mph"/></lane></right></laneSection></lanes>)"
      R"(<objects><object id="o1" s="1" t="5"/><object id="o2" s="2" t="-5"/><tunnel id="tu" s="50" length="10"/></objects><signals><signal id="s1" s="3" t="-4"/><signalReference id="s2" s="4" t="4"/></signals></road>)";
  const RoadNetwork net = parse_opendrive(doc(road) + "", "ok.xodr");
  ASSERT_EQ(net.roads.size(), 1u);
  const Road& r = net.roads[0];
  EXPECT_EQ(r.id, "main street");
  EXPECT_NEAR(*r.speed_limit(10), 50 / 3.6, 1e-12);
  EXPECT_EQ(r.objects.size(), 2u);
  EXPECT_EQ(r.signals.size(), 1u);
  EXPECT_EQ(r.signal_references.size(), 1u);
  ASSERT_EQ(net.warnings.size(), 2u);
  EXPECT_EQ(net.warnings[0], "1 <tunnel>/<bridge> skipped");
  EXPECT_NE(net.warnings[1].find("crossfall"), std::string::npos);
  const Lane& right = r.sections[0].right[0];
  EXPECT_TRUE(right.drivable);
  EXPECT_FALSE(r.sections[0].left[0].drivable);
  EXPECT_NEAR(right.speeds[0].max, 30 * 0.44704, 1e-12);
  EXPECT_EQ(right.marks[0].type, "broken");
  EXPECT_NEAR(right.marks[0].line_length, 3.0, 1e-12);
  EXPECT_NEAR(right.marks[0].space, 9.0, 1e-12);
  const LaneBorders b = r.borders(0, 20);
  EXPECT_NEAR(b.center, 1.5, 1e-12);            // laneOffset shifts the lanes...
  EXPECT_NEAR(b.outer(-1), -2.0, 1e-12);        // ...by width
  EXPECT_NEAR(b.outer(1), 3.5, 1e-12);          // ...and by border, from the centre lane
  EXPECT_NEAR(r.reference(20).y, 0.0, 1e-12);   // ...never the reference line
  EXPECT_NEAR(r.reference(20).x, 20.0, 1e-12);  // normalized pRange, no pRange given
  EXPECT_NEAR(r.surface(20, 2).roll, 0.05, 1e-12);
}

}  // namespace
}  // namespace tb::map::odr
