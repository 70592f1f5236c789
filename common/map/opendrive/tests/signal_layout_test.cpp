// Traffic lights, controllers and the lanes they govern, from a hand-made junction: positions
// worked out by hand from the straight roads' geometry.

#include "common/map/opendrive/signal_layout.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "common/map/opendrive/reader.hpp"

namespace tb::map::odr {
namespace {

constexpr double kPi = std::numbers::pi;

/// Road "1" runs east from (0, 0) for 100 m into junction @p jid, whose connecting road "2"
/// goes on 10 m to road "3" (x 110 to 200, east). Lanes 3.5 m wide: right lanes (-1, -2 on
/// road 1) run east, left lanes west. @p sig1 / @p sig3: the roads' <signals> content;
/// @p controllers: top-level controllers; @p jctl: <controller>s inside the junction.
std::string junction_with(const std::string& sig1, const std::string& sig3,
                          const std::string& controllers, const std::string& jctl,
                          const std::string& jid = "7") {
  const std::string lanes2 =
      R"(<lanes><laneSection s="0"><left><lane id="1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></left><center><lane id="0" type="none"/></center><right><lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane><lane id="-2" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></right></laneSection></lanes>)";
  const std::string lanes1 =
      R"(<lanes><laneSection s="0"><left><lane id="1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></left><center><lane id="0" type="none"/></center><right><lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></right></laneSection></lanes>)";
  return R"(<?xml version="1.0"?><OpenDRIVE><header revMajor="1" revMinor="7"/>)"
         R"(<road id="1" length="100" junction="-1"><link><successor elementType="junction" elementId=")" +
         jid +
         R"("/></link><planView><geometry s="0" x="0" y="0" hdg="0" length="100"><line/></geometry></planView>)" +
         lanes2 + "<signals>" + sig1 + "</signals></road>" +
         R"(<road id="2" length="10" junction=")" + jid +
         R"("><link><predecessor elementType="road" elementId="1" contactPoint="end"/><successor elementType="road" elementId="3" contactPoint="start"/></link><planView><geometry s="0" x="100" y="0" hdg="0" length="10"><line/></geometry></planView>)" +
         lanes1 + "</road>" +
         R"(<road id="3" length="90" junction="-1"><link><predecessor elementType="junction" elementId=")" +
         jid +
         R"("/></link><planView><geometry s="0" x="110" y="0" hdg="0" length="90"><line/></geometry></planView>)" +
         lanes1 + "<signals>" + sig3 + "</signals></road>" + controllers + R"(<junction id=")" +
         jid +
         R"("><connection id="0" incomingRoad="1" connectingRoad="2" contactPoint="start"><laneLink from="-1" to="-1"/></connection>)"
         R"(<connection id="1" incomingRoad="3" connectingRoad="2" contactPoint="end"><laneLink from="1" to="1"/></connection>)" +
         jctl + "</junction></OpenDRIVE>";
}

// Road 1: a light for lane -1 only 2 m before the junction beside the road, a stop line across
// lane -1 at s 96, and one across lane -2 at s 97. Road 3: a light for westbound traffic
// (no validity: every lane of its orientation), no stop line.
const std::string kSig1 =
    R"(<signal id="L1" s="98" t="-8" zOffset="2.1" orientation="+" dynamic="yes" country="DE" type="1000001" height="0.9" width="0.3"><validity fromLane="-1" toLane="-1"/></signal>)"
    R"(<signal id="S1" s="96" t="-1.75" orientation="+" country="DE" type="294" width="3.5"/>)"
    R"(<signal id="S2" s="97" t="-5.25" orientation="+" country="DE" type="294" width="3.5"/>)";
const std::string kSig3 =
    R"(<signal id="L3" s="2" t="5" zOffset="2" orientation="-" dynamic="yes" country="DE" type="1000001" height="1"/>)";
const std::string kControllers =
    R"(<controller id="5" name="east"><control signalId="L1"/></controller>)"
    R"(<controller id="6" name="west"><control signalId="L3" type="0"/></controller>)";
const std::string kJunctionControllers =
    R"(<controller id="5" type="0" sequence="1"/><controller id="6" type="0" sequence="2"/>)";

TEST(SignalLayout, ControllersAndValidityAreRead) {
  const RoadNetwork net =
      parse_opendrive(junction_with(kSig1, kSig3, kControllers, kJunctionControllers), "ok.xodr");
  ASSERT_EQ(net.controllers.size(), 2u);
  EXPECT_EQ(net.controllers[0].id, "5");
  EXPECT_EQ(net.controllers[0].name, "east");
  ASSERT_EQ(net.controllers[1].controls.size(), 1u);
  EXPECT_EQ(net.controllers[1].controls[0].signal_id, "L3");
  EXPECT_EQ(net.controllers[1].controls[0].type, "0");
  ASSERT_EQ(net.junctions[0].controllers.size(), 2u);
  EXPECT_EQ(net.junctions[0].controllers[1].id, "6");
  EXPECT_EQ(net.junctions[0].controllers[1].sequence, 2);
  const RoadSignal& l1 = net.roads[0].signals[0];
  ASSERT_EQ(l1.validity.size(), 1u);
  EXPECT_EQ(l1.validity[0].from, -1);
  EXPECT_TRUE(l1.valid_for(-1));
  EXPECT_FALSE(l1.valid_for(-2));
  EXPECT_TRUE(net.roads[2].signals[0].valid_for(1));  // no validity: every lane
  EXPECT_TRUE(net.warnings.empty()) << net.warnings.front();
}

TEST(SignalLayout, HeadsStandWhereTheFilePutsThem) {
  const RoadNetwork net =
      parse_opendrive(junction_with(kSig1, kSig3, kControllers, kJunctionControllers), "ok.xodr");
  const SignalLayout layout(net);
  ASSERT_EQ(layout.heads().size(), 2u);
  const SignalHead& a = layout.heads()[0];
  EXPECT_EQ(a.signal->id, "L1");
  EXPECT_EQ(a.road, 0);
  EXPECT_EQ(a.signal_group, 5);
  EXPECT_NEAR(a.pose.x, 98.0, 1e-9);
  EXPECT_NEAR(a.pose.y, -8.0, 1e-9);
  EXPECT_NEAR(a.pose.z, 2.1, 1e-9);
  EXPECT_NEAR(a.pose.heading, 0.0, 1e-9);  // for eastbound traffic
  EXPECT_EQ(a.height, 0.9);
  const SignalHead& b = layout.heads()[1];
  EXPECT_EQ(b.signal_group, 6);
  EXPECT_NEAR(b.pose.x, 112.0, 1e-9);
  EXPECT_NEAR(b.pose.y, 5.0, 1e-9);
  EXPECT_NEAR(std::fabs(b.pose.heading), kPi, 1e-9);  // westbound
  ASSERT_EQ(layout.groups().size(), 2u);
  EXPECT_EQ(layout.groups()[0].id, 5);
  EXPECT_EQ(layout.groups()[0].heads, std::vector<std::size_t>{0});
  EXPECT_EQ(layout.groups()[1].heads, std::vector<std::size_t>{1});
  ASSERT_EQ(layout.junctions().size(), 1u);
  EXPECT_EQ(layout.junctions()[0].intersection_id, 7);
  EXPECT_EQ(layout.junctions()[0].groups, (std::vector<int>{5, 6}));
  EXPECT_NE(layout.junction("7"), nullptr);
}

TEST(SignalLayout, LanesIntoTheJunctionGetTheirGroupAndStopLine) {
  const RoadNetwork net =
      parse_opendrive(junction_with(kSig1, kSig3, kControllers, kJunctionControllers), "ok.xodr");
  const SignalLayout layout(net);
  // Eastbound lane -1 of road 1: light L1 (group 5), stop line S1 at s 96 on its centre.
  const SignalApproach* east = layout.approach(0, -1);
  ASSERT_NE(east, nullptr);
  EXPECT_EQ(east->signal_group, 5);
  EXPECT_EQ(east->intersection_id, 7);
  EXPECT_EQ(east->junction, 0u);
  EXPECT_TRUE(east->has_stop_line);
  EXPECT_DOUBLE_EQ(east->stop_s, 96.0);
  EXPECT_NEAR(east->stop.x, 96.0, 1e-9);
  EXPECT_NEAR(east->stop.y, -1.75, 1e-9);
  EXPECT_NEAR(east->stop.heading, 0.0, 1e-9);
  // Lane -2 has a stop line but L1 does not hold for it (validity): no light, no approach.
  EXPECT_EQ(layout.approach(0, -2), nullptr);
  // Lane 1 of road 1 runs away from the junction.
  EXPECT_EQ(layout.approach(0, 1), nullptr);
  // Westbound lane 1 of road 3: L3 holds for every westbound lane; no stop line: the light's s.
  const SignalApproach* west = layout.approach(2, 1);
  ASSERT_NE(west, nullptr);
  EXPECT_EQ(west->signal_group, 6);
  EXPECT_FALSE(west->has_stop_line);
  EXPECT_DOUBLE_EQ(west->stop_s, 2.0);
  EXPECT_NEAR(west->stop.x, 112.0, 1e-9);
  EXPECT_NEAR(west->stop.y, 1.75, 1e-9);
  EXPECT_NEAR(std::fabs(west->stop.heading), kPi, 1e-9);
  EXPECT_EQ(layout.approaches().size(), 2u);
  // A junction that lists no controllers gets those of the lights on its lanes.
  const RoadNetwork bare = parse_opendrive(junction_with(kSig1, kSig3, kControllers, ""), "b");
  EXPECT_EQ(SignalLayout(bare).junctions()[0].groups, (std::vector<int>{5, 6}));
}

void expect_error(const std::string& xml, const std::string& path, const std::string& reason,
                  bool layout = false) {
  try {
    const RoadNetwork net = parse_opendrive(xml, "bad.xodr");
    if (layout)
      SignalLayout{net};
    ADD_FAILURE() << "no error, wanted " << reason;
  } catch (const MapError& e) {
    EXPECT_EQ(e.path(), path) << e.what();
    EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("bad.xodr: ", 0), 0u) << e.what();
  }
}

TEST(SignalLayout, TheReaderTakesAnyControllerIdTheLightsNeedNot) {
  // A map whose lights nobody runs (a view, an export) loads whatever ids its controllers have;
  // only the signal model, built when the lights are used, needs SignalGroupIDs.
  const RoadNetwork net = parse_opendrive(
      junction_with(kSig1, kSig3, R"(<controller id="x1"><control signalId="L1"/></controller>)",
                    ""),
      "odd.xodr");
  ASSERT_EQ(net.controllers.size(), 1u);
  EXPECT_EQ(net.controllers[0].id, "x1");
  EXPECT_THROW(SignalLayout{net}, MapError);
}

TEST(SignalLayout, BadControllersAreRefusedWithElementAndValue) {
  expect_error(
      junction_with(kSig1, kSig3,
                    kControllers + R"(<controller id="8"><control signalId="L9"/></controller>)",
                    ""),
      "controller[@id='8']/control[1]", "attribute 'signalId' is 'L9': no road has that signal");
  expect_error(
      junction_with(kSig1, kSig3,
                    kControllers + R"(<controller id="8"><control signalId="S1"/></controller>)",
                    ""),
      "controller[@id='8']/control[1]", "signal 'S1' of road '1' is not dynamic");
  expect_error(
      junction_with(kSig1, kSig3,
                    kControllers + R"(<controller id="8"><control signalId="L1"/></controller>)",
                    ""),
      "controller[@id='8']/control[1]", "signal 'L1' is already controlled by controller '5'");
  for (const char* id : {"0", "255", "x1", "-3", "1.5"}) {
    expect_error(
        junction_with(
            kSig1, kSig3,
            std::string(R"(<controller id=")") + id + R"("><control signalId="L1"/></controller>)",
            ""),
        std::string("controller[@id='") + id + "']",
        std::string("attribute 'id' is '") + id + "': a controller's id is its signal group", true);
  }
  expect_error(junction_with(kSig1, kSig3, kControllers + kControllers, ""), "controller[@id='5']",
               "duplicate controller id '5'");
  expect_error(junction_with(kSig1, kSig3, kControllers, R"(<controller id="9"/>)"),
               "junction[@id='7']/controller[1]", "attribute 'id' is '9': no <controller>");
  expect_error(junction_with(kSig1, kSig3, kControllers, kJunctionControllers, "J7"),
               "junction[@id='J7']", "must be a decimal 0..65535");
  expect_error(junction_with(kSig1, kSig3, kControllers, "", "70000"), "junction[@id='70000']",
               "must be a decimal 0..65535", true);
  expect_error(junction_with(kSig1, kSig3, kControllers, R"(<controller id="5"/>)"),
               "road[@id='3']/signals/signal[@id='L3']",
               "its controller '6' governs lane 1 into junction '7', which does not list it", true);
  expect_error(
      junction_with(
          R"(<signal id="L1" s="98" t="-8" dynamic="yes"><validity fromLane="a" toLane="-1"/></signal>)",
          "", "", ""),
      "road[@id='1']/signals/signal[@id='L1']/validity[1]",
      "attribute 'fromLane' is not a finite number: 'a'");
}

}  // namespace
}  // namespace tb::map::odr
