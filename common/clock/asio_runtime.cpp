#include "common/clock/asio_runtime.hpp"

namespace tb::clock {

TimerId AsioRuntime::schedule_at(SteadyTime when, TimerCallback cb) {
  const TimerId id = queue_.push(when, std::move(cb));
  // Callbacks that schedule their successors (every periodic timer) would set the timer once
  // per callback of a wake-up; on_timer() sets it once for all of them.
  if (dispatching_)
    return id;
  // Armed for an instant whose timer was cancelled (earlier than every timer left): a timer
  // moved later — cancelled and scheduled again, as the CA service's check timer at every fix
  // — would wake the thread for nothing; re-arming costs a timerfd update instead of a wake-up
  // (issue 33).
  if (!armed_ || queue_.next_due() != armed_for_)
    rearm();
  return id;
}

void AsioRuntime::cancel(TimerId id) {
  // A timer armed for a cancelled callback that nothing replaces fires harmlessly and
  // re-arms for the next one; schedule_at() re-arms when something does.
  queue_.cancel(id);
}

void AsioRuntime::rearm() {
  if (queue_.empty())
    return;
  armed_ = true;
  ++rearms_;
  armed_for_ = queue_.next_due();
  timer_.expires_at(armed_for_);
  timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec == boost::asio::error::operation_aborted)
      return;  // re-armed or shut down
    armed_ = false;
    on_timer();
  });
}

void AsioRuntime::on_timer() {
  ++wakeups_;
  dispatching_ = true;
  try {
    while (!queue_.empty() && queue_.next_due() <= SteadyClock::now())
      queue_.pop()();
  } catch (...) {
    dispatching_ = false;
    rearm();
    throw;
  }
  dispatching_ = false;
  rearm();
}

}  // namespace tb::clock
