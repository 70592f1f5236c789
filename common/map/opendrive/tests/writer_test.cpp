// write_opendrive: every shared map written and read back is the same network.

#include "common/map/opendrive/writer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "common/map/opendrive/lane_graph.hpp"
#include "common/map/opendrive/reader.hpp"

namespace tb::map::odr {
namespace {

namespace fs = std::filesystem;

TEST(Writer, SharedMapsReadBackUnchanged) {
  const char* root = std::getenv("TESTBED_ROOT");
  const fs::path dir =
      fs::path(root != nullptr ? root : ".") / ".." / "shared" / "data" / "opendrive";
  int files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".xodr")
      continue;
    SCOPED_TRACE(e.path().filename().string());
    ++files;
    const RoadNetwork a = load_opendrive(e.path().string());
    const std::string text = write_opendrive(a);
    const RoadNetwork b = parse_opendrive(text, "written");
    ASSERT_EQ(a.roads.size(), b.roads.size());
    ASSERT_EQ(a.junctions.size(), b.junctions.size());
    for (std::size_t i = 0; i < a.roads.size(); ++i) {
      const Road& ra = a.roads[i];
      const Road& rb = b.roads[i];
      EXPECT_EQ(ra.id, rb.id);
      EXPECT_EQ(ra.junction, rb.junction);
      EXPECT_EQ(ra.left_hand_traffic, rb.left_hand_traffic);
      ASSERT_EQ(ra.sections.size(), rb.sections.size());
      for (int k = 0; k <= 20; ++k) {
        const double s = ra.length * k / 20.0;
        const SurfacePose pa = ra.surface(s, 2.5);
        const SurfacePose pb = rb.surface(s, 2.5);
        EXPECT_NEAR(pa.x, pb.x, 1e-9);
        EXPECT_NEAR(pa.y, pb.y, 1e-9);
        EXPECT_NEAR(pa.z, pb.z, 1e-9);
        const std::size_t sec = ra.section_index(s);
        const LaneBorders ba = ra.borders(sec, s);
        const LaneBorders bb = rb.borders(sec, s);
        EXPECT_EQ(ba.left, bb.left);
        EXPECT_EQ(ba.right, bb.right);
      }
      for (std::size_t k = 0; k < ra.sections.size(); ++k) {
        for (const auto* side : {&ra.sections[k].left, &ra.sections[k].right}) {
          for (const Lane& l : *side) {
            const Lane* m = rb.sections[k].lane(l.id);
            ASSERT_NE(m, nullptr);
            EXPECT_EQ(l.type, m->type);
            EXPECT_EQ(l.predecessor, m->predecessor);
            EXPECT_EQ(l.successor, m->successor);
            ASSERT_EQ(l.marks.size(), m->marks.size());
            for (std::size_t j = 0; j < l.marks.size(); ++j) {
              EXPECT_EQ(l.marks[j].type, m->marks[j].type);
              EXPECT_EQ(l.marks[j].width, m->marks[j].width);
            }
          }
        }
      }
    }
    const LaneGraph ga(a), gb(b);
    ASSERT_EQ(ga.size(), gb.size());
    for (std::size_t i = 0; i < ga.size(); ++i) {
      EXPECT_EQ(ga.successors(i), gb.successors(i));
      EXPECT_EQ(ga.neighbours(i), gb.neighbours(i));
    }
  }
  EXPECT_EQ(files, 13);
}

}  // namespace
}  // namespace tb::map::odr
