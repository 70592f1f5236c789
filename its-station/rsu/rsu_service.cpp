#include "its-station/rsu/rsu_service.hpp"

#include <spdlog/spdlog.h>

#include "common/wire/signal_feed.hpp"

namespace tb::its::rsu {

namespace sim = wire::sim;

RsuService::RsuService(clock::Runtime& runtime, facilities::MessageSender& sender,
                       IntersectionMap map, RsuConfig config)
    : runtime_(runtime),
      sender_(sender),
      map_(std::move(map)),
      config_(config),
      spatem_(map_.intersection_id) {}

RsuService::~RsuService() {
  stop();
}

void RsuService::start() {
  if (running_)
    return;
  running_ = true;
  next_mapem_ = runtime_.steady_now();
  send_mapem();
  schedule_spatem(runtime_.steady_now() + config_.spatem_interval);
}

void RsuService::stop() {
  if (!running_)
    return;
  running_ = false;
  runtime_.cancel(mapem_timer_);
  runtime_.cancel(spatem_timer_);
}

void RsuService::send_mapem() {
  const facilities::SendResult r = sender_.send_single_hop(kBtpPortMapem, map_.encoded);
  if (r == facilities::SendResult::kSent) {
    ++counters_.mapem_sent;
    if (sent_listener_)
      sent_listener_(kBtpPortMapem, false, map_.encoded);
  } else {
    ++counters_.send_errors;
    if (!send_error_said_) {
      send_error_said_ = true;
      spdlog::warn("rsu: MAPEM not sent: {} (said once)", facilities::to_string(r));
    }
  }
  // On a fixed grid, so that the rate stays 1 Hz whatever a send costs; after a stall (a
  // stopped process) the grid starts again rather than catching up in a burst.
  next_mapem_ += config_.mapem_interval;
  if (next_mapem_ <= runtime_.steady_now())
    next_mapem_ = runtime_.steady_now() + config_.mapem_interval;
  mapem_timer_ = runtime_.schedule_at(next_mapem_, [this] { send_mapem(); });
}

void RsuService::schedule_spatem(clock::SteadyTime when) {
  runtime_.cancel(spatem_timer_);
  spatem_timer_ = runtime_.schedule_at(when, [this] {
    send_spatem(false);
    schedule_spatem(runtime_.steady_now() + config_.spatem_interval);
  });
}

bool RsuService::stale(clock::SteadyTime now) const {
  return now - latest_at_ > config_.feed_stale_after;
}

void RsuService::send_spatem(bool on_change) {
  if (!latest_)
    return;  // no feed yet: nothing to tell
  const clock::SteadyTime now = runtime_.steady_now();
  if (stale(now)) {
    ++counters_.spatem_stale;
    if (!stale_said_) {
      stale_said_ = true;
      spdlog::warn(
          "rsu: signal feed of intersection {} is {} ms old (> {} ms): no SPATEM until "
          "it resumes",
          map_.intersection_id, last_feed_age_ms().value_or(0),
          std::chrono::duration_cast<std::chrono::milliseconds>(config_.feed_stale_after).count());
    }
    return;
  }
  const std::int64_t now_ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(runtime_.wall_now().time_since_epoch())
          .count();
  const auto bytes = spatem_.build(*latest_, now_ms);
  if (!bytes) {
    ++counters_.encode_errors;
    return;
  }
  const facilities::SendResult r = sender_.send_single_hop(kBtpPortSpatem, *bytes);
  if (r != facilities::SendResult::kSent) {
    ++counters_.send_errors;
    if (!send_error_said_) {
      send_error_said_ = true;
      spdlog::warn("rsu: SPATEM not sent: {} (said once)", facilities::to_string(r));
    }
    return;
  }
  last_sent_ = latest_->groups;
  ++counters_.spatem_sent;
  if (on_change)
    ++counters_.spatem_on_change;
  if (sent_listener_)
    sent_listener_(kBtpPortSpatem, on_change, *bytes);
}

void RsuService::on_datagram(std::span<const std::uint8_t> datagram) {
  ++counters_.feed_datagrams;
  auto states = wire::decode_signal_feed(datagram);
  if (!states) {
    ++counters_.feed_malformed;
    if (!malformed_said_) {
      malformed_said_ = true;
      spdlog::warn(
          "rsu: signal feed datagram of {} bytes dropped: {} (said once; counted in "
          "rsu.feed_malformed)",
          datagram.size(), to_string(states.error()));
    }
    return;
  }
  on_signal_states(*states);
}

void RsuService::on_signal_states(const sim::SignalStates& states) {
  sim::SignalStates mine;
  mine.world_time_ms = states.world_time_ms;
  for (const sim::SignalGroupState& g : states.groups)
    if (g.intersection_id == map_.intersection_id)
      mine.groups.push_back(g);
  if (mine.groups.empty()) {
    ++counters_.feed_foreign;
    return;
  }
  const bool was_stale = latest_ && stale(runtime_.steady_now());
  latest_ = std::move(mine);
  latest_at_ = runtime_.steady_now();
  if (was_stale && stale_said_) {
    stale_said_ = false;
    spdlog::info("rsu: signal feed of intersection {} resumed", map_.intersection_id);
  }
  if (!running_)
    return;
  // EN/TS 103 301 and the C-Roads profile: a SPATEM on every change of a signal state, not
  // only on the 100 ms grid.
  sim::SignalStates sent;
  sent.groups = last_sent_;
  if (!same_states(sent, *latest_)) {
    send_spatem(true);
    // The next periodic SPATEM follows a full interval after this one.
    schedule_spatem(runtime_.steady_now() + config_.spatem_interval);
  }
}

std::optional<std::int64_t> RsuService::last_feed_age_ms() const {
  if (!latest_)
    return std::nullopt;
  return std::chrono::duration_cast<std::chrono::milliseconds>(runtime_.steady_now() - latest_at_)
      .count();
}

}  // namespace tb::its::rsu
