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
  void cancel(TimerId id) override;
  /// How often the armed timer woke the thread (for tests: a wake-up for a cancelled timer
  /// that was replaced by a later one is one too many).
  std::uint64_t wakeups() const { return wakeups_; }
  /// How often the timer was set (each a timerfd_settime system call under Asio's reactor).
  std::uint64_t rearms() const { return rearms_; }

 private:
  void rearm();
  void on_timer();

  boost::asio::steady_timer timer_;
  TimerQueue queue_;
  bool armed_ = false;
  bool dispatching_ = false;  // in on_timer(): it re-arms once when its callbacks are done
  SteadyTime armed_for_{};
  std::uint64_t wakeups_ = 0;
  std::uint64_t rearms_ = 0;
};

}  // namespace tb::clock
