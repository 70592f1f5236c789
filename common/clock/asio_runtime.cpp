#include "common/clock/asio_runtime.hpp"

namespace tb::clock {

TimerId AsioRuntime::schedule_at(SteadyTime when, TimerCallback cb) {
  const TimerId id = queue_.push(when, std::move(cb));
  if (!armed_ || when < armed_for_)
    rearm();
  return id;
}

void AsioRuntime::cancel(TimerId id) {
  // A timer armed for a cancelled callback fires harmlessly and re-arms for the next one.
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
  while (!queue_.empty() && queue_.next_due() <= SteadyClock::now()) {
    queue_.pop()();
  }
  if (!armed_)
    rearm();
}

}  // namespace tb::clock
