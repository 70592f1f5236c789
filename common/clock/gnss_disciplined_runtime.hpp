#pragma once
/// @file A station's ITS clock: GNSS-disciplined, the one clock every standard's timestamp and
/// interval in a station runs on (docs/time.md). Here, below the protocol layers, so that every
/// program that is a station (its-station, its-gn-probe) can use it.

#include <optional>

#include "common/clock/runtime.hpp"

namespace tb::clock {

/// A Runtime on the world's time, as an OBU disciplines its clock from GNSS: UTC is the newest
/// fix's time plus the monotonic time since it arrived, scaled by the rate at which GNSS time
/// has been running against the host's monotonic clock (1 when the simulation runs in real
/// time, faster under sim-server --fast). Its steady time and its timers run at that rate too,
/// so that intervals a standard defines (T_GenCam, DEN repetition and validity, location-table
/// lifetime) follow sim time, not the host's.
///
/// The host's wall clock plays no part once the first fix has come: the world's epoch (a
/// scenario's pinned start_time, a year back, say) may be anything. Before the first fix the
/// clock is the host's; a station sends nothing then (no position), and the log says so.
class GnssDisciplinedRuntime final : public Runtime {
 public:
  /// The rate is measured over at least this much host time, so that a fix's delivery jitter
  /// (a few ms through gpsd) moves it by well under 1 %.
  static constexpr Duration kRateWindow = std::chrono::seconds{1};
  /// A fix further than this from where the clock had got to is a new world (a restarted
  /// simulation, a time jump): the clock takes it as it is and measures the rate afresh.
  static constexpr Duration kResyncThreshold = std::chrono::seconds{5};
  /// A window with a longer pause between two fixes measures the pause, not the rate: it starts
  /// again after it (the simulation waits for its drivers before its first step).
  static constexpr Duration kMaxFixGap = std::chrono::milliseconds{500};
  /// Rates outside [1/kMaxRate, kMaxRate] are not measurements but a stalled or jumping feed.
  static constexpr double kMaxRate = 1000.0;

  explicit GnssDisciplinedRuntime(Runtime& host) : host_(host) {}

  /// A fix whose time (GNSS, i.e. world UTC) is @p gnss_time has just arrived.
  void on_fix(WallTime gnss_time);

  bool synchronised() const { return last_fix_.has_value(); }
  /// GNSS seconds per host second.
  double rate() const { return rate_; }
  /// How many times a fix was taken as a new world (kResyncThreshold).
  unsigned resyncs() const { return resyncs_; }

  /// A host wall-clock instant (a kernel receive stamp, say) on the world's time base.
  WallTime to_its(WallTime host_wall) const;

  SteadyTime steady_now() const override { return its_steady(host_.steady_now()); }
  WallTime wall_now() const override { return its_wall(host_.steady_now()); }
  TimerId schedule_at(SteadyTime when, TimerCallback cb) override;
  void cancel(TimerId id) override { host_.cancel(id); }

 private:
  struct Sample {
    SteadyTime host;  ///< host steady time the fix arrived at
    WallTime gnss;    ///< its GNSS time
  };
  SteadyTime its_steady(SteadyTime host) const;
  WallTime its_wall(SteadyTime host) const;
  Duration scaled(Duration host_elapsed) const;
  /// Moves the steady anchor to @p host, keeping ITS steady time continuous, then sets @p rate.
  void set_rate(SteadyTime host, double rate);

  Runtime& host_;
  double rate_ = 1.0;
  // ITS steady time = steady_anchor_its_ + (host steady − steady_anchor_host_) × rate_.
  SteadyTime steady_anchor_host_{};
  SteadyTime steady_anchor_its_{};
  bool anchored_ = false;
  std::optional<Sample> last_fix_;
  std::optional<Sample> rate_start_;  ///< the fix the current rate window began at
  unsigned resyncs_ = 0;
};

}  // namespace tb::clock
