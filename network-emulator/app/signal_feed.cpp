#include "network-emulator/app/signal_feed.hpp"

#include <spdlog/spdlog.h>

namespace tb::emu {

SignalFeed::SignalFeed(std::vector<Rsu> rsus, trace::Tracer& tracer)
    : rsus_(std::move(rsus)), tracer_(tracer) {}

bool SignalFeed::handle_datagram(std::span<const std::uint8_t> bytes) {
  ++counters_.datagrams;
  auto states = wire::decode_signal_feed(bytes);
  if (!states) {
    ++counters_.malformed;
    const auto kind = static_cast<std::size_t>(states.error());
    if (kind < counters_.malformed_by_error.size()) {
      ++counters_.malformed_by_error[kind];
      if (!logged_[kind]) {
        logged_[kind] = true;
        spdlog::warn(
            "dropping malformed signal-state datagrams ({} bytes): {} (logged once; see the "
            "status line for counts)",
            bytes.size(), wire::to_string(states.error()));
      }
    }
    return false;
  }
  // Every forwarding client sends the server's messages: the first copy of each world time
  // goes on, the others are dropped, and so is one a faster client's newer message overtook.
  const std::int64_t t = states->world_time_ms;
  if (last_world_ms_ && t <= *last_world_ms_ && *last_world_ms_ - t <= kSignalFeedRestartMs) {
    ++counters_.duplicates;
    return false;
  }
  last_world_ms_ = t;
  ++counters_.taken;
  for (const Rsu& rsu : rsus_) {
    own_.world_time_ms = t;
    own_.groups.clear();
    // The server's entries ascend by (intersection, group): the junction's are one run.
    for (const auto& g : states->groups)
      if (g.intersection_id == rsu.intersection_id)
        own_.groups.push_back(g);
    if (own_.groups.empty()) {
      ++counters_.no_groups;
      continue;
    }
    const auto datagram = wire::encode_signal_feed(own_);  // smaller than what came in
    const std::error_code ec = rsu.sink != nullptr ? rsu.sink->send(*datagram)
                                                   : std::make_error_code(std::errc::not_connected);
    if (ec) {
      ++counters_.failed;
      continue;
    }
    ++counters_.sent;
    if (tracer_.enabled())
      tracer_.record("emu.signals",
                     {{"station", rsu.station_id},
                      {"world_ms", static_cast<long long>(t)},
                      {"groups", static_cast<unsigned long long>(own_.groups.size())}});
  }
  return true;
}

}  // namespace tb::emu
