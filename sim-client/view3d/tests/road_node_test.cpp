#include "sim-client/view3d/road_node.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "common/map/builtin_network.hpp"

namespace tb::client::view3d {
namespace {

map::odr::RoadNetwork straight(double length) {
  scenario::MapSpec spec;
  spec.type = scenario::MapType::kStraight;
  spec.lanes = 3;
  spec.oncoming_lanes = 1;
  spec.lane_width = 3.5;
  spec.length = length;
  return map::generate_network(spec);
}

TEST(LaneMarks, LinesLieOnTheLaneBordersWithTheirWidthAndDashes) {
  const auto net = straight(200.0);
  const auto strips = lane_mark_strips(net, kRoadTolerance);
  // Centre line (t = 1.75) and edges (5.25, -5.25) solid; the line between the two forward
  // lanes (t = -1.75) broken, 3 m painted every 12 m.
  std::map<long, std::vector<const MarkStrip*>> by_y;
  for (const auto& s : strips) {
    ASSERT_EQ(s.left.size(), s.right.size());
    ASSERT_GE(s.left.size(), 2u);
    for (std::size_t i = 0; i < s.left.size(); ++i) {
      EXPECT_NEAR(s.left[i][1] - s.right[i][1], 0.12, 1e-9);  // default mark width
      EXPECT_NEAR(s.left[i][2], kMarkLift, 1e-9);
    }
    by_y[std::lround((s.left[0][1] + s.right[0][1]) / 2 * 100)].push_back(&s);
  }
  ASSERT_EQ(by_y.size(), 4u);
  for (long y : {525L, 175L, -525L}) {
    ASSERT_EQ(by_y[y].size(), 1u) << y;
    EXPECT_NEAR(by_y[y][0]->left.front()[0], 0.0, 1e-9);
    EXPECT_NEAR(by_y[y][0]->left.back()[0], 200.0, 1e-9);
  }
  const auto& dashes = by_y[-175L];
  ASSERT_EQ(dashes.size(), 17u);  // 0, 12, ..., 192
  for (std::size_t i = 0; i < dashes.size(); ++i) {
    EXPECT_NEAR(dashes[i]->left.front()[0], 12.0 * static_cast<double>(i), 1e-9);
    EXPECT_NEAR(dashes[i]->left.back()[0], 12.0 * static_cast<double>(i) + 3.0, 1e-9);
  }
}

TEST(LaneMarks, ColoursAndLaneTypes) {
  EXPECT_EQ(mark_colour("yellow")[2], 0.10f);
  EXPECT_EQ(mark_colour("standard"), mark_colour("white"));
  EXPECT_NE(lane_colour("driving"), lane_colour("sidewalk"));
  EXPECT_EQ(lane_colour("entry"), lane_colour("driving"));
}

}  // namespace
}  // namespace tb::client::view3d
