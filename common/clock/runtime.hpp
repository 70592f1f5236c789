#pragma once
/// @file Runtime: a clock that can also call back at a given time.

#include <cstdint>
#include <functional>
#include <map>
#include <string_view>
#include <utility>

#include "common/clock/clock.hpp"

namespace tb::clock {

using TimerId = std::uint64_t;
using TimerCallback = std::function<void()>;

class Runtime : public Clock {
 public:
  /// Calls @p cb once at @p when (or as soon as possible if that is past). Returns an id for
  /// cancel(). Callbacks may schedule and cancel timers.
  virtual TimerId schedule_at(SteadyTime when, TimerCallback cb) = 0;
  TimerId schedule_in(Duration delay, TimerCallback cb) {
    return schedule_at(steady_now() + delay, std::move(cb));
  }
  /// Cancels a pending timer; does nothing if it already fired or was cancelled.
  virtual void cancel(TimerId id) = 0;
};

/// Due timers, earliest first; ties fire in the order they were scheduled. Shared by the
/// manual and the Asio runtime so that both order callbacks the same way.
class TimerQueue {
 public:
  TimerId push(SteadyTime when, TimerCallback cb);
  bool cancel(TimerId id);
  bool empty() const { return timers_.empty(); }
  SteadyTime next_due() const { return timers_.begin()->first.first; }
  /// Removes and returns the earliest timer's callback.
  TimerCallback pop();
  std::size_t size() const { return timers_.size(); }

 private:
  std::map<std::pair<SteadyTime, TimerId>, TimerCallback> timers_;
  std::map<TimerId, SteadyTime> due_by_id_;
  TimerId next_id_ = 1;
};

/// Runtime for tests: time stands still until advance() or advance_to() moves it, firing every
/// timer that falls due on the way, each at its own instant.
class ManualRuntime final : public Runtime {
 public:
  explicit ManualRuntime(WallTime wall_start = WallTime{std::chrono::seconds{1'700'000'000}})
      : clock_(wall_start) {}

  SteadyTime steady_now() const override { return clock_.steady_now(); }
  WallTime wall_now() const override { return clock_.wall_now(); }
  TimerId schedule_at(SteadyTime when, TimerCallback cb) override;
  void cancel(TimerId id) override { queue_.cancel(id); }

  void advance(Duration d) { advance_to(steady_now() + d); }
  void advance_to(SteadyTime t);
  /// Fires the timers due now without moving time.
  void run_due() { advance_to(steady_now()); }
  std::size_t pending() const { return queue_.size(); }

 private:
  ManualClock clock_;
  TimerQueue queue_;
};

}  // namespace tb::clock
