// Frame time of the 3D view: N vehicles driving the lanes of an OpenDRIVE map, the chase
// camera on the first, drawn and swapped in a window at the given size, as the render thread
// does it (DriverView + SDL_GL_SwapWindow, no pacing). Prints the median and percentiles of
// the frame time, the OpenGL renderer and the load average. Needs an X display:
//
//   xvfb-run -a -s "-screen 0 1280x720x24" build/release/bench/view3d_frame_bench
//       --map ../shared/data/opendrive/simple_4way_intersection.xodr --vehicles 20
#include <SDL.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <osg/GL>

#include "common/map/opendrive/mesh.hpp"
#include "common/map/opendrive/reader.hpp"
#include "sim-client/bench/bench_stats.hpp"
#include "sim-client/view/scene.hpp"
#include "sim-client/view3d/driver_view.hpp"
#include "sim-client/view3d/junction_marks.hpp"
#include "sim-client/view3d/road_objects_node.hpp"

namespace {

using namespace tb;
using namespace tb::client::view3d;
using tb::client::bench::loadavg;
using tb::client::bench::percentile;
namespace odr = map::odr;

/// A car driving round a lane's centre line (back and forth along the polyline).
struct Driver {
  const std::vector<odr::Vertex>* line = nullptr;
  std::vector<double> at;  ///< cumulative length
  double s = 0.0, speed = 10.0;
  wire::VehicleState state(std::int64_t sim_ns) const {
    const double total = at.back();
    double u = std::fmod(s, 2.0 * total);
    const bool back = u > total;
    if (back)
      u = 2.0 * total - u;
    const auto it = std::upper_bound(at.begin(), at.end(), u);
    const std::size_t i =
        std::clamp<std::size_t>(static_cast<std::size_t>(it - at.begin()), 1, at.size() - 1);
    const auto& a = (*line)[i - 1];
    const auto& b = (*line)[i];
    const double f = (u - at[i - 1]) / std::max(1e-9, at[i] - at[i - 1]);
    wire::VehicleState v;
    v.position = {a.x + (b.x - a.x) * f, a.y + (b.y - a.y) * f, a.z + (b.z - a.z) * f};
    v.yaw = static_cast<float>(std::atan2(b.y - a.y, b.x - a.x) + (back ? 3.141592653589793 : 0.0));
    v.speed = static_cast<float>(speed);
    v.wheel_speeds = {static_cast<float>(speed), static_cast<float>(speed),
                      static_cast<float>(speed), static_cast<float>(speed)};
    v.sim_time_ns = sim_ns;
    v.lights = wire::kLowBeam;
    return v;
  }
};

}  // namespace

int main(int argc, char** argv) {
  std::string map_file = "../shared/data/opendrive/simple_4way_intersection.xodr";
  int vehicles = 20, frames = 300, warmup = 30, width = 1280, height = 720, follow = 0;
  std::string camera = "chase", screenshot;
  CLI::App cli{"3D view frame time"};
  cli.add_option("--map", map_file, "OpenDRIVE map")->capture_default_str();
  cli.add_option("--vehicles", vehicles)->capture_default_str();
  cli.add_option("--frames", frames, "frames measured")->capture_default_str();
  cli.add_option("--warmup", warmup, "frames drawn first, not measured")->capture_default_str();
  cli.add_option("--width", width)->capture_default_str();
  cli.add_option("--height", height)->capture_default_str();
  cli.add_option("--camera", camera, "chase, cockpit, top, orbit")->capture_default_str();
  cli.add_option("--follow", follow, "the car the camera follows")->capture_default_str();
  bool spread = false;
  cli.add_flag("--spread", spread,
               "cars spread over their lanes (default: 9 m apart from the start)");
  cli.add_option("--screenshot", screenshot, "write the last frame to this PNG");
  CLI11_PARSE(cli, argc, argv);
  if (vehicles < 1 || follow < 0 || follow >= vehicles) {
    fmt::print(stderr, "--follow {}: expected a car from 0 to --vehicles - 1 ({})\n", follow,
               vehicles - 1);
    return 64;
  }
  const auto mode = parse_camera(camera);
  if (!mode) {
    fmt::print(stderr, "--camera {}: expected chase, cockpit, top or orbit\n", camera);
    return 64;
  }

  auto world = std::make_shared<World>();
  try {
    world->network = std::make_shared<const odr::RoadNetwork>(odr::load_opendrive(map_file));
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
  // Every drivable lane's centre line; cars spread over them.
  std::vector<std::vector<odr::Vertex>> lines;
  for (const auto& road : world->network->roads)
    for (std::size_t k = 0; k < road.sections.size(); ++k)
      for (const auto* side : {&road.sections[k].left, &road.sections[k].right})
        for (const auto& lane : *side)
          if (lane.drivable && road.junction_index < 0)
            lines.push_back(odr::lane_centre(road, k, lane.id, 0.05));
  if (lines.empty()) {
    fmt::print(stderr, "{}: no drivable lane\n", map_file);
    return 1;
  }
  std::vector<Driver> drivers;
  const float palette[][3] = {{0.82f, 0.13f, 0.13f}, {0.13f, 0.31f, 0.82f}, {0.13f, 0.63f, 0.25f},
                              {0.9f, 0.75f, 0.1f},   {0.9f, 0.9f, 0.9f},    {0.15f, 0.15f, 0.15f}};
  for (int i = 0; i < vehicles; ++i) {
    Driver d;
    d.line = &lines[static_cast<std::size_t>(i) % lines.size()];
    d.at.push_back(0.0);
    for (std::size_t j = 1; j < d.line->size(); ++j) {
      const auto& a = (*d.line)[j - 1];
      const auto& b = (*d.line)[j];
      d.at.push_back(d.at.back() + std::hypot(b.x - a.x, b.y - a.y));
    }
    // Either 9 m apart from each lane's start, or spread over the lanes' whole way there and
    // back (golden-ratio steps: no two cars of a lane together), so that on a town map some
    // drive towards junctions and some away.
    d.s = spread ? 2.0 * d.at.back() * std::fmod(0.6180339887 * i, 1.0)
                 : 9.0 * static_cast<double>(i / static_cast<int>(lines.size()));
    d.speed = 8.0 + (i % 5);
    drivers.push_back(std::move(d));
    VehicleLook l;
    l.id = fmt::format("car{}", i);
    l.station_id = static_cast<std::uint32_t>(1000 + i);
    const auto& c = palette[i % 6];
    l.colour = {c[0], c[1], c[2]};
    world->vehicles.push_back(l);
  }
  world->version = 1;

  if (SDL_Init(SDL_INIT_VIDEO) != 0) {
    fmt::print(stderr, "SDL: {} (run under xvfb-run)\n", SDL_GetError());
    return 1;
  }
  SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
  SDL_GL_SetAttribute(SDL_GL_DEPTH_SIZE, 24);
  SDL_Window* win = SDL_CreateWindow("view3d_frame_bench", 0, 0, width, height, SDL_WINDOW_OPENGL);
  SDL_GLContext ctx = win != nullptr ? SDL_GL_CreateContext(win) : nullptr;
  if (ctx == nullptr) {
    fmt::print(stderr, "no OpenGL window: {}\n", SDL_GetError());
    return 1;
  }
  SDL_GL_SetSwapInterval(0);
  const std::string renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const std::string load_before = loadavg();
  std::vector<double> frame_ms, draw_ms;
  // The process's CPU time over the measured frames (every thread: llvmpipe's rasterisers
  // too): the frames' cost whatever else the machine runs, where wall time is the machine's.
  auto cpu_ms = [] {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) / 1e6;
  };
  double cpu_start = 0.0, cpu_end = 0.0;
  {
    DriverView view(width, height);
    FrameInput in;
    in.world = world;
    in.own = follow;
    in.choice.camera = *mode;
    in.choice.target = follow;
    const double dt = 1.0 / 60.0;
    for (int f = 0; f < warmup + frames; ++f) {
      if (f == warmup)
        cpu_start = cpu_ms();
      const auto t0 = std::chrono::steady_clock::now();
      in.sim_time_ns = static_cast<std::int64_t>(f * dt * 1e9);
      in.vehicles.clear();
      for (auto& d : drivers) {
        d.s += d.speed * dt;
        in.vehicles.push_back(d.state(in.sim_time_ns));
      }
      const bool last = f + 1 == warmup + frames;
      if (last && !screenshot.empty())
        view.capture_next_frame();
      view.render(in, dt);
      const auto t1 = std::chrono::steady_clock::now();
      SDL_GL_SwapWindow(win);
      glFinish();
      const auto t2 = std::chrono::steady_clock::now();
      if (f >= warmup) {
        frame_ms.push_back(std::chrono::duration<double, std::milli>(t2 - t0).count());
        draw_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      }
      if (last)
        cpu_end = cpu_ms();
      if (last && !screenshot.empty()) {
        if (auto im = view.take_capture()) {
          const std::string err =
              tb::client::write_png(screenshot, im->width, im->height, im->rgba);
          if (!err.empty())
            fmt::print(stderr, "{}\n", err);
        }
      }
    }
    fmt::print("map {}: {} road-surface and {} mark triangles\n", map_file,
               view.road_stats().surface_triangles, view.road_stats().mark_triangles);
    // The same nodes the view built, counted (built again here: DriverView keeps no stats).
    ObjectsNodeStats objects;
    std::size_t marks = 0;
    make_road_objects_node(*world->network, &objects);
    make_junction_marks_node(*world->network, &marks);
    fmt::print("objects: {} shapes, {} triangles in {} tiles; {} junction-mark quads\n",
               objects.shapes, objects.triangles, objects.tiles, marks);
  }
  SDL_GL_DeleteContext(ctx);
  SDL_DestroyWindow(win);
  SDL_Quit();
  const double med = percentile(frame_ms, 0.5);
  fmt::print("renderer: {}\n", renderer);
  fmt::print("{}x{}, {} vehicles, {} camera, {} frames after {} warm-up\n", width, height, vehicles,
             camera, frames, warmup);
  const double p10 = percentile(frame_ms, 0.1), p90 = percentile(frame_ms, 0.9);
  fmt::print(
      "frame (draw + swap) ms: p10 {:.2f} median {:.2f} p90 {:.2f} p99 {:.2f} max {:.2f} -> "
      "{:.1f} fps median ({:.1f} at p90 frame time, {:.1f} at p10)\n",
      p10, med, p90, percentile(frame_ms, 0.99),
      *std::max_element(frame_ms.begin(), frame_ms.end()), 1000.0 / med, 1000.0 / p90,
      1000.0 / p10);
  fmt::print("CPU per frame (all threads) ms: {:.2f}\n", (cpu_end - cpu_start) / frames);
  fmt::print("draw only ms: median {:.2f} p90 {:.2f}\n", percentile(draw_ms, 0.5),
             percentile(draw_ms, 0.9));
  fmt::print("load average before: {}; after: {}\n", load_before, loadavg());
  return 0;
}
