#include "network-emulator/radio/medium.hpp"

#include <algorithm>

namespace tb::emu::radio {

Medium::~Medium() {
  for (clock::TimerId id : timers_)
    runtime_.cancel(id);
}

void Medium::attach(StationId id, FrameSink& sink) {
  receivers_[id].sink = &sink;
}

void Medium::detach(StationId id) {
  receivers_.erase(id);
}

void Medium::on_frame(StationId from, std::span<const std::uint8_t> frame, std::int64_t unix_ns) {
  ++frames_in_;
  if (frame_observer_)
    frame_observer_(from, frame, unix_ns);
  std::shared_ptr<const std::vector<std::uint8_t>> copy;  // made once, only if a frame waits
  for (auto& [to, rx] : receivers_) {
    if (to == from)
      continue;
    const Decision d = channel_.decide(from, to);
    if (!d.deliver)
      continue;
    const clock::SteadyTime now = runtime_.steady_now();
    if (d.delay == clock::Duration{0} && rx.last_due <= now) {
      rx.sink->transmit(frame);
      ++deliveries_;
      continue;
    }
    if (!copy)
      copy = std::make_shared<const std::vector<std::uint8_t>>(frame.begin(), frame.end());
    const clock::SteadyTime due = std::max(now + d.delay, rx.last_due);
    rx.last_due = due;
    auto id = std::make_shared<clock::TimerId>(0);
    *id = runtime_.schedule_at(due, [this, to = to, copy, id] {
      timers_.erase(*id);
      auto it = receivers_.find(to);
      if (it == receivers_.end())
        return;  // detached while the frame was in flight
      it->second.sink->transmit(*copy);
      ++deliveries_;
    });
    timers_.insert(*id);
  }
}

}  // namespace tb::emu::radio
