// sim-client: drive sim-server vehicles with a keyboard, game controller, wheel or the
// scenario's scripted drivers; draw the driver's view; forward states to the network emulator.
#include <csignal>
#include <iostream>

#include <fmt/format.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>

#include "common/trace/tracer.hpp"
#include "sim-client/app/client_app.hpp"

int main(int argc, char** argv) {
  using namespace tb::client;
  // Logs go to stderr so that stdout carries only what was asked for (--list, --help-keys).
  spdlog::set_default_logger(spdlog::stderr_color_mt("sim-client"));
  AppOptions o;
  CLI::App cli{"sim-client: drive vehicles of sim-server and forward their states"};
  cli.add_option("--server", o.server, "sim-server address, HOST[:PORT] (port 2000 by default)")
      ->capture_default_str();
  cli.add_option("--vehicle", o.session.vehicles,
                 "scenario id of a vehicle to drive (repeatable); scripted vehicles run their "
                 "script, others follow this client's input");
  cli.add_flag("--scripted", o.session.scripted, "drive every scripted vehicle of the scenario");
  cli.add_flag("--reconnect", o.session.reconnect,
               "reconnect after the server said the scenario finished (for a server that is "
               "restarted with the next run); otherwise exit 0 then, or with a window say so "
               "and wait until it is closed");
  cli.add_flag("--forward-undriven", o.session.forward_undriven,
               "also forward the states of the vehicles nobody drives (the launcher's scripted "
               "client: a human car's station keeps its fixes before its driver comes and "
               "after they left)");
  cli.add_flag("--list", o.session.list_only,
               "print the scenario's vehicles and who drives them, then exit");
  cli.add_option("--name", o.session.client_name, "client name shown to the server and others")
      ->capture_default_str();
  cli.add_option("--emulator", o.emulator, "network emulator's state port, HOST:PORT")
      ->capture_default_str();
  bool no_forward = false;
  cli.add_flag("--no-forward", no_forward, "do not forward vehicle states to the emulator");
  std::string mapping;
  cli.add_option("--mapping", mapping,
                 "JSON controller mapping (game controller, joystick, wheel); without it the "
                 "keyboard drives")
      ->check(CLI::ExistingFile);
  cli.add_flag("--headless", o.headless, "run without a window");
  std::string screenshot;
  cli.add_option("--screenshot", screenshot, "write a PNG of the view to FILE");
  cli.add_option("--after", o.screenshot_after_s, "seconds after start to take the screenshot")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e6));
  double duration = 0.0;
  cli.add_option("--duration", duration, "quit after SECONDS")->check(CLI::Range(0.0, 1e9));
  cli.add_option("--width", o.width, "view width, pixels")->capture_default_str();
  cli.add_option("--height", o.height, "view height, pixels")->capture_default_str();
  cli.add_option("--fps", o.fps, "view frame rate (at most)")->capture_default_str();
  std::string view = "auto";
  cli.add_option("--view", view,
                 "3d (OpenSceneGraph), topdown (the 2D diagram) or auto: 3d when a display "
                 "is there")
      ->capture_default_str();
  std::string camera;
  cli.add_option("--camera", camera,
                 "3D camera at start: chase, cockpit (or hood), top, orbit (Tab switches); "
                 "default chase, orbit when watching");
  cli.add_option("--follow", o.follow,
                 "3D view: the car (scenario id) the cameras and the HUD follow at start, as if "
                 "picked with [ ] (a watcher sees that car's signal panel and warnings)");
  cli.add_option("--fov", o.fov_deg, "horizontal field of view of the 3D view, degrees")
      ->capture_default_str();
  cli.add_flag("--fullscreen", o.fullscreen, "fill the screen");
  bool no_vsync = false;
  cli.add_flag("--no-vsync", no_vsync, "do not wait for the display's refresh to swap");
  std::string mqtt;
  cli.add_option("--mqtt", mqtt,
                 "broker HOST[:PORT] to read the stations' V2X warnings, CAM links and DENMs "
                 "from (port 1883 by default)");
  cli.add_option("--mqtt-user", o.mqtt_user, "MQTT reader account")->capture_default_str();
  cli.add_option("--mqtt-password", o.mqtt_password, "its password")->capture_default_str();
  std::string trace;
  cli.add_option("--trace", trace, "write trace records (JSON lines) to FILE");
  bool help_keys = false;
  cli.add_flag("--help-keys", help_keys, "print the key map and exit");
  CLI11_PARSE(cli, argc, argv);

  if (help_keys) {
    for (const auto& k : key_map_help())
      fmt::print("{:<18} {}\n", k.keys, k.action);
    return 0;
  }
  o.forward = !no_forward;
  o.vsync = !no_vsync;
  if (const auto v = parse_view(view)) {
    o.view = *v;
  } else {
    fmt::print(stderr, "--view {}: expected 3d, topdown or auto\n", view);
    return kExitUsage;
  }
  if (!camera.empty()) {
    o.camera = tb::client::view3d::parse_camera(camera);
    if (!o.camera) {
      fmt::print(stderr, "--camera {}: expected chase, cockpit, hood, top or orbit\n", camera);
      return kExitUsage;
    }
  }
  if (!mqtt.empty())
    o.mqtt = mqtt;
  if (!mapping.empty())
    o.mapping = mapping;
  if (!screenshot.empty())
    o.screenshot = screenshot;
  if (cli.count("--duration") > 0)
    o.duration_s = duration;
  if (o.session.list_only)
    o.headless = true;

  try {
    if (!trace.empty()) {
      tb::trace::configure(trace, "sim-client");
    } else {
      tb::trace::configure_from_env("sim-client");
    }
    boost::asio::io_context io;
    ClientApp app(io, o);
    boost::asio::signal_set signals(io, SIGINT, SIGTERM);
    signals.async_wait([&](const boost::system::error_code& ec, int sig) {
      if (!ec) {
        spdlog::info("signal {}: stopping", sig);
        app.stop(0);
      }
    });
    const int code = app.run();
    signals.cancel();
    tb::trace::global().flush();
    return code;
  } catch (const MappingError& e) {
    spdlog::error("bad controller mapping: {}", e.what());
    return kExitUsage;
  } catch (const std::invalid_argument& e) {
    spdlog::error("{}", e.what());
    return kExitUsage;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
