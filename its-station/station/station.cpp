#include "its-station/station/station.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <spdlog/spdlog.h>

#include "common/clock/utc.hpp"
#include "common/trace/tracer.hpp"
#include "its-station/apps/signal/dsrc_convert.hpp"
#include "its-station/facilities/transport.hpp"

namespace tb::its::station {

namespace fac = facilities;

ItsClockDiscipline::ItsClockDiscipline(fac::PositionProvider& position,
                                       clock::GnssDisciplinedRuntime& its,
                                       const clock::Clock& host) {
  // The station's ITS clock (docs/time.md): every time a standard dates or times — GN TST and
  // location-table ageing, CAM timing, DENM times, DEN repetition and validity, LDM expiry,
  // security generation time and certificate validity, LCRW — runs on GNSS time, the world's
  // clock (the scenario's start time + sim time), as on a real OBU. The host's clock only
  // serves sockets, gpsd, CAN, MQTT and trace records. It is told of a fix before anything else
  // hears of it.
  position.on_fix([&its, &host](const fac::PositionFix& fix) {
    const bool first = !its.synchronised();
    const unsigned resyncs = its.resyncs();
    its.on_fix(fix.time);
    if (first)
      spdlog::info(
          "ITS clock: on GNSS time from the first fix ({}, {:+.1f} s from the host's "
          "clock)",
          clock::format_utc(fix.time),
          std::chrono::duration<double>(fix.time - host.wall_now()).count());
    else if (its.resyncs() != resyncs)
      spdlog::warn("ITS clock: GNSS time jumped (a restarted simulation?): now {}",
                   clock::format_utc(fix.time));
  });
}

namespace {

geonet::RouterConfig router_config(const StationConfig& c) {
  geonet::RouterConfig r;
  r.station_type = static_cast<geonet::StationType>(c.ca.station_type);
  // EN 302 636-4-1 9.7.4 / Annex H itsGnIsMobile: a road-side unit does not move (issue 34).
  r.is_mobile = c.ca.station_type != messages::station_type::kRoadSideUnit;
  return r;
}

fac::DenConfig den_config(const StationConfig& c) {
  fac::DenConfig d;
  d.station_id = c.station_id;
  d.station_type = c.ca.station_type;
  d.keep_alive_forwarding = c.keep_alive_forwarding;
  return d;
}

}  // namespace

Station::Station(const StationPorts& ports, StationConfig config)
    : runtime_(ports.runtime),
      its_clock_(ports.its_clock),
      vehicle_data_(ports.vehicle_data),
      security_(ports.security),
      config_(std::move(config)),
      position_(ports.gnss, ports.vehicle_data, config_.antenna),
      clock_discipline_(position_, its_clock_, runtime_),
      gn_position_(position_),
      synced_link_(ports.link, its_clock_),
      router_(its_clock_, synced_link_, gn_position_, router_config(config_)),
      btp_(router_),
      sender_(btp_),
      ldm_(its_clock_),
      ca_(its_clock_, position_, vehicle_data_, sender_, ldm_, config_.ca),
      den_locator_(position_),
      den_(its_clock_, sender_, ldm_, den_config(config_), &den_locator_),
      den_port_(den_, config_.denm_repetition_interval, config_.denm_repetition_duration) {
  router_.set_security(security_);
  if (security_) {
    security_->set_trace_station(config_.station_id);
    security_->set_trace_cam_receptions(config_.ca.trace_receptions);
    // LCRW is the application that consumes received CAMs (their positions and dynamics).
    security_->set_verify_policy(config_.verify_policy);
    security_->set_cam_consumer(config_.lcrw);
  }

  btp_.register_port(fac::kBtpPortCam,
                     [this](const btp::Indication& ind, std::span<const std::uint8_t> payload) {
                       receive_cam(ind, payload);
                     });
  btp_.register_port(fac::kBtpPortDenm,
                     [this](const btp::Indication& ind, std::span<const std::uint8_t> payload) {
                       den_.receive(payload, den_reception(ind));
                     });

  if (ports.mqtt) {
    publisher_ =
        std::make_unique<apps::mqtt::StationPublisher>(runtime_, *ports.mqtt, config_.publisher);
    publisher_->set_tracer(&trace::global());
    mirror_to_mqtt();
  }

  if (config_.signals)
    start_signal_app();

  if (config_.lcrw_origin)
    frame_.emplace(*config_.lcrw_origin);
  position_.on_fix([this](const fac::PositionFix& fix) { on_fix(fix); });
  // Only a station that runs LCRW listens: the own state it computes at every CAM received was
  // a sixth of a pooled station's reception cost with LCRW off (station-host/README.md).
  if (config_.lcrw)
    ldm_.on_neighbour([this](const fac::Neighbour& n) {
      if (const auto& fix = position_.current())
        evaluate_lcrw(*fix, own_state(*fix), n.station_id);
    });
}

Station::~Station() {
  cancel_onset();
}

void Station::start() {
  stopped_ = false;
  ca_.start();
  spdlog::info("station {} (type {}) running, CAM policy {}", config_.station_id,
               unsigned{config_.ca.station_type},
               config_.ca.policy.kind == scenario::CamPolicy::Kind::kFixed
                   ? fmt::format("fixed {} ms", config_.ca.policy.period_ms)
                   : std::string("ETSI EN 302 637-2"));
}

void Station::stop() {
  stopped_ = true;
  ca_.stop();
  cancel_onset();
}

// Received CAMs are dated on the ITS clock from their kernel receive stamp, so that
// generationDeltaTime resolves to the right instant and neighbours' states compare with the
// own ones.
void Station::receive_cam(const btp::Indication& ind, std::span<const std::uint8_t> payload) {
  // A verified CAM is checked against its signer's SSP (a permissive station's unverified
  // ones have nothing trustworthy to check against).
  std::optional<std::span<const std::uint8_t>> ssp;
  if (ind.gn && ind.gn->security_report == security::VerifyResult::kOk)
    ssp = ind.gn->permissions;
  ca_.receive(payload, ind.gn ? its_clock_.to_its(ind.gn->rx_time) : its_clock_.wall_now(), ssp);
}

void Station::mirror_to_mqtt() {
  ldm_.on_neighbour([this](const fac::Neighbour& n) {
    apps::mqtt::ReceivedCam c;
    c.station_id = n.station_id;
    c.station_type = n.station_type;
    c.generation_delta_time = n.latest().generation_delta_time;
    c.kinematics = neighbour_kinematics(n);
    c.received_at = n.latest().received_wall;
    publisher_->publish_cam(c);
  });
  ldm_.on_event([this](const fac::Event& e, fac::DenmOutcome) {
    publisher_->publish_denm_received(denm_view(e.denm));
  });
  den_.on_sent([this](const messages::Denm& d) { publisher_->publish_denm_sent(denm_view(d)); });
}

apps::mqtt::Kinematics Station::own_state(const fac::PositionFix& fix) const {
  const fac::VehicleData* vd =
      vehicle_data_ && vehicle_data_->current() ? &*vehicle_data_->current() : nullptr;
  return own_kinematics(fix, vd, config_.ca.vehicle_length_m, config_.ca.vehicle_width_m);
}

void Station::on_fix(const fac::PositionFix& fix) {
  const auto own = own_state(fix);
  if (publisher_) {
    apps::mqtt::StationState s;
    s.station_id = config_.station_id;
    s.station_type = config_.ca.station_type;
    s.kinematics = own;
    s.fix = fix.altitude_m ? apps::mqtt::GnssFix::k3D : apps::mqtt::GnssFix::k2D;
    s.time = fix.time;
    publisher_->publish_state(s);
  }
  evaluate_lcrw(fix, own, std::nullopt);
  update_signal_app(fix, own);
}

// The signal application (issue 34): MAPEM (RLT service, port 2003) and SPATEM (TLM service,
// port 2004) into the LDM's intersection store, from there converted into the application's
// model; the application runs at every own fix and at once when a SPATEM changes the own
// group's state. Without it the station does not listen on the two ports, so a pooled station
// spends nothing on the RSUs' messages (and does not verify them: set_signal_consumer).
void Station::start_signal_app() {
  if (security_)
    security_->set_signal_consumer(true);
  intersection_rx_ = std::make_unique<fac::IntersectionReceiver>(ldm_.intersections());
  signal_app_ = std::make_unique<apps::signal::SignalApplication>(
      its_clock_, apps::signal::SignalAppConfig{},
      [this](const apps::signal::SignalStatus& s) {
        if (publisher_)
          publisher_->publish_signal(s);
      },
      [this](const apps::signal::RlvwWarning& w) { on_rlvw(w); }, &trace::global());
  intersection_rx_->on_map(
      [this](const fac::IntersectionEntry& e, fac::MapOutcome) { on_intersection_map(e); });
  intersection_rx_->on_spat([this](const fac::IntersectionEntry& e) { on_intersection_spat(e); });
  btp_.register_port(fac::kBtpPortMapem,
                     [this](const btp::Indication&, std::span<const std::uint8_t> payload) {
                       intersection_rx_->receive_mapem(payload);
                     });
  btp_.register_port(fac::kBtpPortSpatem,
                     [this](const btp::Indication&, std::span<const std::uint8_t> payload) {
                       intersection_rx_->receive_spatem(payload);
                     });
}

void Station::on_intersection_map(const fac::IntersectionEntry& e) {
  // Converted at every MAPEM (about 1 Hz): the same revision refreshes the application's copy,
  // which forgets an intersection not heard for 30 s like the LDM.
  auto topology = apps::signal::topology_from_geometry(*e.map, its_clock_.wall_now());
  std::optional<std::string> refused;
  if (!topology)
    refused = topology.error().message;
  else if (auto r = signal_app_->on_map(std::move(*topology)); !r)
    refused = r.error().message;
  if (refused && refused_maps_said_.insert({e.id, e.map->revision}).second)
    spdlog::warn("MAPEM: intersection {} revision {} not used: {}", e.id, unsigned{e.map->revision},
                 *refused);
}

void Station::on_intersection_spat(const fac::IntersectionEntry& e) {
  const auto now = its_clock_.wall_now();
  const auto phases = apps::signal::phases_from_state(*e.spat, now, now);
  signal_app_->on_spat(e.id, phases);
}

void Station::update_signal_app(const fac::PositionFix& fix, const apps::mqtt::Kinematics& own) {
  if (!signal_app_)
    return;
  // The application measures from the vehicle's front (the CAM reference point, which the
  // fix already is) along its orientation; a car driving backward has no ingress lane ahead.
  const auto heading = fix.heading_deg ? fix.heading_deg : fix.course_deg;
  if (!heading || !fix.speed_mps || own.reversing)
    return;
  apps::signal::OwnKinematics k;
  k.station_id = config_.station_id;
  k.latitude_deg = fix.latitude_deg;
  k.longitude_deg = fix.longitude_deg;
  k.heading_deg = *heading;
  k.speed_mps = *fix.speed_mps;
  k.longitudinal_accel_mps2 = own.longitudinal_accel_mps2;
  k.time = fix.time;
  signal_app_->update(k);
}

void Station::on_rlvw(const apps::signal::RlvwWarning& w) {
  if (w.event == apps::signal::RlvwEvent::kRaised) {
    ++rlvw_raised_;
    spdlog::info(
        "RLVW: intersection {} lane {} group {}: red light ahead, {:.1f} m to the stop "
        "line at {:.1f} m/s (stopping needs {:.1f} m)",
        w.intersection_id, unsigned{w.lane_id}, unsigned{w.signal_group}, w.distance_to_stop_line_m,
        w.speed_mps, w.stopping_distance_m);
  } else if (w.event == apps::signal::RlvwEvent::kCleared) {
    spdlog::info("RLVW: cleared ({})", apps::signal::to_string(w.clear_reason));
  }
  // One record per event (docs/tracing.md): what an e2e test grades against the car's state
  // trace (the stop line distance at the raise), and the start of the RLVW's way to the HMI.
  trace::global().record(
      "its.rlvw",
      {{"station", config_.station_id},
       {"intersection", unsigned{w.intersection_id}},
       {"lane", unsigned{w.lane_id}},
       {"group", unsigned{w.signal_group}},
       {"event", apps::signal::to_string(w.event)},
       {"reason", w.event == apps::signal::RlvwEvent::kCleared
                      ? apps::signal::to_string(w.clear_reason)
                      : std::string_view{}},
       {"dist", w.distance_to_stop_line_m},
       {"speed", w.speed_mps},
       {"time_to_red", w.time_to_red_s.value_or(-1.0)},
       {"own_ms", static_cast<std::int64_t>(std::chrono::duration_cast<std::chrono::milliseconds>(
                                                w.updated_at.time_since_epoch())
                                                .count())}});
  if (publisher_)
    publisher_->publish_rlvw(w);
}

nlohmann::json Station::signals_status() const {
  const auto& c = intersection_rx_->counters();
  nlohmann::json j{{"intersections", signal_app_->intersections()},
                   {"mapem_received", c.mapem_received},
                   {"spatem_received", c.spatem_received},
                   {"mapem_decode_errors", c.mapem_decode_errors},
                   {"spatem_decode_errors", c.spatem_decode_errors},
                   {"lane", nullptr},
                   {"rlvw", rlvw_raised_},
                   {"rlvw_active", signal_app_->rlvw().active().has_value()}};
  if (const auto& s = signal_app_->last_status(); s && s->on_lane)
    j["lane"] = {{"intersection", s->intersection_id},
                 {"lane", s->lane_id},
                 {"signal_group", s->signal_group},
                 {"light", apps::signal::light_name(s->state)},
                 {"distance_m", s->distance_to_stop_line_m}};
  return j;
}

// LCRW: evaluated at every own fix against the LDM's neighbours, and at every CAM received
// against its sender (a neighbour's state change must not wait up to a fix period, 100 ms, for
// the next own fix before it can raise a warning) and the neighbours with an active warning;
// both states are extrapolated to the evaluation instant.
// And once more at the predicted onset (Lcrw::time_to_onset_s) when a TTC will cross the
// warning threshold before the next fix: otherwise the warning came up to a fix period late
// (the frontal case at 50 km/h warned anywhere between TTC 3.0 and 2.9 s).
//
// `its.lcrw` records (docs/tracing.md) are written here rather than by the application: after
// an own fix one per neighbour assessed, after a CAM only the decision about its sender — one
// record per CAM, not one per neighbour per CAM (with 50 stations that would be a million
// records a second). They are stamped with the start of the evaluation: a warning is published
// from inside it, so the report's decision → publication stage (mqtt) spans the evaluation and
// the hand-off to the MQTT client.
void Station::evaluate_lcrw(const fac::PositionFix& fix, const apps::mqtt::Kinematics& own,
                            std::optional<std::uint32_t> cam_from) {
  if (!config_.lcrw)
    return;
  if (!frame_) {
    // Without a scenario the first fix anchors the local frame LCRW computes in.
    frame_.emplace(geodesy::Geodetic{fix.latitude_deg, fix.longitude_deg, 0.0});
  }
  if (!lcrw_) {
    lcrw_denm_ = std::make_unique<apps::LcrwDenmTrigger>(den_port_, *frame_);
    lcrw_ = std::make_unique<apps::LcrwApplication>(
        its_clock_, apps::LcrwConfig{}, [this](const apps::LcrwWarning& w) { on_lcrw_warning(w); },
        lcrw_denm_.get(), nullptr);
  }
  const std::int64_t decided_ns = trace::Tracer::now_ns();
  published_about_.clear();
  auto& others = lcrw_others_;
  others.clear();
  const auto assess = [&](std::uint32_t id, const fac::Neighbour& n) {
    others.push_back(
        lcrw_kinematics(id, neighbour_kinematics(n), n.latest().generation_time, *frame_));
  };
  const auto& neighbours = ldm_.neighbours();
  if (cam_from) {
    // After a CAM only its sender's state is new: assess the sender, and every neighbour with
    // an active warning (so that time can still update or end it, as before); the others wait
    // for the next own fix (100 ms at 10 Hz). Assessing every neighbour at every CAM made LCRW
    // quadratic in the neighbours per station: with 50 stations each one took 490 CAMs a
    // second × 49 neighbours, most of the testbed's CPU (issue 21, docs/latency.md).
    if (const auto it = neighbours.find(*cam_from); it != neighbours.end())
      assess(it->first, it->second);
    for (const auto& [id, w] : lcrw_->lcrw().active())
      if (const auto it = neighbours.find(id); id != *cam_from && it != neighbours.end())
        assess(it->first, it->second);
  } else {
    for (const auto& [id, n] : neighbours)
      assess(id, n);
  }
  lcrw_->update(lcrw_kinematics(config_.station_id, own, fix.time, *frame_), others);
  schedule_onset(lcrw_->lcrw().time_to_onset_s());
  auto& tracer = trace::global();
  if (!tracer.enabled())
    return;
  const auto& assessed = lcrw_->lcrw().last_assessments();
  for (const auto& n : others) {
    // After a CAM, its sender's decision, and any other that published (a warning cleared on
    // the passing of time), so that every publication has its decision record.
    if (cam_from && n.station_id != *cam_from && !published_about_.contains(n.station_id))
      continue;
    const auto a = assessed.find(n.station_id);
    if (a == assessed.end())
      continue;  // too old to assess
    tracer.record_at(decided_ns, "its.lcrw",
                     {{"station", config_.station_id},
                      {"from", n.station_id},
                      {"gdt", apps::generation_delta_time(n.time)},
                      {"warn", lcrw_->lcrw().active().contains(n.station_id)},
                      {"ttc", a->second.ttc_s}});
  }
}

void Station::on_lcrw_warning(const apps::LcrwWarning& w) {
  published_about_.insert(w.other_station_id);
  spdlog::info("LCRW: {} station {} ({}), TTC {:.2f} s",
               w.event == apps::WarningEvent::kCleared ? "cleared" : "warning", w.other_station_id,
               apps::to_string(w.collision_case), w.ttc_s);
  if (publisher_)
    publisher_->publish_warning(w);
}

void Station::schedule_onset(std::optional<double> onset_s) {
  cancel_onset();
  if (stopped_ || !onset_s || *onset_s >= config_.fix_period_s)
    return;
  // At least 1 ms: a TTC that does not fall as predicted (the other braking) is met again by the
  // next fix, never by a busy loop. On the host's clock, as the fix period it is measured
  // against.
  const auto delay =
      std::chrono::microseconds(std::max<std::int64_t>(1000, std::llround(*onset_s * 1e6)));
  onset_timer_ = runtime_.schedule_in(delay, [this] {
    onset_timer_.reset();
    if (const auto& fix = position_.current())
      evaluate_lcrw(*fix, own_state(*fix), std::nullopt);
  });
}

void Station::cancel_onset() {
  if (onset_timer_) {
    runtime_.cancel(*onset_timer_);
    onset_timer_.reset();
  }
}

nlohmann::json Station::status() {
  nlohmann::json j;
  j["station_id"] = config_.station_id;
  j["fix"] = position_.current().has_value();
  if (position_.current()) {
    j["latitude_deg"] = position_.current()->latitude_deg;
    j["longitude_deg"] = position_.current()->longitude_deg;
  }
  j["frames_before_first_fix"] = synced_link_.dropped_before_sync();
  j["cams_sent"] = ca_.counters().sent;
  j["cams_received"] = ca_.counters().received;
  j["denms_sent"] = den_.counters().sent;
  j["denms_received"] = den_.counters().received;
  j["denms_forwarded"] = den_.counters().forwarded;
  auto& neighbours = j["neighbours"] = nlohmann::json::array();
  neighbours.get_ref<nlohmann::json::array_t&>().reserve(ldm_.neighbours().size());
  for (const auto& [id, n] : ldm_.neighbours()) {
    const auto& s = n.latest();
    nlohmann::json e{{"station_id", id},
                     {"latitude_deg", s.latitude_deg},
                     {"longitude_deg", s.longitude_deg},
                     {"generation_delta_time", s.generation_delta_time}};
    if (s.speed_mps)
      e["speed_mps"] = *s.speed_mps;
    if (s.heading_deg)
      e["heading_deg"] = *s.heading_deg;
    neighbours.push_back(std::move(e));
  }
  j["events"] = ldm_.active_events().size();
  if (signal_app_)
    j["signals"] = signals_status();
  if (security_) {
    // Each verification outcome by name (TS 103 097 drop reasons), and what a permissive
    // station passed up although it failed. A refusal the station had not seen before is also
    // said once in the log (a station of another PKI: untrusted_root).
    nlohmann::json v;
    const auto& counts = security_->verifier().counts();
    for (std::size_t i = 0; i < counts.size(); ++i) {
      if (counts[i] == 0)
        continue;
      const auto r = static_cast<security::VerifyResult>(i);
      v[std::string(security::to_string(r))] = counts[i];
      if (r != security::VerifyResult::kOk && r != security::VerifyResult::kUnknownSigner &&
          !refusals_said_[i]) {
        refusals_said_[i] = true;
        spdlog::warn("security: dropping received packets: {}", security::to_string(r));
      }
    }
    j["security"] = {
        {"mode", security::to_string(security_->mode())},
        {"verify_policy", security::to_string(security_->verify_policy())},
        {"verify", v},
        {"passed_unverified", security_->passed_unverified()},
        {"held", security_->held()},
        // (signer, generationTime) pairs kept for replay detection (verify.replay counts hits)
        {"replay_entries", security_->verifier().replay_entries()},
        {"unsecured_dropped", router_.stats().dropped(geonet::DropReason::kUnsecured)},
        {"cam_ssp_refused", ca_.counters().not_permitted},
        {"denm_ssp_refused", den_.counters().not_permitted},
        {"its_aid_mismatch", btp_.stats().dropped(btp::DropReason::kItsAidMismatch)},
        {"beacons_unsigned", router_.stats().beacons_unsigned}};
  }
  return j;
}

void Station::log_totals() const {
  spdlog::info(
      "CAMs sent {}, received {}; DENMs sent {}, received {}; router drops: {} parse; {} "
      "frame(s) heard before the first fix, not taken in (no world time yet)",
      ca_.counters().sent, ca_.counters().received, den_.counters().sent, den_.counters().received,
      router_.stats().dropped(geonet::DropReason::kParseError), synced_link_.dropped_before_sync());
}

}  // namespace tb::its::station
