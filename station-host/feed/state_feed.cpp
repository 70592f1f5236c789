#include "station-host/feed/state_feed.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "common/clock/utc.hpp"
#include "station-host/feed/epoch_phase.hpp"

namespace tb::host {

StateFeed::StateFeed(const scenario::Scenario& scenario, const geodesy::Georeferencing& frame,
                     clock::Runtime& runtime, std::uint64_t seed)
    : scenario_(scenario),
      frame_(frame),
      runtime_(runtime),
      seed_(seed),
      world_start_(scenario.start_time) {}

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
  // Not the emulator's whole periods: each pooled station's epochs, and so its CA checks, at
  // its own instant of the period (epoch_phase.hpp).
  if (scenario_.rates.gnss_hz > 0)
    gc.epoch_offset = epoch_phase(
        station_id, std::chrono::nanoseconds{std::llround(1e9 / scenario_.rates.gnss_hz)});
  StationSources s;
  s.station_id = station_id;
  s.gnss = std::make_unique<StateGnssReceiver>(gc, frame_, runtime_);
  s.vehicle = std::make_unique<StateVehicleData>(scenario_.rates.can_dynamics_hz,
                                                 v->model.steering_ratio, runtime_);
  if (const auto ns = world_start_.unix_ns())
    s.gnss->set_start_time(clock::from_unix_ns(*ns));
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
  if (const auto start = world_start_.update(world_start, batch_.front(), runtime_.wall_now()))
    for (auto& [id, s] : stations_)
      s.gnss->set_start_time(*start);
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

}  // namespace tb::host
