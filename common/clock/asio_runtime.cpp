#include "common/clock/asio_runtime.hpp"

namespace tb::clock {

TimerId AsioRuntime::schedule_at(SteadyTime when, TimerCallback cb) {
  const TimerId id = queue_.push(when, std::move(cb));
  // Armed for an instant whose timer was cancelled (earlier than every timer left): a timer
  // moved later — cancelled and scheduled again, as the CA service's check timer at every fix
  // — would wake the thread for nothing; re-arming costs a timerfd update instead of a wake-up
  // (issue 33).
  if (!armed_ || when < armed_for_ || armed_for_ < queue_.next_due())
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
  while (!queue_.empty() && queue_.next_due() <= SteadyClock::now()) {
    queue_.pop()();
  }
  if (!armed_)
    rearm();
}

}  // namespace tb::clock
