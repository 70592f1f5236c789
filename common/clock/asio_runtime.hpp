#pragma once
/// @file The real-time Runtime of the programs, driven by a Boost.Asio io_context.

#include <cstdint>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "common/clock/runtime.hpp"

namespace tb::clock {

/// Fires timers from the io_context's thread. One steady_timer is armed for the earliest timer.
class AsioRuntime final : public Runtime {
 public:
  explicit AsioRuntime(boost::asio::io_context& io) : timer_(io) {}
  SteadyTime steady_now() const override { return SteadyClock::now(); }
  WallTime wall_now() const override { return WallClock::now(); }
  TimerId schedule_at(SteadyTime when, TimerCallback cb) override;
  /// Lets timers fire up to @p slack late so that the thread wakes at most once per @p slack
  /// for them (every timer due by then fires in that wake-up), as the kernel's timer slack does
  /// for a process. Zero (the default): each timer at its instant. For station-host, whose
  /// hundreds of stations each keep their own periodic timers.
  void set_timer_slack(Duration slack) { slack_ = slack; }
  void cancel(TimerId id) override;
  /// How often the armed timer woke the thread (for tests: a wake-up for a cancelled timer
  /// that was replaced by a later one is one too many).
  std::uint64_t wakeups() const { return wakeups_; }
  /// How often the timer was set (each a timerfd_settime system call under Asio's reactor).
  std::uint64_t rearms() const { return rearms_; }

 private:
  void rearm();
  SteadyTime wake_at() const;  // of the next wake-up; the queue is not empty
  void on_timer();

  boost::asio::steady_timer timer_;
  TimerQueue queue_;
  bool armed_ = false;
  bool dispatching_ = false;  // in on_timer(): it re-arms once when its callbacks are done
  SteadyTime armed_for_{};
  Duration slack_{};
  SteadyTime no_wake_before_{};  // the last wake-up + slack_
  std::uint64_t wakeups_ = 0;
  std::uint64_t rearms_ = 0;
};

}  // namespace tb::clock
