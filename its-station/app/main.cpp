// its-station: one ITS-G5 station — gpsd positioning, CAN vehicle data, GeoNetworking/BTP over
// the radio interface, CA and DEN services, LDM, LCRW and MQTT. Usage: README.md in
// its-station, "Facilities and the station program".

#include <net/if.h>

#include <array>
#include <chrono>
#include <csignal>
#include <fstream>
#include <memory>
#include <optional>
#include <set>
#include <string>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <nlohmann/json.hpp>

#include "common/can/socketcan_bus.hpp"
#include "common/can/udp_can_bus.hpp"
#include "common/clock/asio_runtime.hpp"
#include "common/clock/gnss_disciplined_runtime.hpp"
#include "common/clock/utc.hpp"
#include "common/geodesy/local_frame.hpp"
#include "common/map/scenario_map.hpp"
#include "common/mqtt/mosquitto_client.hpp"
#include "common/scenario/loader.hpp"
#include "common/trace/tracer.hpp"
#include "its-station/app/adapters.hpp"
#include "its-station/app/time_synced_link.hpp"
#include "its-station/apps/lcrw/lcrw_app.hpp"
#include "its-station/apps/mqtt/publisher.hpp"
#include "its-station/btp/dispatcher.hpp"
#include "its-station/facilities/ca_service.hpp"
#include "its-station/facilities/can_vehicle_data.hpp"
#include "its-station/facilities/den_service.hpp"
#include "its-station/facilities/gpsd_position_provider.hpp"
#include "its-station/facilities/gpsd_process.hpp"
#include "its-station/facilities/ldm.hpp"
#include "its-station/facilities/reference_position.hpp"
#include "its-station/geonet/router.hpp"
#include "its-station/link/packet_socket_link.hpp"
#include "its-station/security/pki_files.hpp"
#include "its-station/security/security_entity.hpp"

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
  std::string trace;
  std::string status_file;
  double duration_s = 0.0;
  std::string log_level = "info";
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

int run(const Options& o) {
  if (!o.trace.empty())
    tb::trace::configure(o.trace, "its-station");
  else
    tb::trace::configure_from_env("its-station");

  // Station identity and configuration, from the scenario where one is given.
  std::optional<tb::scenario::Scenario> scenario;
  const tb::scenario::Vehicle* vehicle = nullptr;
  if (!o.scenario.empty()) {
    scenario = tb::scenario::load_file(o.scenario);
    vehicle = scenario->find_station(o.station_id);
    if (!vehicle)
      throw Fatal{
          fmt::format("scenario {}: no vehicle with station id {}", o.scenario, o.station_id),
          tb::scenario::kExitBadScenario};
  }
  fac::CaConfig ca_cfg;
  ca_cfg.station_id = o.station_id;
  ca_cfg.station_type = static_cast<tb::its::messages::StationType>(
      o.station_type >= 0 ? o.station_type : (vehicle ? vehicle->station_type : 5));
  if (scenario)
    ca_cfg.policy = scenario->cam;
  if (vehicle) {
    ca_cfg.vehicle_length_m = vehicle->model.length_m;
    ca_cfg.vehicle_width_m = vehicle->model.width_m;
    // The scenario's role is the CDD VehicleRole, value for value.
    ca_cfg.vehicle_role = static_cast<tb::its::messages::VehicleRole>(vehicle->role);
    if (vehicle->dangerous_goods)
      ca_cfg.dangerous_goods =
          static_cast<tb::its::messages::DangerousGoodsBasic>(*vehicle->dangerous_goods);
  }
  if (o.cam_policy == "fixed") {
    ca_cfg.policy.kind = tb::scenario::CamPolicy::Kind::kFixed;
  } else if (o.cam_policy == "etsi") {
    ca_cfg.policy.kind = tb::scenario::CamPolicy::Kind::kEtsi;
  }
  if (o.cam_period_ms > 0.0)
    ca_cfg.policy.period_ms = o.cam_period_ms;

  asio::io_context io;
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
  auto can_bus = open_can(io, o);
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

  // Everything above the receiver works with the vehicle's orientation and the CAM reference
  // point (front centre), not the antenna's course and position (reference_position.hpp).
  fac::AntennaGeometry antenna;
  if (vehicle) {
    antenna.vehicle_length_m = vehicle->model.length_m;
    antenna.antenna_forward_m = vehicle->model.antenna.forward_m;
    antenna.antenna_left_m = vehicle->model.antenna.left_m;
  }
  fac::ReferencePositionProvider position(gnss, vehicle_data.get(), antenna);

  // The station's ITS clock (docs/time.md): every time a standard dates or times — GN TST and
  // location-table ageing, CAM timing, DENM times, DEN repetition and validity, LDM expiry,
  // security generation time and certificate validity, LCRW — runs on GNSS time, the world's
  // clock (the scenario's start time + sim time), as on a real OBU. The host's clock only
  // serves sockets, gpsd, CAN, MQTT and trace records. It is told of a fix before anything else
  // hears of it.
  tb::clock::GnssDisciplinedRuntime its_clock(runtime);
  position.on_fix([&](const fac::PositionFix& fix) {
    const bool first = !its_clock.synchronised();
    const unsigned resyncs = its_clock.resyncs();
    its_clock.on_fix(fix.time);
    if (first)
      spdlog::info(
          "ITS clock: on GNSS time from the first fix ({}, {:+.1f} s from the host's "
          "clock)",
          tb::clock::format_utc(fix.time),
          std::chrono::duration<double>(fix.time - runtime.wall_now()).count());
    else if (its_clock.resyncs() != resyncs)
      spdlog::warn("ITS clock: GNSS time jumped (a restarted simulation?): now {}",
                   tb::clock::format_utc(fix.time));
  });

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

  tb::its::station::GnPositionAdapter gn_position(position);
  tb::its::geonet::RouterConfig gn_cfg;
  gn_cfg.station_type = static_cast<tb::its::geonet::StationType>(ca_cfg.station_type);
  tb::its::station::TimeSyncedLink synced_link(**link, its_clock);
  tb::its::geonet::Router router(its_clock, synced_link, gn_position, gn_cfg);
  std::unique_ptr<tb::its::security::SecurityEntity> security = make_security(o, scenario);
  router.set_security(security.get());
  if (security)
    security->set_trace_station(o.station_id);
  if (security && !security->can_sign(tb::its::security::kPsidGnMgmt))
    spdlog::warn(
        "security: the AT of {} has no GN-MGMT permission (psid 141, an older "
        "its-pki): beacons go unsigned; make the PKI again to sign them",
        o.pki_dir);
  tb::its::btp::Dispatcher btp(router);
  tb::its::station::BtpMessageSender sender(btp);

  // Facilities.
  fac::Ldm ldm(its_clock);
  fac::CaService ca(its_clock, position, vehicle_data.get(), sender, ldm, ca_cfg);
  fac::DenConfig den_cfg;
  den_cfg.station_id = o.station_id;
  den_cfg.station_type = ca_cfg.station_type;
  den_cfg.keep_alive_forwarding = !o.no_keep_alive_forwarding;
  tb::its::station::GnAreaLocator den_locator(position);
  fac::DenService den(its_clock, sender, ldm, den_cfg, &den_locator);
  // Received CAMs are dated on the ITS clock from their kernel receive stamp, so that
  // generationDeltaTime resolves to the right instant and neighbours' states compare with the
  // own ones.
  btp.register_port(fac::kBtpPortCam, [&](const tb::its::btp::Indication& ind,
                                          std::span<const std::uint8_t> payload) {
    // A verified CAM is checked against its signer's SSP (a permissive station's unverified
    // ones have nothing trustworthy to check against).
    std::optional<std::span<const std::uint8_t>> ssp;
    if (ind.gn && ind.gn->security_report == tb::its::security::VerifyResult::kOk)
      ssp = ind.gn->permissions;
    ca.receive(payload, ind.gn ? its_clock.to_its(ind.gn->rx_time) : its_clock.wall_now(), ssp);
  });
  btp.register_port(fac::kBtpPortDenm, [&](const tb::its::btp::Indication& ind,
                                           std::span<const std::uint8_t> payload) {
    den.receive(payload, tb::its::station::den_reception(ind));
  });

  // MQTT.
  std::unique_ptr<tb::mqtt::MosquittoClient> mqtt;
  std::unique_ptr<apps::mqtt::StationPublisher> publisher;
  if (!o.mqtt_host.empty()) {
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
    mqtt = std::make_unique<tb::mqtt::MosquittoClient>(runtime, mc);
    publisher = std::make_unique<apps::mqtt::StationPublisher>(
        runtime, *mqtt,
        apps::mqtt::PublisherConfig{o.mqtt_prefix, o.station_id,
                                    std::chrono::milliseconds{o.mqtt_cam_interval_ms}});
    publisher->set_tracer(&tb::trace::global());
    mqtt->start();
    spdlog::info("MQTT: publishing to {}:{} under {}", o.mqtt_host, o.mqtt_port, topics.root());
    ldm.on_neighbour([&](const fac::Neighbour& n) {
      apps::mqtt::ReceivedCam c;
      c.station_id = n.station_id;
      c.station_type = n.station_type;
      c.generation_delta_time = n.latest().generation_delta_time;
      c.kinematics = tb::its::station::neighbour_kinematics(n);
      c.received_at = n.latest().received_wall;
      publisher->publish_cam(c);
    });
    ldm.on_event([&](const fac::Event& e, fac::DenmOutcome) {
      publisher->publish_denm_received(tb::its::station::denm_view(e.denm));
    });
    den.on_sent([&](const tb::its::messages::Denm& d) {
      publisher->publish_denm_sent(tb::its::station::denm_view(d));
    });
  }

  // LCRW: evaluated at every own fix against the LDM's neighbours, and at every CAM received
  // against its sender (a neighbour's state change must not wait up to a fix period, 100 ms,
  // for the next own fix before it can raise a warning) and the neighbours with an active
  // warning; both states are extrapolated to the evaluation instant.
  // And once more at the predicted onset (Lcrw::time_to_onset_s) when a TTC will cross the
  // warning threshold before the next fix: otherwise the warning came up to a fix period late
  // (the frontal case at 50 km/h warned anywhere between TTC 3.0 and 2.9 s).
  // LCRW computes in an East-North-Up frame; with a scenario it is anchored where the map's
  // (0, 0, 0) lies (the map's geoReference, or the scenario's origin: common/map's ScenarioMap).
  std::optional<tb::geodesy::LocalFrame> frame;
  if (scenario)
    frame.emplace(*tb::map::ScenarioMap(*scenario).origin().origin);
  tb::its::station::DenPortAdapter den_port(
      den,
      std::chrono::duration_cast<tb::clock::Duration>(
          std::chrono::duration<double, std::milli>(o.denm_repetition_ms)),
      std::chrono::duration_cast<tb::clock::Duration>(
          std::chrono::duration<double>(o.denm_repetition_duration_s)));
  std::unique_ptr<apps::LcrwDenmTrigger> lcrw_denm;
  std::unique_ptr<apps::LcrwApplication> lcrw;
  std::set<std::uint32_t> published_about;  // neighbours of the current evaluation's warnings
  asio::steady_timer lcrw_onset(io);
  // A fix period: an onset further away is met by the next fix's evaluation.
  const double fix_period_s = 1.0 / (scenario ? scenario->rates.gnss_hz : 10.0);
  std::function<void()> evaluate_at_onset;
  const auto own_state = [&](const fac::PositionFix& fix) {
    const fac::VehicleData* vd =
        vehicle_data && vehicle_data->current() ? &*vehicle_data->current() : nullptr;
    return tb::its::station::own_kinematics(fix, vd, ca_cfg.vehicle_length_m,
                                            ca_cfg.vehicle_width_m);
  };
  // `its.lcrw` records (docs/tracing.md) are written here rather than by the application:
  // after an own fix one per neighbour assessed, after a CAM only the decision about its
  // sender — one record per CAM, not one per neighbour per CAM (with 50 stations that would be
  // a million records a second). They are stamped with the start of the evaluation: a warning
  // is published from inside it, so the report's decision → publication stage (mqtt) spans the
  // evaluation and the hand-off to the MQTT client.
  const auto evaluate_lcrw = [&](const fac::PositionFix& fix, const apps::mqtt::Kinematics& own,
                                 std::optional<std::uint32_t> cam_from) {
    if (!o.lcrw)
      return;
    if (!frame) {
      // Without a scenario the first fix anchors the local frame LCRW computes in.
      frame.emplace(tb::geodesy::Geodetic{fix.latitude_deg, fix.longitude_deg, 0.0});
    }
    if (!lcrw) {
      lcrw_denm = std::make_unique<apps::LcrwDenmTrigger>(den_port, *frame);
      lcrw = std::make_unique<apps::LcrwApplication>(
          its_clock, apps::LcrwConfig{},
          [&](const apps::LcrwWarning& w) {
            published_about.insert(w.other_station_id);
            spdlog::info("LCRW: {} station {} ({}), TTC {:.2f} s",
                         w.event == apps::WarningEvent::kCleared ? "cleared" : "warning",
                         w.other_station_id, apps::to_string(w.collision_case), w.ttc_s);
            if (publisher)
              publisher->publish_warning(w);
          },
          lcrw_denm.get(), nullptr);
    }
    const std::int64_t decided_ns = tb::trace::Tracer::now_ns();
    published_about.clear();
    std::vector<apps::VehicleKinematics> others;
    const auto assess = [&](std::uint32_t id, const fac::Neighbour& n) {
      others.push_back(tb::its::station::lcrw_kinematics(
          id, tb::its::station::neighbour_kinematics(n), n.latest().generation_time, *frame));
    };
    const auto& neighbours = ldm.neighbours();
    if (cam_from) {
      // After a CAM only its sender's state is new: assess the sender, and every neighbour with
      // an active warning (so that time can still update or end it, as before); the others
      // wait for the next own fix (100 ms at 10 Hz). Assessing every neighbour at every CAM
      // made LCRW quadratic in the neighbours per station: with 50 stations each one took 490
      // CAMs a second × 49 neighbours, most of the testbed's CPU (issue 21, docs/latency.md).
      if (const auto it = neighbours.find(*cam_from); it != neighbours.end())
        assess(it->first, it->second);
      for (const auto& [id, w] : lcrw->lcrw().active())
        if (const auto it = neighbours.find(id); id != *cam_from && it != neighbours.end())
          assess(it->first, it->second);
    } else {
      for (const auto& [id, n] : neighbours)
        assess(id, n);
    }
    lcrw->update(tb::its::station::lcrw_kinematics(o.station_id, own, fix.time, *frame), others);
    if (const auto onset = lcrw->lcrw().time_to_onset_s(); onset && *onset < fix_period_s) {
      // At least 1 ms: a TTC that does not fall as predicted (the other braking) is met again
      // by the next fix, never by a busy loop.
      lcrw_onset.expires_after(
          std::chrono::microseconds(std::max<std::int64_t>(1000, std::llround(*onset * 1e6))));
      lcrw_onset.async_wait([&](const boost::system::error_code& ec) {
        if (!ec)
          evaluate_at_onset();
      });
    } else {
      lcrw_onset.cancel();
    }
    auto& tracer = tb::trace::global();
    if (!tracer.enabled())
      return;
    const auto& assessed = lcrw->lcrw().last_assessments();
    for (const auto& n : others) {
      // After a CAM, its sender's decision, and any other that published (a warning cleared
      // on the passing of time), so that every publication has its decision record.
      if (cam_from && n.station_id != *cam_from && !published_about.contains(n.station_id))
        continue;
      const auto a = assessed.find(n.station_id);
      if (a == assessed.end())
        continue;  // too old to assess
      tracer.record_at(decided_ns, "its.lcrw",
                       {{"station", o.station_id},
                        {"from", n.station_id},
                        {"gdt", apps::generation_delta_time(n.time)},
                        {"warn", lcrw->lcrw().active().contains(n.station_id)},
                        {"ttc", a->second.ttc_s}});
    }
  };
  evaluate_at_onset = [&] {
    if (const auto& fix = position.current())
      evaluate_lcrw(*fix, own_state(*fix), std::nullopt);
  };
  position.on_fix([&](const fac::PositionFix& fix) {
    const auto own = own_state(fix);
    if (publisher) {
      apps::mqtt::StationState s;
      s.station_id = o.station_id;
      s.station_type = ca_cfg.station_type;
      s.kinematics = own;
      s.fix = fix.altitude_m ? apps::mqtt::GnssFix::k3D : apps::mqtt::GnssFix::k2D;
      s.time = fix.time;
      publisher->publish_state(s);
    }
    evaluate_lcrw(fix, own, std::nullopt);
  });
  ldm.on_neighbour([&](const fac::Neighbour& n) {
    if (const auto& fix = position.current())
      evaluate_lcrw(*fix, own_state(*fix), n.station_id);
  });

  // Status file: the LDM as the station sees it, for operators and tests.
  asio::steady_timer status_timer(io);
  std::array<bool, static_cast<std::size_t>(tb::its::security::VerifyResult::kCount)>
      refusals_said{};
  auto write_status = [&] {
    if (o.status_file.empty())
      return;
    nlohmann::json j;
    j["station_id"] = o.station_id;
    j["fix"] = position.current().has_value();
    if (position.current()) {
      j["latitude_deg"] = position.current()->latitude_deg;
      j["longitude_deg"] = position.current()->longitude_deg;
    }
    j["frames_before_first_fix"] = synced_link.dropped_before_sync();
    j["cams_sent"] = ca.counters().sent;
    j["cams_received"] = ca.counters().received;
    j["denms_sent"] = den.counters().sent;
    j["denms_received"] = den.counters().received;
    j["denms_forwarded"] = den.counters().forwarded;
    j["neighbours"] = nlohmann::json::array();
    for (const auto& [id, n] : ldm.neighbours()) {
      const auto& s = n.latest();
      nlohmann::json e{{"station_id", id},
                       {"latitude_deg", s.latitude_deg},
                       {"longitude_deg", s.longitude_deg},
                       {"generation_delta_time", s.generation_delta_time}};
      if (s.speed_mps)
        e["speed_mps"] = *s.speed_mps;
      if (s.heading_deg)
        e["heading_deg"] = *s.heading_deg;
      j["neighbours"].push_back(e);
    }
    j["events"] = ldm.active_events().size();
    if (security) {
      // Each verification outcome by name (TS 103 097 drop reasons), and what a permissive
      // station passed up although it failed. A refusal the station had not seen before is
      // also said once in the log (a station of another PKI: untrusted_root).
      nlohmann::json v;
      const auto& counts = security->verifier().counts();
      for (std::size_t i = 0; i < counts.size(); ++i) {
        if (counts[i] == 0)
          continue;
        const auto r = static_cast<tb::its::security::VerifyResult>(i);
        v[std::string(tb::its::security::to_string(r))] = counts[i];
        if (r != tb::its::security::VerifyResult::kOk &&
            r != tb::its::security::VerifyResult::kUnknownSigner && !refusals_said[i]) {
          refusals_said[i] = true;
          spdlog::warn("security: dropping received packets: {}", tb::its::security::to_string(r));
        }
      }
      j["security"] = {
          {"mode", tb::its::security::to_string(security->mode())},
          {"verify", v},
          {"passed_unverified", security->passed_unverified()},
          {"held", security->held()},
          // (signer, generationTime) pairs kept for replay detection (verify.replay counts hits)
          {"replay_entries", security->verifier().replay_entries()},
          {"unsecured_dropped", router.stats().dropped(tb::its::geonet::DropReason::kUnsecured)},
          {"cam_ssp_refused", ca.counters().not_permitted},
          {"denm_ssp_refused", den.counters().not_permitted},
          {"its_aid_mismatch", btp.stats().dropped(tb::its::btp::DropReason::kItsAidMismatch)},
          {"beacons_unsigned", router.stats().beacons_unsigned}};
    }
    const std::string tmp = o.status_file + ".tmp";
    std::ofstream(tmp) << j.dump() << "\n";
    std::rename(tmp.c_str(), o.status_file.c_str());
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
    ca.stop();
    gnss.stop();
    signals.cancel();
    status_timer.cancel();
    lcrw_onset.cancel();
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
  ca.start();
  status_tick();
  spdlog::info("station {} (type {}) running, CAM policy {}", o.station_id,
               unsigned{ca_cfg.station_type},
               ca_cfg.policy.kind == tb::scenario::CamPolicy::Kind::kFixed
                   ? fmt::format("fixed {} ms", ca_cfg.policy.period_ms)
                   : std::string("ETSI EN 302 637-2"));
  io.run();

  if (mqtt)
    mqtt->stop();
  tb::trace::global().flush();
  spdlog::info(
      "CAMs sent {}, received {}; DENMs sent {}, received {}; router drops: {} parse; {} "
      "frame(s) heard before the first fix, not taken in (no world time yet)",
      ca.counters().sent, ca.counters().received, den.counters().sent, den.counters().received,
      router.stats().dropped(tb::its::geonet::DropReason::kParseError),
      synced_link.dropped_before_sync());
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
  app.add_option("--trace", o.trace, "write trace records (JSON lines) to FILE");
  app.add_option("--status-file", o.status_file,
                 "write the station's LDM view as JSON to FILE every 0.5 s");
  app.add_option("--duration", o.duration_s, "stop after this many seconds (0: run until signal)");
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
