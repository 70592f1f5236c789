#include "network-emulator/radio/medium.hpp"

#include <algorithm>

namespace tb::emu::radio {

Medium::~Medium() {
  for (clock::TimerId id : timers_)
    runtime_.cancel(id);
}

void Medium::attach(StationId id, FrameSink& sink) {
  Receiver& r = receivers_[id];
  r.sink = &sink;
  r.pooled = nullptr;
  if (std::find(unplaced_.begin(), unplaced_.end(), id) == unplaced_.end())
    unplaced_.push_back(id);
}

void Medium::attach_pooled(StationId id, PooledSink& host) {
  Receiver& r = receivers_[id];
  r.sink = nullptr;
  r.pooled = &host;
  if (std::find(unplaced_.begin(), unplaced_.end(), id) == unplaced_.end())
    unplaced_.push_back(id);
}

void Medium::detach(StationId id) {
  receivers_.erase(id);
}

void Medium::offer(StationId from) {
  offered_.clear();
  if (culling_ && channel_.reachable(from, reachable_)) {
    for (const StationId id : reachable_)
      if (id != from && receivers_.contains(id))
        offered_.push_back(id);
    // Receivers with no position yet cannot be placed in range or out of it: offered, so that
    // their links count unknown_position as without culling. Checked until they have one.
    std::erase_if(unplaced_, [this](StationId id) {
      return !receivers_.contains(id) || channel_.has_position(id);
    });
    for (const StationId id : unplaced_)
      if (id != from)
        offered_.push_back(id);
    // Id order, as without culling: the channel draws its random numbers in the same order
    // for the links it decides, so a seed gives the same outcome either way.
    std::sort(offered_.begin(), offered_.end());
    const std::size_t others = receivers_.size() - (receivers_.contains(from) ? 1 : 0);
    const std::uint64_t culled = others - offered_.size();
    culled_ += culled;
    channel_.count_culled(culled);
    return;
  }
  for (const auto& [to, rx] : receivers_)
    if (to != from)
      offered_.push_back(to);
}

void Medium::schedule(clock::SteadyTime due, std::function<void()> fn) {
  auto id = std::make_shared<clock::TimerId>(0);
  *id = runtime_.schedule_at(due, [this, id, fn = std::move(fn)] {
    timers_.erase(*id);
    fn();
  });
  timers_.insert(*id);
}

void Medium::on_frame(StationId from, std::span<const std::uint8_t> frame, std::int64_t unix_ns) {
  ++frames_in_;
  if (frame_observer_)
    frame_observer_(from, frame, unix_ns);
  deliver(from, frame);
}

void Medium::on_remote_frame(StationId from, std::span<const std::uint8_t> frame) {
  ++remote_frames_in_;
  deliver(from, frame);
}

void Medium::deliver(StationId from, std::span<const std::uint8_t> frame) {
  std::shared_ptr<const std::vector<std::uint8_t>> copy;  // made once, only if a frame waits
  offer(from);
  pooled_.clear();
  const clock::SteadyTime now = runtime_.steady_now();
  for (const StationId to : offered_) {
    const Decision d = channel_.decide(from, to);
    if (!d.deliver)
      continue;
    Receiver& rx = receivers_.find(to)->second;
    const bool at_once = d.delay == clock::Duration{0} && rx.last_due <= now;
    const clock::SteadyTime due = at_once ? now : std::max(now + d.delay, rx.last_due);
    if (!at_once)
      rx.last_due = due;
    if (rx.pooled) {
      pooled_.push_back({rx.pooled, due, to});
      continue;
    }
    if (at_once) {
      rx.sink->transmit(frame);
      ++deliveries_;
      continue;
    }
    if (!copy)
      copy = std::make_shared<const std::vector<std::uint8_t>>(frame.begin(), frame.end());
    schedule(due, [this, to = to, copy] {
      auto it = receivers_.find(to);
      if (it == receivers_.end() || !it->second.sink)
        return;  // detached (or re-attached behind a host) while the frame was in flight
      it->second.sink->transmit(*copy);
      ++deliveries_;
    });
  }
  if (!pooled_.empty())
    flush_pooled(frame, now, copy);
}

void Medium::flush_pooled(std::span<const std::uint8_t> frame, clock::SteadyTime now,
                          std::shared_ptr<const std::vector<std::uint8_t>>& copy) {
  // One transmit per (host, due time): the receivers of a host that get the frame together
  // share one frame on the host's port. Stable, so that ids stay in order within a group.
  std::stable_sort(pooled_.begin(), pooled_.end(),
                   [](const PooledDelivery& a, const PooledDelivery& b) {
                     return a.host != b.host ? std::less<>()(a.host, b.host) : a.due < b.due;
                   });
  for (std::size_t i = 0; i < pooled_.size();) {
    std::size_t j = i;
    group_.clear();
    while (j < pooled_.size() && pooled_[j].host == pooled_[i].host &&
           pooled_[j].due == pooled_[i].due)
      group_.push_back(pooled_[j++].to);
    PooledSink* host = pooled_[i].host;
    if (pooled_[i].due == now) {
      host->transmit(group_, frame);
      ++pooled_transmits_;
      deliveries_ += group_.size();
    } else {
      if (!copy)
        copy = std::make_shared<const std::vector<std::uint8_t>>(frame.begin(), frame.end());
      schedule(pooled_[i].due, [this, host, ids = group_, copy]() mutable {
        // Only those still behind this host (detached while the frame was in flight: not).
        std::erase_if(ids, [&](StationId id) {
          const auto it = receivers_.find(id);
          return it == receivers_.end() || it->second.pooled != host;
        });
        if (ids.empty())
          return;
        host->transmit(ids, *copy);
        ++pooled_transmits_;
        deliveries_ += ids.size();
      });
    }
    i = j;
  }
}

}  // namespace tb::emu::radio
