// its-station: one ITS-G5 station — gpsd positioning, CAN vehicle data, GeoNetworking/BTP over
// the radio interface, CA and DEN services, LDM, LCRW and MQTT. Usage: README.md in
// its-station, "Facilities and the station program".

#include <net/if.h>

#include <chrono>
#include <csignal>
#include <fstream>
#include <memory>
#include <optional>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <nlohmann/json.hpp>

#include "common/can/socketcan_bus.hpp"
#include "common/can/udp_can_bus.hpp"
#include "common/clock/asio_runtime.hpp"
#include "common/clock/gnss_disciplined_runtime.hpp"
#include "common/mqtt/mosquitto_client.hpp"
#include "common/scenario/loader.hpp"
#include "common/trace/tracer.hpp"
#include "common/util/snapshot_file.hpp"
#include "its-station/app/rsu_mode.hpp"
#include "its-station/apps/mqtt/messages.hpp"
#include "its-station/facilities/can_vehicle_data.hpp"
#include "its-station/facilities/gpsd_position_provider.hpp"
#include "its-station/facilities/gpsd_process.hpp"
#include "its-station/link/packet_socket_link.hpp"
#include "its-station/security/pki_files.hpp"
#include "its-station/security/security_entity.hpp"
#include "its-station/station/station.hpp"
#include "its-station/station/station_config.hpp"

namespace {

namespace asio = boost::asio;
namespace fac = tb::its::facilities;
namespace apps = tb::its::apps;
using namespace std::chrono_literals;

struct Options {
  std::uint32_t station_id = 0;
  int station_type = -1;  // -1: from the scenario, else passengerCar
  std::string scenario;
  std::string radio = "wlan0";
  std::string can_transport = "auto";  // auto | socketcan | udp | none
  std::string can_interface = "vcan0";
  std::uint16_t can_udp_port = 20000;
  std::string dbc = TESTBED_VEHICLE_DBC;
  std::string gpsd;  // host:port of an existing gpsd; empty: start our own
  std::uint16_t gpsd_port = 2947;
  std::uint16_t nmea_port = 10110;
  double gpsd_wait_s = 10.0;
  std::string cam_policy;  // etsi | fixed; empty: from the scenario
  std::string security;    // none | signed | signed-permissive; empty: from the scenario
  std::string pki_dir;     // its-pki's directory (root, AA, this station's AT)
  // PSID=PAST_MS[:FUTURE_MS], each over the scenario's security_time_windows for that PSID
  std::vector<std::string> security_time_windows;
  double cam_period_ms = 0.0;
  std::string mqtt_host;
  int mqtt_port = 1883;
  std::string mqtt_user;
  std::string mqtt_password;
  std::string mqtt_password_file;
  std::string mqtt_prefix = "its";
  int mqtt_cam_interval_ms = 200;
  double denm_repetition_ms = 100.0;
  // While the risk lasts: LCRW cancels its event when the warning clears, and its DENMs are valid
  // for 10 s (LcrwDenmConfig), which ends repetition at the latest (EN 302 637-3,
  // T_RepetitionDuration).
  double denm_repetition_duration_s = 10.0;
  bool no_keep_alive_forwarding = false;
  bool lcrw = true;
  bool signal_app = true;  // --no-signal-app (--signals is an RSU's feed)
  std::string trace;
  std::string status_file;
  double duration_s = 0.0;
  std::string log_level = "info";
  std::string signals;  // RSU mode: the signal feed's udp://HOST:PORT (default 0.0.0.0:4720)
};

/// The security entity of --security / the scenario's `security`, with this station's AT and
/// the scenario's root from --pki-dir; null for none.
std::unique_ptr<tb::its::security::SecurityEntity> make_security(
    const Options& o, const std::optional<tb::scenario::Scenario>& scenario);

/// What cannot go on: a message for the log and the exit code.
struct Fatal {
  std::string message;
  int code = 1;
};

std::pair<std::string, std::string> split_host_port(const std::string& s, const char* what) {
  const auto colon = s.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == s.size())
    throw Fatal{fmt::format("{} '{}': expected HOST:PORT", what, s), 1};
  return {s.substr(0, colon), s.substr(colon + 1)};
}

std::unique_ptr<tb::can::CanBus> open_can(asio::io_context& io, const Options& o) {
  if (o.can_transport == "none")
    return nullptr;
  const bool kernel_can = tb::can::socketcan_available();
  const bool iface = if_nametoindex(o.can_interface.c_str()) != 0;
  bool use_socketcan = o.can_transport == "socketcan";
  if (o.can_transport == "auto") {
    use_socketcan = kernel_can && iface;
    if (use_socketcan)
      spdlog::info("CAN: SocketCAN on {} (kernel CAN present, interface exists)", o.can_interface);
    else
      spdlog::info("CAN: UDP stand-in (cannelloni format) on port {} because {}", o.can_udp_port,
                   kernel_can ? fmt::format("there is no interface {}", o.can_interface)
                              : std::string("this kernel has no SocketCAN"));
  }
  if (use_socketcan) {
    auto bus = tb::can::SocketCanBus::open(io, o.can_interface);
    if (!bus)
      throw Fatal{fmt::format("CAN: cannot open SocketCAN interface '{}': {}", o.can_interface,
                              bus.error().message())};
    return std::move(*bus);
  }
  try {
    return tb::can::UdpCanBus::bind(
        io, asio::ip::udp::endpoint(asio::ip::address_v4::any(), o.can_udp_port));
  } catch (const boost::system::system_error& e) {
    throw Fatal{fmt::format("CAN: cannot bind UDP port {}: {}", o.can_udp_port, e.what())};
  }
}

tb::its::station::StationOverrides overrides(const Options& o) {
  tb::its::station::StationOverrides v;
  v.station_type = o.station_type;
  v.cam_policy = o.cam_policy;
  v.cam_period_ms = o.cam_period_ms;
  v.no_lcrw = !o.lcrw;
  v.no_signals = !o.signal_app;
  v.no_keep_alive_forwarding = o.no_keep_alive_forwarding;
  v.denm_repetition_ms = o.denm_repetition_ms;
  v.denm_repetition_duration_s = o.denm_repetition_duration_s;
  v.mqtt_prefix = o.mqtt_prefix;
  v.mqtt_cam_interval_ms = o.mqtt_cam_interval_ms;
  return v;
}

int run(const Options& o) {
  if (!o.trace.empty())
    tb::trace::configure(o.trace, "its-station");
  else
    tb::trace::configure_from_env("its-station");

  // Station identity and configuration, from the scenario where one is given.
  std::optional<tb::scenario::Scenario> scenario;
  const tb::scenario::Vehicle* vehicle = nullptr;
  // A road-side unit (issue 34): our station id among the scenario's `rsus`.
  const tb::scenario::Rsu* rsu = nullptr;
  if (!o.scenario.empty()) {
    scenario = tb::scenario::load_file(o.scenario);
    vehicle = scenario->find_station(o.station_id);
    if (!vehicle)
      rsu = scenario->find_rsu(o.station_id);
    if (!vehicle && !rsu)
      throw Fatal{fmt::format("scenario {}: no vehicle and no rsu with station id {}", o.scenario,
                              o.station_id),
                  tb::scenario::kExitBadScenario};
  }
  tb::its::station::StationOverrides station_overrides = overrides(o);
  Options effective = o;
  if (rsu) {
    // RSU mode: station type roadSideUnit (15), no CAN, no LCRW.
    if (o.station_type < 0)
      station_overrides.station_type = tb::its::messages::station_type::kRoadSideUnit;
    station_overrides.no_lcrw = true;
    effective.can_transport = "none";
    spdlog::info("rsu {}: station {} serves junction {} (station type {}, no CAN, no LCRW)",
                 rsu->id, o.station_id, rsu->junction, station_overrides.station_type);
  } else if (!o.signals.empty()) {
    spdlog::warn("--signals {} ignored: station {} is no road-side unit of the scenario", o.signals,
                 o.station_id);
  }
  const tb::its::station::StationConfig config = tb::its::station::make_station_config(
      o.station_id, scenario ? &*scenario : nullptr, vehicle, station_overrides);

  // One thread runs it (concurrency hint 1): a handler's post() (the MQTT flush, the pooled
  // links' flush) then waits in the thread's private queue, where the default hint makes each
  // one interrupt the reactor (an epoll_ctl and an extra epoll_wait, issue 33).
  asio::io_context io{1};
  tb::clock::AsioRuntime runtime(io);

  // Positioning: our own gpsd fed NMEA over UDP, unless told to use an existing one.
  std::optional<fac::GpsdProcess> gpsd_process;
  fac::GpsdPositionProvider::Config gps_cfg;
  if (o.gpsd.empty()) {
    fac::GpsdProcess::Options p;
    p.client_port = std::to_string(o.gpsd_port);
    p.nmea_port = std::to_string(o.nmea_port);
    auto started = fac::GpsdProcess::start(p);
    if (!started)
      throw Fatal{"gpsd: " + started.error()};
    gpsd_process.emplace(std::move(*started));
    spdlog::info("gpsd: started ({}), NMEA on UDP {}", fmt::join(gpsd_process->argv(), " "),
                 o.nmea_port);
    gps_cfg.host = "127.0.0.1";
    gps_cfg.port = std::to_string(o.gpsd_port);
  } else {
    std::tie(gps_cfg.host, gps_cfg.port) = split_host_port(o.gpsd, "--gpsd");
  }
  fac::GpsdPositionProvider gnss(io, runtime, gps_cfg);

  // Vehicle data.
  auto can_bus = open_can(io, effective);
  // The decoder points into the database's messages: it must outlive the decoder.
  std::optional<tb::can::Database> can_db;
  std::unique_ptr<fac::CanVehicleDataProvider> vehicle_data;
  if (can_bus) {
    auto db = tb::can::Database::load(o.dbc);
    if (!db)
      throw Fatal{"CAN database: " + db.error().message()};
    can_db = std::move(*db);
    auto decoder = fac::CanVehicleDecoder::create(*can_db);
    if (!decoder)
      throw Fatal{fmt::format("CAN database {}: {}", o.dbc, decoder.error().detail)};
    vehicle_data =
        std::make_unique<fac::CanVehicleDataProvider>(*can_bus, std::move(*decoder), runtime);
    vehicle_data->start();
  }

  // The station's ITS clock (docs/time.md), disciplined by the Station from its fixes.
  tb::clock::GnssDisciplinedRuntime its_clock(runtime);

  // Radio: the real interface (hwsim in OCB mode, or the veth stand-in of the same name).
  auto link = tb::its::link::PacketSocketLink::open(io, o.radio);
  if (!link)
    throw Fatal{link.error().message() +
                (link.error().kind == tb::its::link::OpenErrorKind::kNoSuchInterface
                     ? " — is the station's radio set up (--radio)?"
                     : "")};
  spdlog::info("radio: {} ({}), MAC {}", o.radio,
               (*link)->driver().empty() ? "driver unknown" : (*link)->driver(),
               tb::its::link::to_string((*link)->address()));

  std::unique_ptr<tb::its::security::SecurityEntity> security = make_security(o, scenario);
  if (security && !security->can_sign(tb::its::security::kPsidGnMgmt))
    spdlog::warn(
        "security: the AT of {} has no GN-MGMT permission (psid 141, an older "
        "its-pki): beacons go unsigned; make the PKI again to sign them",
        o.pki_dir);

  // MQTT: one login per station, unless the scenario keeps this station off MQTT.
  std::unique_ptr<tb::mqtt::MosquittoClient> mqtt;
  std::string mqtt_root;
  if (!o.mqtt_host.empty() && !config.mqtt)
    spdlog::info("MQTT: off for this station (the scenario's station.mqtt)");
  if (!o.mqtt_host.empty() && config.mqtt) {
    tb::mqtt::ClientConfig mc;
    mc.host = o.mqtt_host;
    mc.port = o.mqtt_port;
    mc.client_id = fmt::format("station-{}", o.station_id);
    mc.username = o.mqtt_user;
    mc.password = o.mqtt_password;
    if (!o.mqtt_password_file.empty()) {
      std::ifstream in(o.mqtt_password_file);
      if (!in || !std::getline(in, mc.password))
        throw Fatal{fmt::format("--mqtt-password-file {}: cannot read a password from it",
                                o.mqtt_password_file)};
    }
    apps::mqtt::Topics topics(o.mqtt_prefix, o.station_id);
    mc.status_topic = topics.status();
    mc.publish_prefix = topics.root() + "/";
    mqtt_root = topics.root();
    mqtt = std::make_unique<tb::mqtt::MosquittoClient>(runtime, mc);
    // What one wake-up publishes (a burst of received CAMs) goes to the broker in one write
    // once the io_context has run the wake-up's handlers: a post from the io thread itself waits
    // in its queue and costs no wake-up (issue 33, docs/latency.md).
    mqtt->set_flush_request(
        [&io, client = mqtt.get()] { asio::post(io, [client] { client->flush(); }); });
  }

  tb::its::station::Station station(
      tb::its::station::StationPorts{runtime, its_clock, gnss, vehicle_data.get(), **link,
                                     security.get(), mqtt.get()},
      config);
  if (mqtt) {
    mqtt->start();
    spdlog::info("MQTT: publishing to {}:{} under {}", o.mqtt_host, o.mqtt_port, mqtt_root);
  }
  std::unique_ptr<tb::its::app::RsuMode> rsu_mode;
  if (rsu) {
    try {
      rsu_mode = std::make_unique<tb::its::app::RsuMode>(
          io, its_clock, station.sender(), *scenario, *rsu,
          o.signals.empty() ? tb::its::app::kDefaultSignalsUrl : o.signals);
    } catch (const tb::map::odr::MapError& e) {
      throw Fatal{fmt::format("scenario {}: rsu {}: {}", o.scenario, rsu->id, e.what()),
                  tb::scenario::kExitBadScenario};
    } catch (const std::invalid_argument& e) {
      throw Fatal{e.what(), 2};
    }
  }

  // Status file: the LDM as the station sees it, for operators and tests.
  asio::steady_timer status_timer(io);
  std::optional<tb::StatusFileWriter> status_file;
  if (!o.status_file.empty())
    status_file.emplace(o.status_file);
  auto write_status = [&] {
    if (!status_file)
      return;
    nlohmann::json j = station.status();
    if (rsu_mode)
      j["rsu"] = rsu_mode->status();
    status_file->write(j.dump() + "\n");
  };
  std::function<void()> status_tick = [&] {
    write_status();
    status_timer.expires_after(500ms);
    status_timer.async_wait([&](const boost::system::error_code& ec) {
      if (!ec)
        status_tick();
    });
  };

  // Shutdown on SIGINT/SIGTERM (or after --duration).
  asio::signal_set signals(io, SIGINT, SIGTERM);
  asio::steady_timer gpsd_deadline(io);
  asio::steady_timer duration_timer(io);
  int exit_code = 0;
  auto shutdown = [&](const std::string& why, int code) {
    spdlog::info("shutting down: {}", why);
    exit_code = code;
    if (rsu_mode)
      rsu_mode->stop();
    station.stop();
    gnss.stop();
    signals.cancel();
    status_timer.cancel();
    gpsd_deadline.cancel();
    duration_timer.cancel();
    write_status();
    io.stop();
  };
  signals.async_wait([&](const boost::system::error_code& ec, int sig) {
    if (!ec)
      shutdown(sig == SIGINT ? "SIGINT" : "SIGTERM", 0);
  });
  if (o.duration_s > 0) {
    duration_timer.expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(o.duration_s)));
    duration_timer.async_wait([&](const boost::system::error_code& ec) {
      if (!ec)
        shutdown("--duration elapsed", 0);
    });
  }
  // gpsd must answer within --gpsd-wait, or the station cannot work at all.
  gpsd_deadline.expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(o.gpsd_wait_s)));
  gpsd_deadline.async_wait([&](const boost::system::error_code& ec) {
    if (ec || gnss.connected())
      return;
    spdlog::error("gpsd at {}:{} did not accept a connection within {} s{}", gps_cfg.host,
                  gps_cfg.port, o.gpsd_wait_s,
                  gpsd_process && !gpsd_process->running() ? " (our gpsd exited)" : "");
    shutdown("no gpsd", 1);
  });

  gnss.start();
  station.start();
  if (rsu_mode) {
    try {
      rsu_mode->start();
    } catch (const boost::system::system_error& e) {
      throw Fatal{fmt::format("rsu: cannot listen for the signal feed on {}: {}",
                              o.signals.empty() ? tb::its::app::kDefaultSignalsUrl : o.signals,
                              e.what())};
    }
  }
  status_tick();
  io.run();

  if (mqtt) {
    mqtt->stop();
    spdlog::info("MQTT: {} message(s) mirrored in {} batch(es)", mqtt->batched_messages(),
                 mqtt->batches());
  }
  tb::trace::global().flush();
  station.log_totals();
  return exit_code;
}

std::unique_ptr<tb::its::security::SecurityEntity> make_security(
    const Options& o, const std::optional<tb::scenario::Scenario>& scenario) {
  namespace sec = tb::its::security;
  sec::SecurityMode mode = sec::SecurityMode::kNone;
  if (!o.security.empty()) {
    mode = *sec::parse_security_mode(o.security);  // CLI11 checked the name
  } else if (scenario) {
    switch (scenario->security) {
      case tb::scenario::SecurityMode::kNone:
        break;
      case tb::scenario::SecurityMode::kSigned:
        mode = sec::SecurityMode::kSigned;
        break;
      case tb::scenario::SecurityMode::kSignedPermissive:
        mode = sec::SecurityMode::kSignedPermissive;
        break;
    }
  }
  if (mode == sec::SecurityMode::kNone)
    return nullptr;
  if (o.pki_dir.empty())
    throw Fatal{fmt::format("security {} needs --pki-dir (make one with its-pki make)",
                            sec::to_string(mode)),
                2};
  // Generation-time windows per ITS-AID: the defaults, then the scenario's, then the options.
  sec::VerifierConfig config;
  if (scenario) {
    for (const auto& [psid, w] : scenario->security_time_windows) {
      sec::TimePolicy p = sec::default_time_policy(psid);
      if (w.past_ms)
        p.past = std::chrono::milliseconds(*w.past_ms);
      if (w.future_ms)
        p.future = std::chrono::milliseconds(*w.future_ms);
      config.time_policy[psid] = p;
    }
  }
  for (const auto& spec : o.security_time_windows) {
    const auto w = sec::parse_time_window(spec);  // CLI11 checked it
    config.time_policy[w->first] = w->second;
  }
  for (const auto& [psid, p] : config.time_policy)
    spdlog::info("security: generation-time window of ITS-AID {}: -{} ms .. +{} ms{}", psid,
                 std::chrono::duration_cast<std::chrono::milliseconds>(p.past).count(),
                 std::chrono::duration_cast<std::chrono::milliseconds>(p.future).count(),
                 p.replay_detection ? ", replays dropped" : "");
  try {
    auto creds = sec::load_station_credentials(sec::PkiPaths{o.pki_dir}, o.station_id);
    sec::Verifier verifier({creds.root}, config);
    // The chain is checked here, the validity per packet on the ITS clock: before the first
    // fix nobody knows the world's date, which a pinned start_time puts far from the host's.
    const auto aa = verifier.add_authority(
        creds.aa, static_cast<sec::Time64>(creds.aa.tbs.validity.start) * 1'000'000);
    if (aa != sec::VerifyResult::kOk)
      throw Fatal{fmt::format("{}: the AA does not verify under the root: {}", o.pki_dir,
                              sec::to_string(aa)),
                  2};
    spdlog::info("security: {}, AT {} of {}", sec::to_string(mode),
                 sec::PkiPaths{o.pki_dir}.at_cert(o.station_id).string(), o.pki_dir);
    return std::make_unique<sec::SecurityEntity>(
        mode, sec::Signer(std::move(creds.at), std::move(creds.at_key), creds.aa),
        std::move(verifier));
  } catch (const sec::PkiFileError& e) {
    throw Fatal{fmt::format("security: {}", e.what()), 2};
  } catch (const sec::CryptoError& e) {
    throw Fatal{fmt::format("security: {}", e.what()), 2};
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"its-station: an ITS-G5 station (GN/BTP, CA, DEN, LDM, LCRW, MQTT)"};
  app.add_option("--station-id", o.station_id, "ETSI StationID")->required();
  app.add_option("--station-type", o.station_type,
                 "CDD StationType (default: from the scenario, else 5 passengerCar)")
      ->check(CLI::Range(0, 255));
  app.add_option("--scenario", o.scenario, "scenario file (CAM policy, vehicle size, origin)");
  app.add_option("--radio", o.radio, "radio interface (hwsim OCB or the veth stand-in)")
      ->capture_default_str();
  app.add_option("--can", o.can_transport, "CAN transport")
      ->check(CLI::IsMember({"auto", "socketcan", "udp", "none"}))
      ->capture_default_str();
  app.add_option("--can-interface", o.can_interface, "SocketCAN interface")->capture_default_str();
  app.add_option("--can-udp-port", o.can_udp_port, "CAN-over-UDP (cannelloni) port")
      ->capture_default_str();
  app.add_option("--dbc", o.dbc, "CAN database")->check(CLI::ExistingFile)->capture_default_str();
  app.add_option("--gpsd", o.gpsd, "use an existing gpsd at HOST:PORT instead of starting one");
  app.add_option("--gpsd-port", o.gpsd_port, "client port of the gpsd we start")
      ->capture_default_str();
  app.add_option("--nmea-port", o.nmea_port, "UDP port our gpsd reads NMEA from")
      ->capture_default_str();
  app.add_option("--gpsd-wait", o.gpsd_wait_s, "seconds to wait for gpsd before giving up")
      ->capture_default_str();
  app.add_option("--cam-policy", o.cam_policy, "override the scenario's CAM policy")
      ->check(CLI::IsMember({"etsi", "fixed"}));
  app.add_option("--security", o.security,
                 "override the scenario's security: none, signed, signed-permissive")
      ->check(CLI::IsMember({"none", "signed", "signed-permissive"}));
  app.add_option("--pki-dir", o.pki_dir, "its-pki directory with root, AA and this station's AT");
  app.add_option("--security-time-window", o.security_time_windows,
                 "generation-time window of an ITS-AID, PSID=PAST_MS[:FUTURE_MS] (e.g. "
                 "37=10000:40), repeatable; over the scenario's security_time_windows "
                 "(default for every ITS-AID: 2000:40)")
      ->check(CLI::Validator(
          [](std::string& v) {
            const auto w = tb::its::security::parse_time_window(v);
            return w ? std::string() : w.error();
          },
          "PSID=PAST_MS[:FUTURE_MS]"));
  app.add_option("--cam-period-ms", o.cam_period_ms, "period of the fixed CAM policy")
      ->check(CLI::Range(10.0, 10000.0));
  app.add_option("--mqtt-host", o.mqtt_host, "MQTT broker (none: no MQTT)");
  app.add_option("--mqtt-port", o.mqtt_port, "MQTT broker port")->capture_default_str();
  app.add_option("--mqtt-user", o.mqtt_user, "MQTT user name");
  app.add_option("--mqtt-password", o.mqtt_password, "MQTT password");
  app.add_option("--mqtt-password-file", o.mqtt_password_file, "file holding the MQTT password")
      ->check(CLI::ExistingFile);
  app.add_option("--mqtt-prefix", o.mqtt_prefix, "topic prefix")->capture_default_str();
  // The contract's limit is one per source per 200 ms (its-station/apps/README.md); a large
  // run may want fewer, since each mirrored CAM costs the station a TCP write (issue 21).
  app.add_option("--mqtt-cam-interval-ms", o.mqtt_cam_interval_ms,
                 "least time between two received CAMs of one source mirrored to MQTT")
      ->check(CLI::Range(200, 60000))
      ->capture_default_str();
  app.add_option("--denm-repetition-ms", o.denm_repetition_ms, "T_Repetition of application DENMs")
      ->check(CLI::Range(1.0, 10000.0))
      ->capture_default_str();
  app.add_option("--denm-repetition-duration", o.denm_repetition_duration_s,
                 "T_RepetitionDuration of application DENMs, s (repetition also ends with the "
                 "event's validity or its cancellation)")
      ->check(CLI::Range(0.0, 86400.0))
      ->capture_default_str();
  app.add_flag("--no-keep-alive-forwarding", o.no_keep_alive_forwarding,
               "do not keep other stations' DENMs alive (EN 302 637-3 clause 8.2.2, optional)");
  app.add_flag("!--no-lcrw", o.lcrw, "do not run the LCRW application");
  app.add_flag("!--no-signal-app", o.signal_app,
               "do not run the signal application (MAPEM/SPATEM reception, RLVW, GLOSA)");
  app.add_option("--trace", o.trace, "write trace records (JSON lines) to FILE");
  app.add_option("--status-file", o.status_file,
                 "write the station's LDM view as JSON to FILE every 0.5 s");
  app.add_option("--duration", o.duration_s, "stop after this many seconds (0: run until signal)");
  app.add_option("--signals", o.signals,
                 "road-side unit: the signal feed's address, udp://HOST:PORT (default "
                 "udp://0.0.0.0:4720; ignored for a vehicle)");
  app.add_option("--log-level", o.log_level, "trace, debug, info, warn, error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::from_str(o.log_level));

  try {
    return run(o);
  } catch (const Fatal& f) {
    spdlog::error("{}", f.message);
    return f.code;
  } catch (const tb::scenario::ScenarioError& e) {
    spdlog::error("{}", e.what());
    return tb::scenario::kExitBadScenario;
  } catch (const std::exception& e) {
    spdlog::error("its-station: {}", e.what());
    return 1;
  }
}
