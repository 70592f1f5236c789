// The world's marks and objects rendered for real (llvmpipe in an Xvfb this test starts), and
// checked where the camera's matrices project the file's positions: a stop line in front of
// a car waiting at the shipped four-way junction, and a building where a hand-made file puts
// it. Frames are left in Testing/Temporary/view3d/ for a person to look at.
#include <gtest/gtest.h>

#include <SDL.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <numbers>

#include "common/map/opendrive/reader.hpp"
#include "sim-client/view/scene.hpp"
#include "sim-client/view3d/driver_view.hpp"
#include "sim-client/view3d/road_objects_node.hpp"
#include "sim-client/view3d/tests/render_fixture.hpp"

namespace tb::client::view3d {
namespace {

namespace fs = std::filesystem;
namespace odr = map::odr;

bool white_near(const Image& im, const osg::Vec2d& p) {
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy) {
      const Rgb c = pixel(im, static_cast<int>(p.x()) + dx, static_cast<int>(p.y()) + dy);
      if (c.r > 200 && c.g > 200 && c.b > 200)
        return true;
    }
  return false;
}

VehicleLook look(const std::string& id, const std::string& colour) {
  VehicleLook l;
  l.id = id;
  l.station_id = 1001;
  const SDL_Color c = *parse_colour(colour);
  l.colour = {c.r / 255.0f, c.g / 255.0f, c.b / 255.0f};
  return l;
}

class WorldRender : public RenderTest {};

FrameInput frame(std::shared_ptr<World> w, const wire::VehicleState& s, CameraMode camera) {
  FrameInput in;
  in.world = std::move(w);
  in.vehicles = {s};
  in.sim_time_ns = 5'000'000'000;
  in.own = 0;
  in.choice.camera = camera;
  in.status.connection = "connected to test";
  return in;
}

std::shared_ptr<World> world_of(odr::RoadNetwork net, const std::string& colour, int version) {
  auto w = std::make_shared<World>();
  w->network = std::make_shared<const odr::RoadNetwork>(std::move(net));
  w->vehicles = {look("me", colour)};
  w->version = version;
  return w;
}

TEST_F(WorldRender, AStopLineIsVisibleInFrontOfACarWaitingAtTheJunction) {
  // Red waits on the east arm (road 1) in lane 1, towards the junction (west), its front 10 m
  // behind the stop line (s 4.5: x 16.5, lane 1 is y 0 to 3.5), the chase camera behind it
  // (nearer, the car hides the line from a camera above and behind it).
  const fs::path file = maps_dir() / "four_way_junction.xodr";
  odr::RoadNetwork with = odr::load_opendrive(file.string());
  odr::RoadNetwork without = odr::load_opendrive(file.string());
  for (odr::Road& r : without.roads) {
    r.signals.clear();
    r.objects.clear();
  }
  const odr::Road& arm = with.roads[static_cast<std::size_t>(with.road_index("1"))];
  const odr::SurfacePose car = arm.surface(16.75, 1.75);
  wire::VehicleState s;
  s.position = {car.x, car.y, car.z};
  s.yaw = static_cast<float>(std::numbers::pi);
  s.sim_time_ns = 5'000'000'000;
  const double line_z = arm.surface(4.5, 1.75).z + 0.02;

  const Image marked =
      shoot(frame(world_of(std::move(with), "#d02020", 1), s, CameraMode::kChase), "stop_line");
  const CameraPose pose = view_->pose();
  const Image plain =
      shoot(frame(world_of(std::move(without), "#d02020", 2), s, CameraMode::kChase),
            "stop_line_without_marks");
  int points = 0, white = 0, white_without = 0;
  for (double y = 0.3; y <= 3.21; y += 0.2) {
    const osg::Vec2d p = project(pose, {16.5, y, line_z});
    ASSERT_GT(p.x(), 2);
    ASSERT_LT(p.x(), kW - 2);
    ASSERT_GT(p.y(), 150);  // below the mirror
    ASSERT_LT(p.y(), kH - 2);
    // In front of the car: above it on the screen, near the middle.
    EXPECT_LT(p.y(), project(pose, {car.x - 2.25, car.y, car.z}).y());
    ++points;
    white += white_near(marked, p);
    white_without += white_near(plain, p);
  }
  EXPECT_GE(white, points * 8 / 10) << "of " << points << " points on the stop line";
  EXPECT_LE(white_without, points / 10) << "the same frame without the marks";
}

TEST_F(WorldRender, ABuildingIsDrawnWhereTheFileStandsIt) {
  // One 200 m road east along y = 0; a house at s 100, t -20 (so x 94 to 106, y -24 to -16),
  // 9 m tall; seen from the top camera over a car at (100, 0).
  const std::string xml =
      R"(<?xml version="1.0"?><OpenDRIVE><header revMajor="1" revMinor="7"/>)"
      R"(<road id="1" length="200" junction="-1"><planView><geometry s="0" x="0" y="0" hdg="0" length="200"><line/></geometry></planView>)"
      R"(<lanes><laneSection s="0"><left><lane id="1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></left><center><lane id="0" type="none"/></center><right><lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></right></laneSection></lanes>)"
      R"(<objects><object id="house" type="building" s="100" t="-20" zOffset="0" hdg="0" length="12" width="8" height="9"/></objects></road></OpenDRIVE>)";
  wire::VehicleState s;
  s.position = {100.0, -1.75, 0.0};
  s.sim_time_ns = 5'000'000'000;
  odr::RoadNetwork bare = odr::parse_opendrive(xml, "house.xodr");
  bare.roads[0].objects.clear();
  FrameInput in =
      frame(world_of(odr::parse_opendrive(xml, "house.xodr"), "#2050d0", 1), s, CameraMode::kTop);
  in.own = -1;
  in.choice.target = 0;
  const Image im = shoot(in, "building_top");
  const CameraPose pose = view_->pose();
  in.world = world_of(std::move(bare), "#2050d0", 2);
  const Image without = shoot(in, "building_top_without");
  const auto roof = roof_colour("house", 0);
  const double roof_sum = roof[0] + roof[1] + roof[2];
  auto at = [&](const Image& image, double x, double y) {
    const osg::Vec2d p = project(pose, {x, y, 9.0});
    EXPECT_GT(p.x(), 0);
    EXPECT_LT(p.x(), kW);
    EXPECT_GT(p.y(), 0);
    EXPECT_LT(p.y(), kH);
    return pixel(image, static_cast<int>(p.x()), static_cast<int>(p.y()));
  };
  // The roof's hue (the sun scales all three channels alike), and not the ground's.
  auto is_roof = [&](double x, double y) {
    const Rgb c = at(im, x, y), g = at(without, x, y);
    const double sum = c.r + c.g + c.b;
    const bool hue = sum > 60 && std::fabs(c.r / sum - roof[0] / roof_sum) < 0.04 &&
                     std::fabs(c.g / sum - roof[1] / roof_sum) < 0.04;
    const bool changed = std::abs(c.r - g.r) + std::abs(c.g - g.g) + std::abs(c.b - g.b) > 30;
    return hue && changed;
  };
  // The roof over the footprint, just inside each corner and in the middle.
  for (const auto& [x, y] :
       {std::pair{100.0, -20.0}, {94.7, -23.3}, {105.3, -23.3}, {94.7, -16.7}, {105.3, -16.7}})
    EXPECT_TRUE(is_roof(x, y)) << "no roof at (" << x << ", " << y << ")";
  // Nothing of it beyond: 1.5 m outside each side the picture is the one without the house.
  for (const auto& [x, y] :
       {std::pair{92.5, -20.0}, {107.5, -20.0}, {100.0, -25.5}, {100.0, -14.5}}) {
    const Rgb c = at(im, x, y), g = at(without, x, y);
    EXPECT_LT(std::abs(c.r - g.r) + std::abs(c.g - g.g) + std::abs(c.b - g.b), 10)
        << "something drawn outside the house at (" << x << ", " << y << ")";
  }
}

}  // namespace
}  // namespace tb::client::view3d
