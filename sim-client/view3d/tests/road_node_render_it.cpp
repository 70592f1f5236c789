// The ground and the junctions (road_node.hpp) rendered for real (Mesa's llvmpipe in an Xvfb
// the test starts): the shipped hilly map (scenarios/maps/four_way_junction.xodr) and a
// hand-made junction, checked by colours at pixels worked out from the camera pose and the
// map's geometry. The frames are left in
// build/…/Testing/Temporary/view3d/ for a person to look at.
#include <gtest/gtest.h>

#include <SDL.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <numbers>

#include "common/map/opendrive/mesh.hpp"
#include "common/map/opendrive/reader.hpp"
#include "common/map/opendrive/terrain.hpp"
#include "sim-client/view/scene.hpp"
#include "sim-client/view3d/driver_view.hpp"
#include "sim-client/view3d/tests/render_fixture.hpp"

namespace tb::client::view3d {
namespace {

namespace fs = std::filesystem;
namespace odr = map::odr;

/// Grass, lit or in shade, near or a little fogged: green above red and blue.
bool grass(Rgb c) {
  return c.g > c.r + 12 && c.g > c.b + 12;
}
/// The sky and what the fog fades into: blue above green above red.
bool sky(Rgb c) {
  return c.b > c.g && c.g > c.r && c.b > 150;
}
/// Asphalt or the sidewalks' paving: grey to beige, no colour dominating.
bool paved(Rgb c) {
  return std::abs(c.r - c.g) < 25 && c.r >= c.b && c.r - c.b < 40;
}
/// The sidewalks' paving (lane_colour("sidewalk"), lit).
bool sidewalk(Rgb c) {
  return c.r > 150 && c.r - c.b > 15 && c.r >= c.g;
}
bool asphalt(Rgb c) {
  return c.r < 120 && c.g < 120 && c.b < 120 && std::abs(c.r - c.b) < 20 &&
         std::abs(c.r - c.g) < 20;
}

VehicleLook look(const std::string& id, std::uint32_t station) {
  VehicleLook l;
  l.id = id;
  l.station_id = station;
  l.colour = {0.85f, 0.1f, 0.8f};
  return l;
}

class RoadNodeRender : public RenderTest {
 protected:
  void SetUp() override {
    RenderTest::SetUp();
    if (IsSkipped() || HasFatalFailure())
      return;
    net_ = std::make_shared<const odr::RoadNetwork>(
        odr::load_opendrive((maps_dir() / "four_way_junction.xodr").string()));
    terrain_ = std::make_unique<odr::Terrain>(*net_);
  }

  /// A world with one car standing on the ground at (x, y), watched (no own car).
  FrameInput watching(double x, double y, double yaw) { return watching(net_, x, y, yaw); }
  FrameInput watching(std::shared_ptr<const odr::RoadNetwork> net, double x, double y, double yaw) {
    auto w = std::make_shared<World>();
    w->network = std::move(net);
    w->vehicles = {look("car", 1001)};
    w->version = 1;
    FrameInput in;
    in.world = std::move(w);
    wire::VehicleState s;
    s.position = {x, y, terrain_->height_at(x, y)};
    s.yaw = static_cast<float>(yaw);
    s.sim_time_ns = 5'000'000'000;
    in.vehicles = {s};
    in.sim_time_ns = s.sim_time_ns;
    in.own = -1;
    in.choice.target = 0;
    in.status.connection = "connected to test";
    in.status.input = "keyboard";
    in.status.watching = true;
    return in;
  }

  std::shared_ptr<const odr::RoadNetwork> net_;
  std::unique_ptr<odr::Terrain> terrain_;
};

TEST_F(RoadNodeRender, NoGapUnderARaisedRoadSeenFromBelowIt) {
  // From the driver's seat of a car in the middle of the junction (z = 0), looking north-east
  // at the loop that joins the east and north arms: it runs 3 to 6 m up, well above the
  // driver's eyes, so a gap under it would show the sky.
  FrameInput in = watching(0.0, 0.0, std::numbers::pi / 4);
  in.vehicles[0].position[2] = 0.0;
  in.own = 0;
  in.status.watching = false;
  in.choice.camera = CameraMode::kCockpit;
  const Image im = shoot(in, "terrain_under_raised_loop");
  const CameraPose& pose = view_->pose();
  const odr::Road* loop = nullptr;
  for (const odr::Road& r : net_->roads)
    if (r.id == "10")
      loop = &r;
  ASSERT_NE(loop, nullptr);
  // Along the loop's inner edge (its left shoulder's border, t = 5): a point 0.3 m under the
  // edge and 0.3 m in from it shows ground (the road's embankment, or the slope in front of
  // it), or a nearer road where one hides it (the north arm's sidewalk, near the loop's end);
  // never the sky. Without the terrain every one of them is sky (the ground a plane at z = 0).
  int checked = 0, ground = 0;
  for (double s = 0.0; s <= loop->length; s += 4.0) {
    const odr::SurfacePose edge = loop->surface(s, 5.3);
    const osg::Vec3d under(edge.x, edge.y, edge.z - 0.3);
    const osg::Vec2d p = project(pose, under);
    // In front of the camera, in the picture and clear of the mirror and the dashboard.
    if ((under - pose.eye) *
                osg::Vec3d(std::cos(std::numbers::pi / 4), std::sin(std::numbers::pi / 4), 0) <
            1.0 ||
        p.x() < 2 || p.x() > kW - 3 || p.y() < 160 || p.y() > kH - 200)
      continue;
    ASSERT_GT(under.z(), pose.eye.z() + 1.0) << "s " << s;  // above the eyes
    ++checked;
    const Rgb c = pixel(im, static_cast<int>(p.x()), static_cast<int>(p.y()));
    ground += grass(c);
    EXPECT_TRUE(grass(c) || paved(c)) << "s " << s << " pixel " << p.x() << ", " << p.y() << ": "
                                      << c.r << " " << c.g << " " << c.b;
    EXPECT_FALSE(sky(c)) << "s " << s;
  }
  EXPECT_GE(checked, 30);
  EXPECT_GE(ground, checked * 8 / 10);
}

TEST_F(RoadNodeRender, TheJunctionFromAboveIsOneSurfaceWithoutStripes) {
  // Straight down on the junction box (24 m square, twelve connecting roads overlapping in
  // it): inside the box every pixel is the one asphalt grey.
  FrameInput in = watching(0.0, -16.0, std::numbers::pi / 2);
  in.choice.camera = CameraMode::kTop;
  in.choice.top_zoom = 1.8;
  const Image a = shoot(in, "junction_top");
  const CameraPose& pose = view_->pose();
  // The box's cross (within 3.4 m of either axis, where the straight-on roads run): the
  // corners between the turning roads are grass.
  const auto in_cross = [](double x, double y) {
    return (std::fabs(x) <= 3.4 && std::fabs(y) <= 11.5) ||
           (std::fabs(y) <= 3.4 && std::fabs(x) <= 11.5);
  };
  int checked = 0, bad = 0;
  for (double x = -11.5; x <= 11.5; x += 0.25) {
    for (double y = -11.5; y <= 11.5; y += 0.25) {
      if (!in_cross(x, y))
        continue;
      const osg::Vec2d p = project(pose, {x, y, 0.0});
      if (p.x() < 2 || p.x() > kW - 3 || p.y() < 2 || p.y() > kH - 3)
        continue;
      ++checked;
      const Rgb c = pixel(a, static_cast<int>(p.x()), static_cast<int>(p.y()));
      if (!asphalt(c)) {
        ++bad;
        ADD_FAILURE() << "(" << x << ", " << y << ") pixel " << p.x() << ", " << p.y() << ": "
                      << c.r << " " << c.g << " " << c.b;
        if (bad > 10)
          break;
      }
    }
  }
  EXPECT_GT(checked, 2000);
  EXPECT_EQ(bad, 0);
  // One asphalt grey over the box: z-fighting between overlapping roads (or ground showing
  // through) would show as pixels of a different shade.
  int lo = 255, hi = 0;
  for (double x = -11.5; x <= 11.5; x += 0.5) {
    for (double y = -11.5; y <= 11.5; y += 0.5) {
      const osg::Vec2d p = project(pose, {x, y, 0.0});
      if (!in_cross(x, y) || p.y() < 2 || p.y() > kH - 3)
        continue;
      const Rgb c = pixel(a, static_cast<int>(p.x()), static_cast<int>(p.y()));
      lo = std::min(lo, c.g);
      hi = std::max(hi, c.g);
    }
  }
  EXPECT_LE(hi - lo, 3);
}

TEST_F(RoadNodeRender, AJunctionsCarriagewayIsDrawnOverAnotherConnectingRoadsSidewalk) {
  // Two connecting roads of one junction crossing at the same height: J1 along x with a 2 m
  // sidewalk right of its lanes (y from -5.5 to -3.5), J2 along y, its lanes over J1's
  // sidewalk where |x| < 3.5. Seen from above: J2's asphalt across the sidewalk, one grey,
  // and the sidewalk only where no carriageway covers it.
  const auto lane = [](int id, const char* type, double width) {
    return "<lane id=\"" + std::to_string(id) + "\" type=\"" + type +
           "\"><width sOffset=\"0\" a=\"" + std::to_string(width) +
           "\" b=\"0\" c=\"0\" d=\"0\"/></lane>";
  };
  const auto road = [&](const char* id, double x, double y, double hdg, const std::string& right) {
    return std::string("<road id=\"") + id +
           "\" length=\"40\" junction=\"J\"><planView><geometry s=\"0\" x=\"" + std::to_string(x) +
           "\" y=\"" + std::to_string(y) + "\" hdg=\"" + std::to_string(hdg) +
           "\" length=\"40\"><line/></geometry></planView><lanes><laneSection s=\"0\"><left>" +
           lane(1, "driving", 3.5) +
           "</left><center><lane id=\"0\" type=\"none\"/></center><right>" + right +
           "</right></laneSection></lanes></road>";
  };
  const auto net = std::make_shared<const odr::RoadNetwork>(odr::parse_opendrive(
      "<OpenDRIVE><header revMajor=\"1\" revMinor=\"6\"/>" +
          road("J1", -20, 0, 0, lane(-1, "driving", 3.5) + lane(-2, "sidewalk", 2.0)) +
          road("J2", 0, -20, std::numbers::pi / 2, lane(-1, "driving", 3.5)) +
          "<junction id=\"J\" name=\"crossing\"/></OpenDRIVE>",
      "crossing.xodr"));
  FrameInput in = watching(net, 14.0, -14.0, std::numbers::pi / 2);
  in.choice.camera = CameraMode::kTop;
  in.choice.top_zoom = 2.0;
  const Image im = shoot(in, "junction_sidewalk_under_carriageway");
  const CameraPose& pose = view_->pose();
  int under = 0, grey_lo = 255, grey_hi = 0, alone = 0;
  for (double x = -3.2; x <= 3.2; x += 0.2) {
    for (double y = -5.3; y <= -3.7; y += 0.2) {
      const osg::Vec2d p = project(pose, {x, y, 0.0});
      const Rgb c = pixel(im, static_cast<int>(p.x()), static_cast<int>(p.y()));
      EXPECT_TRUE(asphalt(c)) << "(" << x << ", " << y << "): " << c.r << " " << c.g << " " << c.b;
      grey_lo = std::min(grey_lo, c.g);
      grey_hi = std::max(grey_hi, c.g);
      ++under;
    }
  }
  EXPECT_GT(under, 200);
  EXPECT_LE(grey_hi - grey_lo, 3);
  for (double x : {-15.0, -10.0, -6.0, 6.0, 10.0}) {
    const osg::Vec2d p = project(pose, {x, -4.5, 0.0});
    const Rgb c = pixel(im, static_cast<int>(p.x()), static_cast<int>(p.y()));
    alone += sidewalk(c);
    EXPECT_TRUE(sidewalk(c)) << x << ": " << c.r << " " << c.g << " " << c.b;
  }
  EXPECT_EQ(alone, 5);
}

}  // namespace
}  // namespace tb::client::view3d
