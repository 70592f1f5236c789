// The built-in layouts generated as OpenDRIVE networks put every lane where RoadMap has it.

#include "common/map/builtin_network.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "common/map/opendrive/queries.hpp"
#include "common/map/opendrive/reader.hpp"
#include "common/map/opendrive/writer.hpp"
#include "common/map/road_map.hpp"

namespace tb::scenario {
// Test names carry the layout rather than the bytes of the struct (which hold a pointer).
void PrintTo(const MapSpec& m, std::ostream* os) {
  *os << static_cast<int>(m.type) << ":" << m.lanes << "/" << m.oncoming_lanes;
}
}  // namespace tb::scenario

namespace tb::map {
namespace {

scenario::MapSpec spec_of(scenario::MapType type, int lanes, int oncoming) {
  scenario::MapSpec s;
  s.type = type;
  s.lanes = lanes;
  s.oncoming_lanes = oncoming;
  s.length = 800;
  s.radius = 120;
  s.arm_length = 200;
  return s;
}

class BuiltinNetwork : public testing::TestWithParam<scenario::MapSpec> {};

TEST_P(BuiltinNetwork, LanesSitWhereRoadMapHasThem) {
  const scenario::MapSpec spec = GetParam();
  const RoadMap built_in(spec);
  // Written and read back: what scenario-check --export-xodr gives other tools.
  const odr::RoadNetwork net =
      odr::parse_opendrive(odr::write_opendrive(generate_network(spec)), "x");
  const odr::LaneLocator loc(net);
  int checked = 0;
  for (const Road& road : built_in.roads()) {
    for (const Lane& lane : road.lanes) {
      const double len = length(lane.centre);
      for (double f : {0.05, 0.3, 0.62, 0.95}) {
        const Pose p = built_in.lane_pose(lane.road, lane.index, f * len);
        if (spec.type == scenario::MapType::kCrossing && std::hypot(p.p.x, p.p.y) < 10)
          continue;
        const auto at = loc.locate(p.p.x, p.p.y);
        ASSERT_TRUE(at);
        EXPECT_EQ(at->ref.road, lane.road);
        EXPECT_EQ(at->ref.lane, opendrive_lane_id(spec, lane.index));
        const odr::Road& r = net.roads[static_cast<std::size_t>(at->ref.road)];
        EXPECT_NEAR(at->t, odr::lane_centre_t(r, at->ref.lane, at->s), 1e-6);
        // Direction of travel: along s for right lanes.
        const double hdg = r.reference(at->s).hdg + (r.forward(at->ref.lane) ? 0 : M_PI);
        EXPECT_NEAR(std::remainder(hdg - p.yaw, 2 * M_PI), 0, 1e-6);
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 7);
}

INSTANTIATE_TEST_SUITE_P(Layouts, BuiltinNetwork,
                         testing::Values(spec_of(scenario::MapType::kStraight, 2, 1),
                                         spec_of(scenario::MapType::kStraight, 3, 0),
                                         spec_of(scenario::MapType::kStraight, 4, 2),
                                         spec_of(scenario::MapType::kRing, 2, 1),
                                         spec_of(scenario::MapType::kRing, 3, 3),
                                         spec_of(scenario::MapType::kCrossing, 2, 1)));

TEST(BuiltinNetworkErrors, SameRefusalsAsRoadMap) {
  scenario::MapSpec s = spec_of(scenario::MapType::kRing, 2, 1);
  s.radius = 3;
  EXPECT_THROW(generate_network(s), std::invalid_argument);
}

}  // namespace
}  // namespace tb::map
