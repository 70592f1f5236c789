#include "network-emulator/gnss/world_start.hpp"

#include <spdlog/spdlog.h>

#include "common/clock/utc.hpp"

namespace tb::emu {

std::optional<clock::WallTime> WorldStart::update(std::int64_t from_states,
                                                  const wire::VehicleState& first,
                                                  clock::WallTime now) {
  // Once known, only a start the states carry can move it: the fallbacks below would drift
  // with every batch.
  if (unix_ns_ && (from_states == wire::kUnknownWorldStart || from_states == *unix_ns_))
    return std::nullopt;
  std::int64_t start_ns = from_states;
  std::string source;
  if (from_states != wire::kUnknownWorldStart) {
    source = "sim-server's, with the states";
  } else if (scenario_start_) {
    start_ns = clock::to_unix_ns(*scenario_start_);
    source = "the scenario's start_time (the states do not carry one)";
  } else {
    // A sender that knows no start time (a tool, an old client) and a scenario that pins none:
    // the world started when this state's sim time says, by the host's clock.
    start_ns = clock::to_unix_ns(now) - first.sim_time_ns;
    source =
        "the host's clock minus the first state's sim time (the states carry no start time and "
        "the scenario pins none)";
  }
  if (unix_ns_ == start_ns)
    return std::nullopt;
  const bool first_time = !unix_ns_;
  unix_ns_ = start_ns;
  source_ = std::move(source);
  const auto start = clock::from_unix_ns(start_ns);
  const std::string when = clock::format_utc(start);
  if (first_time)
    spdlog::info("GNSS time: sim time 0 is {}, {}", when, source_);
  else
    spdlog::warn("GNSS time: sim time 0 is now {}, {} (a restarted sim-server)", when, source_);
  return start;
}

}  // namespace tb::emu
