#pragma once
/// @file A Runtime whose clocks can be held at one instant while work that happens at one
/// instant runs: station-host hands one received frame to hundreds of stations, and each read
/// the clock several times (a vDSO call of ~70 ns on a virtual machine: 9 % of the host's CPU
/// at 300 stations, issue 33). Held, they all receive the frame at the instant it was taken up,
/// which is what a broadcast reception is.

#include <optional>
#include <utility>

#include "common/clock/runtime.hpp"

namespace tb::clock {

class HeldClockRuntime final : public Runtime {
 public:
  /// @p inner keeps the timers and the clocks; it must outlive this object.
  explicit HeldClockRuntime(Runtime& inner) : inner_(inner) {}

  SteadyTime steady_now() const override { return depth_ > 0 ? steady_ : inner_.steady_now(); }
  WallTime wall_now() const override { return depth_ > 0 ? wall_ : inner_.wall_now(); }
  TimerId schedule_at(SteadyTime when, TimerCallback cb) override {
    return inner_.schedule_at(when, std::move(cb));
  }
  void cancel(TimerId id) override { inner_.cancel(id); }

  /// Holds the clocks at the current instant until it goes; a hold inside another keeps the
  /// outer one's instant.
  class Hold {
   public:
    explicit Hold(HeldClockRuntime& rt, std::optional<WallTime> at = std::nullopt) : rt_(&rt) {
      if (rt_->depth_++ == 0) {
        rt_->steady_ = rt_->inner_.steady_now();
        rt_->wall_ = rt_->inner_.wall_now();
        if (at && *at < rt_->wall_) {
          rt_->steady_ -= rt_->wall_ - *at;
          rt_->wall_ = *at;
        }
      }
    }
    ~Hold() {
      if (rt_ != nullptr)
        --rt_->depth_;
    }
    Hold(Hold&& o) noexcept : rt_(std::exchange(o.rt_, nullptr)) {}
    Hold(const Hold&) = delete;
    Hold& operator=(const Hold&) = delete;
    Hold& operator=(Hold&&) = delete;

   private:
    HeldClockRuntime* rt_;
  };
  [[nodiscard]] Hold hold() { return Hold(*this); }
  /// Holds the clocks at @p host_wall, an instant of the inner wall clock already past (a
  /// kernel receive stamp): what is taken up is taken up as of when it arrived, however late
  /// the process got to it (issue 33: a fix read 60 ms late put a pooled station's ITS clock
  /// 60 ms behind, and its neighbours' packets beyond the 40 ms future tolerance). An instant
  /// not yet past holds now.
  [[nodiscard]] Hold hold_at(WallTime host_wall) { return Hold(*this, host_wall); }

 private:
  Runtime& inner_;
  int depth_ = 0;
  SteadyTime steady_{};
  WallTime wall_{};
};

}  // namespace tb::clock
