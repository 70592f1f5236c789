// station-host: many pooled ITS stations in one process (issue 33). Each is a complete stack
// (its-station's Station) with its own ITS clock, GNSS receiver fed from the state stream, link
// with its own MAC on the host's one interface, security entity and LDM.

#include <sys/socket.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <nlohmann/json.hpp>

#include "common/clock/asio_runtime.hpp"
#include "common/clock/gnss_disciplined_runtime.hpp"
#include "common/clock/held_clock_runtime.hpp"
#include "common/map/scenario_map.hpp"
#include "common/mqtt/mosquitto_client.hpp"
#include "common/scenario/loader.hpp"
#include "common/trace/tracer.hpp"
#include "common/util/kernel_stamp.hpp"
#include "its-station/facilities/shared_cam_decoder.hpp"
#include "its-station/station/station.hpp"
#include "network-emulator/radio/bridge_medium.hpp"
#include "station-host/app/host_config.hpp"
#include "station-host/app/host_security.hpp"
#include "station-host/app/host_status.hpp"
#include "station-host/feed/state_feed.hpp"
#include "station-host/link/host_socket.hpp"
#include "station-host/link/pooled_links.hpp"

namespace {

namespace asio = boost::asio;
using namespace std::chrono_literals;
using tb::host::ConfigError;

struct Options {
  std::string scenario;
  std::string stations;
  std::string radio = "wlan0";
  std::string states;
  std::string forwarding = "auto";
  std::string pki_dir;
  std::uint64_t seed = 1;
  std::string mqtt_host;
  int mqtt_port = 1883;
  std::string mqtt_user;
  std::string mqtt_password_file;
  std::string mqtt_prefix = "its";
  std::string status_file;
  std::string trace;
  double duration_s = 0.0;
  std::string log_level = "info";
};

/// One pooled station: its ITS clock, security entity and stack. Its GNSS receiver and vehicle
/// data belong to the feed, its link to the host's links.
struct PooledStation {
  std::unique_ptr<tb::clock::GnssDisciplinedRuntime> its_clock;
  std::unique_ptr<tb::its::security::SecurityEntity> security;
  std::unique_ptr<tb::its::station::Station> station;
};

std::unique_ptr<tb::mqtt::MosquittoClient> make_mqtt(const Options& o, tb::clock::Runtime& rt,
                                                     std::uint32_t first_station) {
  tb::mqtt::ClientConfig mc;
  mc.host = o.mqtt_host;
  mc.port = o.mqtt_port;
  // One login per host; its stations are disjoint from other hosts', so the first names it.
  mc.client_id = fmt::format("station-host-{}", first_station);
  mc.username = o.mqtt_user;
  if (!o.mqtt_password_file.empty()) {
    std::ifstream in(o.mqtt_password_file);
    if (!in || !std::getline(in, mc.password))
      throw ConfigError(fmt::format("--mqtt-password-file {}: cannot read a password from it",
                                    o.mqtt_password_file));
  }
  return std::make_unique<tb::mqtt::MosquittoClient>(rt, mc);
}

int run(const Options& o) {
  if (!o.trace.empty())
    tb::trace::configure(o.trace, "station-host");
  else
    tb::trace::configure_from_env("station-host");

  const tb::scenario::Scenario scenario = tb::scenario::load_file(o.scenario);
  const std::vector<std::uint32_t> ids = tb::host::parse_station_list(o.stations);
  const auto vehicles = tb::host::pooled_vehicles(scenario, ids);
  const tb::host::UdpEndpoint states = tb::host::parse_states_url(o.states);
  const auto why_not_kernel = tb::emu::radio::why_bridge_cannot_carry(scenario.channel);
  const tb::host::Forwarding forwarding =
      tb::host::resolve_forwarding(o.forwarding, why_not_kernel.value_or(""));
  const bool signs = scenario.security != tb::scenario::SecurityMode::kNone;
  if (signs && o.pki_dir.empty())
    throw ConfigError(
        "the scenario signs: --pki-dir DIR is needed (DIR/<station id>/ per station)");
  std::vector<std::filesystem::path> pki_dirs;
  if (signs)
    for (const std::uint32_t id : ids)
      pki_dirs.push_back(tb::host::station_pki_dir(o.pki_dir, id));

  const tb::map::ScenarioMap map(scenario);
  // One thread runs it (concurrency hint 1): a handler's post() (the MQTT flush, the pooled
  // links' flush) then waits in the thread's private queue, where the default hint makes each
  // one interrupt the reactor (an epoll_ctl and an extra epoll_wait, issue 33).
  asio::io_context io{1};
  tb::clock::AsioRuntime asio_runtime(io);
  // A frame read or a state datagram is taken up by many stations at one instant: the clock is
  // read once for all of them (common/clock/held_clock_runtime.hpp).
  tb::clock::HeldClockRuntime runtime(asio_runtime);

  auto socket = tb::host::HostSocket::open(io, o.radio);
  if (!socket)
    throw ConfigError(fmt::format("--radio: {}", socket.error().message()));
  std::optional<tb::host::PooledLinks> links;
  links.emplace(**socket, runtime, forwarding == tb::host::Forwarding::kKernel, [&] {
    asio::post(io, [&] {
      const auto held = runtime.hold();
      links->flush();
    });
  });
  (*socket)->set_handler([&](std::span<const std::uint8_t> frame, tb::clock::WallTime rx) {
    const auto held = runtime.hold();
    links->on_frame(frame, rx);
  });
  spdlog::info("station-host: {} pooled station(s) on {}, {}", ids.size(), o.radio,
               forwarding == tb::host::Forwarding::kKernel
                   ? "kernel forwarding (own transmissions looped back in-process)"
                   : fmt::format("forwarding in radio-medium ({})",
                                 why_not_kernel.value_or("--forwarding user")));

  tb::host::StateFeed feed(scenario, map.georeferencing(), runtime, o.seed);
  asio::ip::udp::socket state_socket(io);
  try {
    const asio::ip::udp::endpoint ep(asio::ip::make_address(states.address), states.port);
    state_socket.open(ep.protocol());
    state_socket.set_option(asio::socket_base::reuse_address(true));
    state_socket.set_option(asio::socket_base::receive_buffer_size(4 << 20));
    state_socket.bind(ep);
  } catch (const boost::system::system_error& e) {
    throw ConfigError(fmt::format("--states {}: cannot listen: {}", o.states, e.what()));
  }

  std::unique_ptr<tb::mqtt::MosquittoClient> mqtt;
  bool any_mqtt = false;
  for (const auto* v : vehicles)
    any_mqtt = any_mqtt || v->station_mqtt;
  if (any_mqtt && !o.mqtt_host.empty()) {
    mqtt = make_mqtt(o, runtime, ids.front());
    mqtt->start();
    spdlog::info("MQTT: one login for the stations that mirror to {}:{}", o.mqtt_host, o.mqtt_port);
  }

  // The stations hear each frame one after the other: one decoded CAM for all of them
  // (its-station/facilities/README.md: 1.21 → 0.55 µs per station and CAM at 300). Declared
  // before the stations, which hold it.
  tb::its::facilities::SharedCamDecoder cam_decoder;
  tb::its::geonet::SharedPacketParser packet_parser;
  std::vector<PooledStation> pooled;
  pooled.reserve(ids.size());
  tb::its::station::StationOverrides overrides;
  overrides.mqtt_prefix = o.mqtt_prefix;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const std::uint32_t id = ids[i];
    PooledStation p;
    p.its_clock = std::make_unique<tb::clock::GnssDisciplinedRuntime>(runtime);
    if (signs)
      p.security = tb::host::make_station_security(scenario, pki_dirs[i], id);
    tb::host::StationSources& src = feed.add(id);
    auto config = tb::its::station::make_station_config(id, &scenario, vehicles[i], overrides);
    const tb::its::station::StationPorts ports{runtime,
                                               *p.its_clock,
                                               *src.gnss,
                                               src.vehicle.get(),
                                               links->link(id),
                                               p.security.get(),
                                               config.mqtt ? mqtt.get() : nullptr};
    p.station = std::make_unique<tb::its::station::Station>(ports, std::move(config));
    p.station->share_cam_decoder(cam_decoder);
    p.station->share_packet_parser(packet_parser);
    pooled.push_back(std::move(p));
  }

  // Each state datagram is taken up as of its kernel receive stamp (SO_TIMESTAMPNS): the fixes
  // in it discipline the pooled stations' ITS clocks, which a datagram read late would put
  // behind (HeldClockRuntime::hold_at).
  {
    const int on = 1;
    if (::setsockopt(state_socket.native_handle(), SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof on) < 0)
      throw ConfigError(
          fmt::format("--states {}: SO_TIMESTAMPNS: {}", o.states, std::strerror(errno)));
    state_socket.non_blocking(true);
  }
  std::vector<std::uint8_t> datagram(65536);
  std::function<void()> receive_states = [&] {
    state_socket.async_wait(
        asio::ip::udp::socket::wait_read, [&](const boost::system::error_code& ec) {
          if (ec == asio::error::operation_aborted)
            return;
          for (;;) {
            iovec iov{datagram.data(), datagram.size()};
            alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timespec))];
            msghdr msg{};
            msg.msg_iov = &iov;
            msg.msg_iovlen = 1;
            msg.msg_control = control;
            msg.msg_controllen = sizeof control;
            const ssize_t n = ::recvmsg(state_socket.native_handle(), &msg, 0);
            if (n < 0)
              break;  // EAGAIN: all read (an error is the next wait's)
            const auto stamp = tb::kernel_rx_unix_ns(msg);
            const auto held =
                stamp ? runtime.hold_at(tb::clock::from_unix_ns(*stamp)) : runtime.hold();
            feed.handle_datagram({datagram.data(), static_cast<std::size_t>(n)});
          }
          receive_states();
        });
  };

  tb::host::HostStatus status(o.status_file);
  auto write_status = [&] {
    if (o.status_file.empty())
      return;
    std::vector<const tb::its::station::Station*> stations;
    std::vector<const tb::its::security::SecurityEntity*> entities;
    for (const PooledStation& p : pooled) {
      stations.push_back(p.station.get());
      entities.push_back(p.security.get());
    }
    status.write(stations, entities, links->counters(), (*socket)->stats(), feed.counters());
  };
  // Every station with every neighbour id: at 300 stations in range that is 90,000 ids, and
  // written twice a second it took 12 % of the host's CPU. 0.5 s up to 50 stations, then 10 ms
  // more per station.
  const auto status_interval = std::max<tb::clock::Duration>(500ms, pooled.size() * 10ms);
  asio::steady_timer status_timer(io);
  std::function<void()> status_tick = [&] {
    write_status();
    status_timer.expires_after(status_interval);
    status_timer.async_wait([&](const boost::system::error_code& ec) {
      if (!ec)
        status_tick();
    });
  };

  asio::signal_set signals(io, SIGINT, SIGTERM);
  asio::steady_timer duration_timer(io);
  auto shutdown = [&](const std::string& why) {
    spdlog::info("shutting down: {}", why);
    for (PooledStation& p : pooled)
      p.station->stop();
    signals.cancel();
    status_timer.cancel();
    duration_timer.cancel();
    state_socket.close();
    write_status();
    io.stop();
  };
  signals.async_wait([&](const boost::system::error_code& ec, int sig) {
    if (!ec)
      shutdown(sig == SIGINT ? "SIGINT" : "SIGTERM");
  });
  if (o.duration_s > 0) {
    duration_timer.expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(o.duration_s)));
    duration_timer.async_wait([&](const boost::system::error_code& ec) {
      if (!ec)
        shutdown("--duration elapsed");
    });
  }

  for (PooledStation& p : pooled)
    p.station->start();
  receive_states();
  status_tick();
  spdlog::info("station-host: stations {} running, states on {}", o.stations, o.states);
  io.run();

  if (mqtt)
    mqtt->stop();
  tb::trace::global().flush();
  const auto& c = links->counters();
  spdlog::info(
      "station-host: frames read {} (plain {}, pooled {}, malformed pooled {}), deliveries {}, "
      "looped back {}, sent {} (errors {}); states {} (malformed datagrams {})",
      c.frames, c.plain, c.pooled, c.malformed_pooled, c.deliveries, c.looped_back, c.sent,
      c.send_errors, feed.counters().states, feed.counters().malformed);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"station-host: many pooled ITS stations (complete stacks) in one process"};
  app.add_option("--scenario", o.scenario, "scenario file")->required();
  app.add_option("--stations", o.stations, "pooled stations of the scenario: ID[,ID...]")
      ->required();
  app.add_option("--radio", o.radio, "the host's radio interface")->capture_default_str();
  app.add_option("--states", o.states, "where the state stream arrives: udp://ADDR:PORT")
      ->required();
  app.add_option("--forwarding", o.forwarding,
                 "how radio-medium forwards: auto, kernel or user (as radio-medium's option)")
      ->capture_default_str();
  app.add_option("--pki-dir", o.pki_dir, "its-pki export per station: DIR/<station id>/");
  app.add_option("--seed", o.seed, "the GNSS error model's seed (network-emulator's --seed)")
      ->capture_default_str();
  app.add_option("--mqtt-host", o.mqtt_host, "MQTT broker (none: no MQTT)");
  app.add_option("--mqtt-port", o.mqtt_port, "MQTT broker port")->capture_default_str();
  app.add_option("--mqtt-user", o.mqtt_user, "MQTT user name");
  app.add_option("--mqtt-password-file", o.mqtt_password_file, "file holding the MQTT password")
      ->check(CLI::ExistingFile);
  app.add_option("--mqtt-prefix", o.mqtt_prefix, "topic prefix")->capture_default_str();
  app.add_option("--status-file", o.status_file,
                 "write every station's counters and neighbours as JSON to FILE every 0.5 s "
                 "(10 ms per station above 50 stations) and at the end");
  app.add_option("--trace", o.trace, "write trace records (JSON lines) to FILE");
  app.add_option("--duration", o.duration_s, "stop after this many seconds (0: run until signal)");
  app.add_option("--log-level", o.log_level, "trace, debug, info, warn, error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::from_str(o.log_level));
  try {
    return run(o);
  } catch (const ConfigError& e) {
    spdlog::error("station-host: {}", e.what());
    return 2;
  } catch (const tb::scenario::ScenarioError& e) {
    spdlog::error("{}", e.what());
    return tb::scenario::kExitBadScenario;
  } catch (const std::exception& e) {
    spdlog::error("station-host: {}", e.what());
    return 1;
  }
}
