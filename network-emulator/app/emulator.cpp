#include "network-emulator/app/emulator.hpp"

#include <chrono>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common/clock/utc.hpp"
#include "common/map/rsu_site.hpp"

namespace tb::emu {

Emulator::Emulator(const scenario::Scenario& scenario, const tb::can::Database& dbc,
                   const std::vector<StationEndpoints>& stations, const StationIoFactory& make_io,
                   const clock::Clock& clock, trace::Tracer& tracer, std::uint64_t seed)
    : scenario_(scenario),
      clock_(clock),
      tracer_(tracer),
      map_(scenario),
      world_start_(scenario.start_time) {
  std::optional<can::CanFeeder> first_feeder;
  const std::vector<map::RsuSite> sites = map::rsu_sites(scenario.rsus, map_);
  std::vector<SignalFeed::Rsu> feed;
  for (const StationEndpoints& e : stations) {
    if (const scenario::Rsu* r = scenario.find_rsu(e.station_id)) {
      add_rsu(e, *r, sites[static_cast<std::size_t>(r - scenario.rsus.data())], make_io, seed,
              feed);
      continue;
    }
    const scenario::Vehicle* v = scenario.find_station(e.station_id);
    if (!v)
      throw std::runtime_error(fmt::format("station {} is not in the scenario", e.station_id));
    gnss::AgentConfig gc;
    gc.station_id = e.station_id;
    gc.rate_hz = scenario.rates.gnss_hz;
    // Until sim-server's start time arrives with the states (world_start_).
    gc.start_time = scenario.start_time.value_or(std::chrono::system_clock::time_point{});
    gc.errors = scenario.gnss;
    gc.seed = seed;
    gc.antenna = v->model.antenna;
    can::FeederConfig cc;
    cc.dynamics_hz = scenario.rates.can_dynamics_hz;
    cc.body_hz = scenario.rates.can_body_hz;
    cc.steering_ratio = v->model.steering_ratio;
    // One feeder made from the DBC, the others share its messages and encodings.
    if (!first_feeder || !first_feeder->same_rates(cc)) {
      auto feeder = can::CanFeeder::create(dbc, cc);
      if (!feeder)
        throw std::runtime_error(feeder.error().message());
      first_feeder.emplace(std::move(*feeder));
    }
    stations_.emplace(e.station_id, std::unique_ptr<Station>(new Station{
                                        e.station_id, e, gnss::GpsAgent(gc, map_.georeferencing()),
                                        first_feeder->sibling(cc), make_io(e), PeerHealth(clock),
                                        PeerHealth(clock), std::nullopt}));
  }
  signals_ = std::make_unique<SignalFeed>(std::move(feed), tracer_);
}

void Emulator::add_rsu(const StationEndpoints& e, const scenario::Rsu& r, const map::RsuSite& site,
                       const StationIoFactory& make_io, std::uint64_t seed,
                       std::vector<SignalFeed::Rsu>& feed) {
  const map::odr::SignalisedJunction* junction = map_.signals().junction(r.junction);
  if (junction == nullptr)  // the scenario loader refuses such an RSU
    throw std::runtime_error(
        fmt::format("RSU {}: junction \"{}\" has no traffic lights", r.id, r.junction));
  gnss::AgentConfig gc;
  gc.station_id = e.station_id;
  gc.rate_hz = scenario_.rates.gnss_hz;
  gc.start_time = scenario_.start_time.value_or(std::chrono::system_clock::time_point{});
  // A receiver on a mast has the same errors as one on a roof; its antenna is the RSU's point.
  gc.errors = scenario_.gnss;
  gc.seed = seed;
  wire::VehicleState fixed;
  fixed.station_id = e.station_id;
  fixed.position = {site.x, site.y, site.antenna_z};
  auto station = std::unique_ptr<Station>(
      new Station{e.station_id, e, gnss::GpsAgent(gc, map_.georeferencing()), std::nullopt,
                  make_io(e), PeerHealth(clock_), PeerHealth(clock_), fixed});
  feed.push_back({e.station_id, junction->intersection_id, station->io.signals.get()});
  rsus_.push_back(station.get());
  spdlog::info(
      "RSU {} (station {}) at junction {}: GNSS at ({:.1f}, {:.1f}), {:.1f} m up "
      "(ground {:.2f} m); signal feed to {}:{}{}",
      r.id, e.station_id, r.junction, site.x, site.y, r.height_m, site.ground_z, e.address,
      e.signal_port, e.netns.empty() ? "" : " in netns " + e.netns);
  stations_.emplace(e.station_id, std::move(station));
}

bool Emulator::handle_datagram(std::span<const std::uint8_t> bytes) {
  ++counters_.datagrams;
  std::int64_t world_start = wire::kUnknownWorldStart;
  const auto count = wire::decode_batch(bytes, batch_, &world_start);
  if (!count) {
    ++counters_.malformed;
    const auto kind = static_cast<std::size_t>(count.error());
    if (kind < counters_.malformed_by_error.size()) {
      ++counters_.malformed_by_error[kind];
      if (!logged_malformed_[kind]) {
        logged_malformed_[kind] = true;
        spdlog::warn(
            "dropping malformed vehicle-state datagrams ({} bytes): {} (logged once; "
            "see the status line for counts)",
            bytes.size(), wire::to_string(count.error()));
      }
    }
    return false;
  }
  if (const auto start = world_start_.update(world_start, batch_.front(), clock_.wall_now())) {
    for (auto& [id, s] : stations_)
      s->gps.set_start_time(*start);
    tracer_.record("emu.world_start", {{"world_start_ns", clock::to_unix_ns(*start)}});
  }
  const wire::VehicleState* newest = nullptr;
  for (const wire::VehicleState& state : batch_) {
    handle_state(state);
    if (newest == nullptr || state.sim_time_ns > newest->sim_time_ns)
      newest = &state;
  }
  if (newest != nullptr && !rsus_.empty())
    feed_rsus(*newest);
  return true;
}

void Emulator::feed_rsus(const wire::VehicleState& newest) {
  // The RSUs stand still: their receivers see the same instants as the vehicles' (epochs on
  // whole periods of sim time, GpsAgent), so the stream's time drives them too.
  for (Station* s : rsus_) {
    wire::VehicleState& f = *s->fixed;
    f.tick = newest.tick;
    f.sim_time_ns = newest.sim_time_ns;
    f.step_wall_ns = newest.step_wall_ns;
    f.send_wall_ns = newest.send_wall_ns;
    ++counters_.rsu_states;
    feed_gps(*s, f);
  }
}

void Emulator::handle_state(const wire::VehicleState& state) {
  const auto it = stations_.find(state.station_id);
  if (it == stations_.end()) {
    ++counters_.unknown_station;
    if (!logged_unknown_) {
      logged_unknown_ = true;
      spdlog::warn(
          "dropping states of station {}, which is not a station of this emulator "
          "(logged once; see the status line for counts)",
          state.station_id);
    }
    return;
  }
  ++counters_.states;
  Station& s = *it->second;
  if (tracer_.enabled())  // no record fields built per state when tracing is off
    tracer_.record("emu.state", {{"station", s.id}, {"tick", state.tick}});
  if (s.fixed)
    return;  // an RSU's id in the stream: it stands where the scenario puts it, whatever comes
  feed_gps(s, state);
  if (const auto frames = s.can->on_state(state); !frames.empty())
    send_can(s, state, frames);
}

void Emulator::feed_gps(Station& s, const wire::VehicleState& state) {
  if (const auto nmea = s.gps.on_state(state))
    send_nmea(s, state, *nmea);
}

void Emulator::send_nmea(Station& s, const wire::VehicleState& state, std::string_view nmea) {
  if (!s.io.gnss)
    return;
  if (!s.gnss_health.should_send()) {
    ++counters_.nmea_skipped;
    return;
  }
  const std::error_code ec =
      s.io.gnss->send({reinterpret_cast<const std::uint8_t*>(nmea.data()), nmea.size()});
  if (ec) {
    ++counters_.nmea_failed;
  } else {
    ++counters_.nmea_sent;
    if (tracer_.enabled()) {
      const auto fix_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                              s.gps.last_fix().time.time_since_epoch())
                              .count();
      tracer_.record("emu.nmea", {{"station", s.id}, {"tick", state.tick}, {"fix_ms", fix_ms}});
    }
  }
  report(s, "GNSS", s.gnss_health.record(ec), s.gnss_health);
}

void Emulator::send_can(Station& s, const wire::VehicleState& state,
                        std::span<const tb::can::CanFrame> frames) {
  if (!s.io.can)
    return;
  if (!s.can_health.should_send()) {
    counters_.can_skipped += frames.size();
    return;
  }
  const std::error_code ec = s.io.can->send(frames);
  if (ec) {
    counters_.can_failed += frames.size();
  } else {
    counters_.can_frames_sent += frames.size();
    // One record per state's frames, which travel together (one cannelloni datagram): one per
    // frame was five times the records for nothing the report joins on (issue 21).
    if (tracer_.enabled())
      tracer_.record("emu.can",
                     {{"station", s.id}, {"tick", state.tick}, {"frames", frames.size()}});
  }
  report(s, "CAN", s.can_health.record(ec), s.can_health);
}

void Emulator::report(Station& s, const char* feed, PeerHealth::Change change,
                      const PeerHealth& h) {
  const auto& e = s.endpoints;
  const std::string where =
      e.netns.empty() ? e.address : fmt::format("{} in netns {}", e.address, e.netns);
  if (change == PeerHealth::Change::kPaused)
    spdlog::warn(
        "station {}: {} receiver at {} is gone ({}); pausing its feed, retrying every "
        "second",
        s.id, feed, where, h.last_error().message());
  else if (change == PeerHealth::Change::kResumed)
    spdlog::info("station {}: {} receiver at {} is back; feed resumed", s.id, feed, where);
}

std::size_t Emulator::paused_stations() const {
  std::size_t n = 0;
  for (const auto& [id, s] : stations_)
    n += (s->gnss_health.paused() || s->can_health.paused()) ? 1 : 0;
  return n;
}

std::string Emulator::status_line() const {
  const Counters& c = counters_;
  return fmt::format(
      "states {} (datagrams {}, malformed {}, unknown station {}) | NMEA sent {} failed {} "
      "skipped {} | CAN frames sent {} failed {} skipped {} | stations {} paused {}{}",
      c.states, c.datagrams, c.malformed, c.unknown_station, c.nmea_sent, c.nmea_failed,
      c.nmea_skipped, c.can_frames_sent, c.can_failed, c.can_skipped, stations_.size(),
      paused_stations(), signal_status());
}

std::string Emulator::signal_status() const {
  const SignalFeedCounters& g = signals_->counters();
  if (rsus_.empty() && g.datagrams == 0)
    return "";
  return fmt::format(
      " | signals {} (malformed {}, duplicates {}) to {} RSUs: sent {} failed {} without "
      "their junction {}",
      g.datagrams, g.malformed, g.duplicates, rsus_.size(), g.sent, g.failed, g.no_groups);
}

}  // namespace tb::emu
