// Input → the first frame that shows it, against the real sim-server: a W key event is put on
// SDL's queue (as the X server's would be), the program's thread reads it with the controller
// poll, the controls go to the server, a physics step applies them, the state comes back, and
// the render thread draws a frame whose throttle bar (the state's controls) shows it; the
// figure is key event → that frame swapped. Then the same for the key's release. Also t1
// (controller poll → start of the physics step that applies it, from the server's own trace
// records, as scripts/report computes it) with the 3D view drawing and with no view at all, so
// that the view's cost to the input path shows. Needs an X display and $TESTBED_BIN/sim-server:
//
//   xvfb-run -a -s "-screen 0 1280x720x24" build/release/bench/view3d_latency_bench
#include <SDL.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <fstream>
#include <map>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <nlohmann/json.hpp>

#include "sim-client/app/client_app.hpp"
#include "sim-client/app/tests/sim_server_process.hpp"
#include "sim-client/bench/bench_stats.hpp"

namespace {

using namespace tb::client;
using tb::client::bench::loadavg;
using tb::client::bench::percentile;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

std::string scenario(int vehicles) {
  std::string v = R"({ "id": "me", "station_id": 3001, "color": "#2050d0",
      "spawn": { "lane": 0, "s": 30, "speed": 0 }, "driver": "human" })";
  for (int i = 1; i < vehicles; ++i)
    v += fmt::format(
        R"(, {{ "id": "c{}", "station_id": {}, "color": "#d02020",
      "spawn": {{ "lane": {}, "s": {}, "speed": 10 }},
      "driver": {{ "type": "lane_follow", "speed_profile": [ {{ "t": 0, "speed": 10 }} ] }} }})",
        i, 3001 + i, i % 3, 60 + 25 * (i / 3));
  return fmt::format(R"({{
  "name": "view3d-latency",
  "warmup_s": 0,
  "map": {{ "type": "straight", "lanes": 3, "oncoming_lanes": 1, "lane_width": 3.5,
           "length": 3000 }},
  "origin": {{ "lat": 41.1, "lon": 29.0, "alt": 60 }},
  "vehicles": [ {} ]
}})",
                     v);
}

std::string summary(const std::vector<double>& v) {
  return fmt::format("median {:.1f} p90 {:.1f} p99 {:.1f} max {:.1f} ms (n={})", percentile(v, 0.5),
                     percentile(v, 0.9), percentile(v, 0.99),
                     v.empty() ? NAN : *std::max_element(v.begin(), v.end()), v.size());
}

/// t1 of station @p station from a sim-server trace: for each input time, the first step
/// that applied it.
std::vector<double> t1_from_trace(const std::string& file, std::uint32_t station) {
  std::ifstream in(file);
  std::map<std::int64_t, std::int64_t> step_ts;        // tick → ts
  std::map<std::int64_t, std::int64_t> first_applied;  // input_ns → tick
  for (std::string line; std::getline(in, line);) {
    const auto r = nlohmann::json::parse(line, nullptr, false);
    if (!r.is_object())
      continue;
    const std::string ev = r.value("ev", "");
    if (ev == "server.step") {
      step_ts[r.value("tick", std::int64_t{0})] = r.value("ts", std::int64_t{0});
    } else if (ev == "server.controls" && r.value("station", 0u) == station) {
      const auto input = r.value("input_ns", std::int64_t{0});
      const auto tick = r.value("tick", std::int64_t{0});
      if (input > 0 && !first_applied.contains(input))
        first_applied[input] = tick;
    }
  }
  std::vector<double> out;
  for (const auto& [input, tick] : first_applied)
    if (const auto it = step_ts.find(tick); it != step_ts.end())
      out.push_back(static_cast<double>(it->second - input) / 1e6);
  return out;
}

struct Run {
  std::vector<double> press, release, t1, fps;
  std::string renderer;
};

void push_key(SDL_Scancode code, bool down) {
  SDL_Event e{};
  e.type = down ? SDL_KEYDOWN : SDL_KEYUP;
  e.key.state = down ? SDL_PRESSED : SDL_RELEASED;
  e.key.keysym.scancode = code;
  SDL_PushEvent(&e);
}

/// One run: a fresh sim-server with its trace, this client driving "me".
Run run(bool view, int trials, int vehicles, const AppOptions& base, double seconds_without) {
  Run out;
  tb::client::testing::SimServerProcess server;
  const std::string trace =
      (std::filesystem::temp_directory_path() / fmt::format("v3dlat_{}_{}.jsonl", getpid(), view))
          .string();
  // Nobody drives the other cars (they stand braked): the physics starts at once, not after
  // waiting for their scripts' driver.
  server.start_text(scenario(vehicles), {"--trace", trace, "--start-timeout", "0"});
  if (!server.available() || server.port() == 0)
    throw std::runtime_error("sim-server did not start (build it; $TESTBED_BIN): " + server.log());

  std::mutex mu;
  std::condition_variable cv;
  struct Seen {
    Clock::time_point finished;
    float throttle;
  };
  std::vector<Seen> frames;
  boost::asio::io_context io;
  std::atomic<ClientApp*> app_ptr{nullptr};
  std::string failure;
  std::thread loop([&] {
    AppOptions o = base;
    o.server = fmt::format("127.0.0.1:{}", server.port());
    o.forward = false;
    o.session.vehicles = {"me"};
    o.headless = !view;
    o.view = view ? ViewKind::k3d : ViewKind::kAuto;
    o.frame_observer = [&](const tb::client::view3d::FrameStats& s) {
      std::lock_guard l(mu);
      frames.push_back({s.finished, s.subject_controls.throttle});
      cv.notify_all();
    };
    try {
      ClientApp app(io, o);
      app_ptr = &app;
      if (app.render_loop() != nullptr)
        out.renderer = app.render_loop()->renderer();
      app.run();
      app_ptr = nullptr;
    } catch (const std::exception& e) {
      failure = e.what();
    }
  });
  const auto stop = [&] {
    boost::asio::post(io, [&] {
      if (auto* a = app_ptr.load())
        a->stop(0);
    });
    loop.join();
  };
  // Up and driving: the first state with our controls.
  std::this_thread::sleep_for(2s);
  if (!failure.empty()) {
    loop.join();
    throw std::runtime_error(failure);
  }
  std::mt19937 rng(42);
  std::uniform_int_distribution<int> pause_ms(150, 400);
  if (view) {
    const auto first_with = [&](Clock::time_point after, auto pred) -> std::optional<double> {
      std::unique_lock l(mu);
      const bool ok = cv.wait_for(l, 3s, [&] {
        for (const auto& f : frames)
          if (f.finished > after && pred(f.throttle))
            return true;
        return false;
      });
      if (!ok)
        return std::nullopt;
      for (const auto& f : frames)
        if (f.finished > after && pred(f.throttle))
          return std::chrono::duration<double, std::milli>(f.finished - after).count();
      return std::nullopt;
    };
    for (int i = 0; i < trials; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(pause_ms(rng)));
      {
        std::lock_guard l(mu);
        frames.clear();
      }
      auto t0 = Clock::now();
      push_key(SDL_SCANCODE_W, true);
      if (auto ms = first_with(t0, [](float t) { return t > 0.0f; }))
        out.press.push_back(*ms);
      std::this_thread::sleep_for(std::chrono::milliseconds(pause_ms(rng)));
      {
        std::lock_guard l(mu);
        frames.clear();
      }
      t0 = Clock::now();
      push_key(SDL_SCANCODE_W, false);
      if (auto ms = first_with(t0, [](float t) { return t == 0.0f; }))
        out.release.push_back(*ms);
      // Brake back to a standstill now and then, so that the car stays near the others.
      if (i % 5 == 4) {
        push_key(SDL_SCANCODE_S, true);
        std::this_thread::sleep_for(1500ms);
        push_key(SDL_SCANCODE_S, false);
      }
    }
    if (auto* a = app_ptr.load(); a != nullptr && a->render_loop() != nullptr)
      out.fps.push_back(a->render_loop()->fps());
  } else {
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds_without));
  }
  stop();
  std::this_thread::sleep_for(300ms);  // the trace's last lines
  out.t1 = t1_from_trace(trace, 3001);
  std::filesystem::remove(trace);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  int trials = 40, vehicles = 20;
  AppOptions base;
  CLI::App cli{"3D view: input → first frame that shows it; t1 with and without the view"};
  cli.add_option("--trials", trials, "key presses (each also released)")->capture_default_str();
  cli.add_option("--vehicles", vehicles, "cars in the scenario (one is ours)")
      ->capture_default_str();
  cli.add_option("--width", base.width)->capture_default_str();
  cli.add_option("--height", base.height)->capture_default_str();
  cli.add_option("--fps", base.fps)->capture_default_str();
  CLI11_PARSE(cli, argc, argv);
  spdlog::set_level(spdlog::level::warn);
  try {
    const std::string load0 = loadavg();
    const Run with = run(true, trials, vehicles, base, 0.0);
    const Run without = run(false, 0, vehicles, base, 20.0);
    fmt::print("renderer: {}; {}x{} at most {} fps, {} cars; render thread's rate {:.1f} fps\n",
               with.renderer, base.width, base.height, base.fps, vehicles,
               with.fps.empty() ? 0.0 : with.fps.front());
    fmt::print("key press   -> first frame with throttle: {}\n", summary(with.press));
    fmt::print("key release -> first frame without:       {}\n", summary(with.release));
    std::vector<double> both = with.press;
    both.insert(both.end(), with.release.begin(), with.release.end());
    fmt::print("either                                    {}\n", summary(both));
    fmt::print("t1 with the 3D view:    {}\n", summary(with.t1));
    fmt::print("t1 with no view at all: {}\n", summary(without.t1));
    fmt::print("load average before: {}; after: {}\n", load0, loadavg());
  } catch (const std::exception& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
  return 0;
}
