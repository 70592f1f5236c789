#pragma once
/// @file Injectable clocks and timers.
///
/// Logic never reads the system clock or sleeps: it asks a Clock for the time and a Runtime to
/// call it back later. Programs wire AsioRuntime (real time, driven by an io_context) in main;
/// tests use ManualRuntime and advance time by hand, so they run without sleeps.

#include <chrono>
#include <cstdint>

namespace tb::clock {

using SteadyClock = std::chrono::steady_clock;
using SteadyTime = SteadyClock::time_point;
using WallClock = std::chrono::system_clock;
/// CLOCK_REALTIME; the trace records and the sim's wall-clock stamps use it.
using WallTime = WallClock::time_point;
using Duration = std::chrono::nanoseconds;

class Clock {
 public:
  virtual ~Clock() = default;
  /// Monotonic time, for intervals and timers.
  virtual SteadyTime steady_now() const = 0;
  /// Wall-clock (UTC) time, for timestamps that leave the process.
  virtual WallTime wall_now() const = 0;
};

/// The operating system's clocks.
class SystemClock final : public Clock {
 public:
  SteadyTime steady_now() const override { return SteadyClock::now(); }
  WallTime wall_now() const override { return WallClock::now(); }
};

/// A clock that moves only when told to. Wall time moves together with steady time.
class ManualClock : public Clock {
 public:
  explicit ManualClock(WallTime wall_start = WallTime{std::chrono::seconds{1'700'000'000}})
      : wall_offset_(wall_start.time_since_epoch()) {}
  SteadyTime steady_now() const override { return now_; }
  WallTime wall_now() const override { return WallTime{now_.time_since_epoch() + wall_offset_}; }
  void advance(Duration d) { now_ += d; }
  void set_steady(SteadyTime t) { now_ = t; }

 private:
  SteadyTime now_{};
  Duration wall_offset_;
};

/// Nanoseconds since the Unix epoch, the unit of trace timestamps and wire time stamps.
inline std::int64_t to_unix_ns(WallTime t) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}
inline WallTime from_unix_ns(std::int64_t ns) {
  return WallTime{std::chrono::duration_cast<WallClock::duration>(std::chrono::nanoseconds{ns})};
}

}  // namespace tb::clock
