#include "station-host/feed/state_feed.hpp"

#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common/clock/utc.hpp"

namespace tb::host {

StateFeed::StateFeed(const scenario::Scenario& scenario, const geodesy::Georeferencing& frame,
                     clock::Runtime& runtime, std::uint64_t seed)
    : scenario_(scenario), frame_(frame), runtime_(runtime), seed_(seed) {}

StationSources& StateFeed::add(std::uint32_t station_id) {
  const scenario::Vehicle* v = scenario_.find_station(station_id);
  if (v == nullptr)
    throw std::invalid_argument(
        fmt::format("station {} is not a vehicle of scenario '{}'", station_id, scenario_.name));
  if (stations_.contains(station_id))
    throw std::invalid_argument(fmt::format("station {} is listed twice", station_id));
  // The network-emulator's agent configuration (app/emulator.cpp), so that the same seed gives
  // the same errors.
  emu::gnss::AgentConfig gc;
  gc.station_id = station_id;
  gc.rate_hz = scenario_.rates.gnss_hz;
  gc.start_time = scenario_.start_time.value_or(std::chrono::system_clock::time_point{});
  gc.errors = scenario_.gnss;
  gc.seed = seed_;
  gc.antenna = v->model.antenna;
  StationSources s;
  s.station_id = station_id;
  s.gnss = std::make_unique<StateGnssReceiver>(gc, frame_, runtime_);
  s.vehicle = std::make_unique<StateVehicleData>(scenario_.rates.can_dynamics_hz,
                                                 v->model.steering_ratio, runtime_);
  if (world_start_ns_)
    s.gnss->set_start_time(clock::from_unix_ns(*world_start_ns_));
  return stations_.emplace(station_id, std::move(s)).first->second;
}

bool StateFeed::handle_datagram(std::span<const std::uint8_t> bytes) {
  ++counters_.datagrams;
  std::int64_t world_start = wire::kUnknownWorldStart;
  const auto count = wire::decode_batch(bytes, batch_, &world_start);
  if (!count) {
    ++counters_.malformed;
    const auto kind = static_cast<std::size_t>(count.error());
    if (kind < logged_malformed_.size() && !logged_malformed_[kind]) {
      logged_malformed_[kind] = true;
      spdlog::warn("dropping malformed state datagrams ({} bytes): {} (logged once)", bytes.size(),
                   wire::to_string(count.error()));
    }
    return false;
  }
  if (!world_start_ns_ ||
      (world_start != wire::kUnknownWorldStart && world_start != *world_start_ns_))
    use_world_start(world_start, batch_.front());
  for (const wire::VehicleState& state : batch_) {
    const auto it = stations_.find(state.station_id);
    if (it == stations_.end()) {
      // The stream carries every vehicle: full stations and other hosts' are not ours.
      ++counters_.other_station;
      continue;
    }
    ++counters_.states;
    it->second.gnss->on_state(state);
    it->second.vehicle->on_state(state);
  }
  return true;
}

// The emulator's rule (network-emulator/app/emulator.cpp), so that a pooled station's fix time
// is the one a full station's agent writes into its NMEA (docs/time.md).
void StateFeed::use_world_start(std::int64_t world_start_ns, const wire::VehicleState& first) {
  std::string source;
  if (world_start_ns != wire::kUnknownWorldStart) {
    source = "sim-server's, with the states";
  } else if (scenario_.start_time) {
    world_start_ns = clock::to_unix_ns(*scenario_.start_time);
    source = "the scenario's start_time (the states do not carry one)";
  } else {
    world_start_ns = clock::to_unix_ns(runtime_.wall_now()) - first.sim_time_ns;
    source = "the host's clock minus the first state's sim time (no start time known)";
  }
  if (world_start_ns_ == world_start_ns)
    return;
  const bool first_time = !world_start_ns_;
  world_start_ns_ = world_start_ns;
  const auto start = clock::from_unix_ns(world_start_ns);
  for (auto& [id, s] : stations_)
    s.gnss->set_start_time(start);
  const std::string when = clock::format_utc(start);
  if (first_time)
    spdlog::info("GNSS time: sim time 0 is {}, {}", when, source);
  else
    spdlog::warn("GNSS time: sim time 0 is now {}, {} (a restarted sim-server)", when, source);
}

}  // namespace tb::host
