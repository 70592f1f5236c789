// sim-server: the world of a scenario — every vehicle's physics at a fixed step — served over
// TCP to sim-clients (sim-server/README.md, PROTOCOL.md).

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>

#include <fmt/format.h>

#include <csignal>
#include <fstream>
#include <sstream>

#include "common/clock/asio_runtime.hpp"
#include "common/clock/utc.hpp"
#include "common/map/scenario_map.hpp"
#include "common/scenario/loader.hpp"
#include "common/trace/tracer.hpp"
#include "sim-server/physics/world.hpp"
#include "sim-server/server/hub.hpp"
#include "sim-server/server/sim_loop.hpp"
#include "sim-server/server/tcp_server.hpp"

namespace {

constexpr int kExitRuntimeError = 1;

/// The map for the log: the built-in layout, or the OpenDRIVE file with its size.
std::string map_name(const tb::scenario::Scenario& s) {
  switch (s.map.type) {
    case tb::scenario::MapType::kStraight:
      return "straight (built-in)";
    case tb::scenario::MapType::kRing:
      return "ring (built-in)";
    case tb::scenario::MapType::kCrossing:
      return "crossing (built-in)";
    case tb::scenario::MapType::kOpenDrive:
      return fmt::format("{} (OpenDRIVE, {} roads, {} junctions)", s.map.file,
                         s.network->roads.size(), s.network->junctions.size());
  }
  return "?";
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"sim-server: Bullet vehicle dynamics for every car of a scenario, over TCP"};
  std::string scenario_file, trace_file, bind = "0.0.0.0", log_level = "info";
  std::uint16_t port = 2000;
  bool fast = false;
  std::optional<double> duration;
  std::size_t queue = tb::server::TcpOptions{}.max_queued_frames;
  bool mesh_cast = false;
  double start_timeout_s = 30.0;
  app.add_option("--scenario", scenario_file, "scenario file (JSON)")->required();
  app.add_option("--port", port, "TCP port to listen on (0: any free port)")->capture_default_str();
  app.add_option("--bind", bind, "address to listen on")->capture_default_str();
  app.add_flag("--fast", fast,
               "step as fast as possible instead of in real time (each step waits for the drivers' "
               "controls)");
  app.add_option("--duration", duration,
                 "stop after this many seconds of sim time "
                 "(default: the scenario's duration, else run until "
                 "stopped)")
      ->check(CLI::PositiveNumber);
  app.add_option("--trace", trace_file, "write trace records (JSON lines) to this file");
  app.add_option("--queue", queue,
                 "State frames queued per client before it is dropped as too "
                 "slow")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  app.add_option("--start-timeout", start_timeout_s,
                 "seconds the first step waits for a driver on every scripted vehicle "
                 "(0: start at once)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 3600.0));
  app.add_flag("--mesh-raycast", mesh_cast,
               "wheels ray-test the road mesh instead of the flat ground (for non-flat maps)");
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::from_str(log_level));

  tb::scenario::Scenario scenario;
  try {
    scenario = tb::scenario::load_file(scenario_file);
  } catch (const tb::scenario::ScenarioError& e) {
    spdlog::error("{}", e.what());
    return tb::scenario::kExitBadScenario;
  }
  const std::string scenario_text = read_text(scenario_file);
  const std::size_t map_bytes = scenario.map_text ? scenario.map_text->size() : 0;
  if (scenario_text.size() > tb::wire::sim::kMaxScenarioText ||
      scenario.vehicles.size() > tb::wire::sim::kMaxVehicles ||
      map_bytes > tb::wire::sim::kMaxMapText) {
    spdlog::error(
        "{}: too large for the protocol ({} bytes, {} vehicles, a map of {} bytes; limits {}, {} "
        "and {})",
        scenario_file, scenario_text.size(), scenario.vehicles.size(), map_bytes,
        tb::wire::sim::kMaxScenarioText, tb::wire::sim::kMaxVehicles, tb::wire::sim::kMaxMapText);
    return tb::scenario::kExitBadScenario;
  }
  if (!duration)
    duration = scenario.duration_s;
  if (!trace_file.empty()) {
    try {
      tb::trace::configure(trace_file, "sim-server");
    } catch (const std::exception& e) {
      spdlog::error("--trace: {}", e.what());
      return kExitRuntimeError;
    }
  } else if (const auto path = tb::trace::configure_from_env("sim-server"); !path.empty()) {
    spdlog::info("tracing to {}", path);
  }

  std::unique_ptr<tb::server::physics::World> world;
  try {
    const auto map = std::make_shared<const tb::map::ScenarioMap>(scenario);
    for (const auto& note : map->notes())
      spdlog::info("map: {}", note);
    for (const auto& warning : scenario.network->warnings)
      spdlog::warn("map {}: {}", scenario.network->source, warning);
    world = std::make_unique<tb::server::physics::World>(
        scenario, map,
        tb::server::physics::WorldOptions{
            .step_s = 1.0 / scenario.rates.physics_hz,
            .ground_cast =
                mesh_cast ? std::optional(tb::server::physics::GroundCast::kMesh) : std::nullopt,
            .warmup_steps = static_cast<std::uint64_t>(
                std::llround(scenario.warmup_s * scenario.rates.physics_hz))});
    const auto& o = map->origin();
    spdlog::info(
        "map frame placed by the {} at {:.7f}, {:.7f}, {:.2f} m; wheels ray-test {} ({} "
        "ground triangles)",
        o.source, o.origin->latitude_deg, o.origin->longitude_deg, o.origin->altitude_m,
        world->mesh_cast() ? "the road mesh" : "the flat ground", world->ground_triangles());
    // The loader checked the plans against the map; the controllers refuse what they cannot run.
    const tb::server::SignalSet lights(scenario.signals, 0);
    for (const auto& p : scenario.signals) {
      spdlog::info("traffic lights at junction {}: {} signal groups, {} phases, a {:g} s cycle{}",
                   p.junction, p.groups.size(), p.phases.size(), p.cycle_s(),
                   p.default_plan ? " (the default plan: the scenario gives none)" : "");
    }
  } catch (const std::exception& e) {
    spdlog::error("{}: cannot build the world: {}", scenario_file, e.what());
    return tb::scenario::kExitBadScenario;
  }

  boost::asio::io_context io;
  tb::clock::AsioRuntime runtime(io);
  tb::server::Hub hub(*world, scenario, scenario_text, runtime);
  std::unique_ptr<tb::server::TcpServer> server;
  try {
    server =
        std::make_unique<tb::server::TcpServer>(io, hub, tb::server::TcpOptions{bind, port, queue});
  } catch (const std::exception& e) {
    spdlog::error("cannot listen on {}:{}: {}", bind, port, e.what());
    return kExitRuntimeError;
  }

  bool stopping = false;
  boost::asio::steady_timer deadline(io);
  std::chrono::steady_clock::time_point give_up;
  std::function<void()> wait_for_clients = [&] {
    if (server->live_connections() == 0 || std::chrono::steady_clock::now() > give_up) {
      io.stop();
      return;
    }
    deadline.expires_after(std::chrono::milliseconds(10));
    deadline.async_wait([&](boost::system::error_code ec) {
      if (!ec)
        wait_for_clients();
    });
  };
  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  auto shutdown = [&](const std::string& why, tb::wire::sim::CloseReason reason) {
    if (stopping)
      return;
    stopping = true;
    spdlog::info("shutting down: {}", why);
    server->stop();
    hub.shutdown(why, reason);
    signals.cancel();
    // Give the clients' last bytes a moment to leave, but never let a client that does not read
    // them keep the process alive.
    give_up = std::chrono::steady_clock::now() + std::chrono::seconds(1);
    wait_for_clients();
  };
  tb::server::SimLoop loop(
      runtime, *world, &hub,
      {fast, duration, std::chrono::milliseconds(std::llround(start_timeout_s * 1000.0))},
      [&io](std::function<void()> fn) { boost::asio::post(io, std::move(fn)); },
      [&] { shutdown("scenario finished", tb::wire::sim::CloseReason::kScenarioFinished); });
  signals.async_wait([&](boost::system::error_code ec, int sig) {
    if (!ec) {
      loop.stop();
      shutdown(sig == SIGINT ? "SIGINT" : "SIGTERM", tb::wire::sim::CloseReason::kShutdown);
    }
  });

  spdlog::info("scenario '{}' ({}): {} vehicle(s), map {}, physics {} Hz{}", scenario.name,
               scenario_file, world->size(), map_name(scenario), scenario.rates.physics_hz,
               fast ? ", fast" : ", real time");
  spdlog::info("listening on {}:{}", bind, server->port());
  {
    // One clock for the whole world (docs/time.md): every program dates sim time from here.
    const auto start = tb::clock::from_unix_ns(hub.world_start_ns());
    spdlog::info("world time: sim time 0 is {} ({})", tb::clock::format_utc(start),
                 scenario.start_time ? "the scenario's start_time"
                                     : "the host's clock now; a scenario may pin start_time");
    tb::trace::global().record("server.world_start", {{"world_start_ns", hub.world_start_ns()},
                                                      {"pinned", scenario.start_time.has_value()}});
  }
  loop.start();
  io.run();
  const auto& st = hub.stats();
  spdlog::info(
      "stopped after {} steps ({:.2f} s sim time); {} connection(s), {} closed for bad input, "
      "{} dropped as too slow, {} control value(s) clamped, {} watchdog stop(s), {} late "
      "step(s), {} resync(s), {} fast step(s) that gave up waiting for a driver",
      world->tick(), world->sim_time_ns() * 1e-9, st.connections, st.protocol_errors, st.slow_drops,
      st.clamped_values, st.watchdog_stops, loop.late_steps(), loop.resyncs(),
      loop.driver_waits_timed_out());
  const auto& off = world->off_road();
  spdlog::info(
      "off the road: {} departure(s) from the drivable lanes, {} vehicle(s) off them now{}",
      off.departures(), off.off_now(), tb::server::off_road_list(*world));
  tb::trace::global().flush();
  return 0;
}
