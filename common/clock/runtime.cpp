#include "common/clock/runtime.hpp"

namespace tb::clock {

TimerId TimerQueue::push(SteadyTime when, TimerCallback cb) {
  const TimerId id = next_id_++;
  timers_.emplace(std::make_pair(when, id), std::move(cb));
  due_by_id_.emplace(id, when);
  return id;
}

bool TimerQueue::cancel(TimerId id) {
  const auto it = due_by_id_.find(id);
  if (it == due_by_id_.end())
    return false;
  timers_.erase(std::make_pair(it->second, id));
  due_by_id_.erase(it);
  return true;
}

TimerCallback TimerQueue::pop() {
  auto node = timers_.extract(timers_.begin());
  due_by_id_.erase(node.key().second);
  return std::move(node.mapped());
}

TimerId ManualRuntime::schedule_at(SteadyTime when, TimerCallback cb) {
  return queue_.push(when, std::move(cb));
}

void ManualRuntime::advance_to(SteadyTime t) {
  while (!queue_.empty() && queue_.next_due() <= t) {
    const SteadyTime due = queue_.next_due();
    if (due > clock_.steady_now())
      clock_.set_steady(due);
    queue_.pop()();
  }
  if (t > clock_.steady_now())
    clock_.set_steady(t);
}

}  // namespace tb::clock
