#include "common/clock/gnss_disciplined_runtime.hpp"

#include <chrono>
#include <cmath>

namespace tb::clock {

namespace {

Duration times(Duration d, double factor) {
  return Duration{std::llround(static_cast<double>(d.count()) * factor)};
}

}  // namespace

Duration GnssDisciplinedRuntime::scaled(Duration host_elapsed) const {
  return rate_ == 1.0 ? host_elapsed : times(host_elapsed, rate_);
}

SteadyTime GnssDisciplinedRuntime::its_steady(SteadyTime host) const {
  if (!anchored_)
    return host;
  return steady_anchor_its_ + scaled(host - steady_anchor_host_);
}

WallTime GnssDisciplinedRuntime::its_wall(SteadyTime host) const {
  if (!last_fix_)
    return host_.wall_now() +
           std::chrono::duration_cast<WallClock::duration>(host - host_.steady_now());
  return last_fix_->gnss +
         std::chrono::duration_cast<WallClock::duration>(scaled(host - last_fix_->host));
}

WallTime GnssDisciplinedRuntime::to_its(WallTime host_wall) const {
  // The host's wall clock only locates the stamp against now; the world's time comes from the
  // fix, so an epoch far from the host's date (a pinned start_time) does not matter.
  const SteadyTime host_now = host_.steady_now();
  return its_wall(host_now - std::chrono::duration_cast<Duration>(host_.wall_now() - host_wall));
}

void GnssDisciplinedRuntime::set_rate(SteadyTime host, double rate) {
  steady_anchor_its_ = its_steady(host);
  steady_anchor_host_ = host;
  anchored_ = true;
  rate_ = rate;
}

void GnssDisciplinedRuntime::on_fix(WallTime gnss_time) {
  const SteadyTime now = host_.steady_now();
  const Sample fix{now, gnss_time};
  if (!last_fix_) {
    set_rate(now, 1.0);
    last_fix_ = fix;
    rate_start_ = fix;
    return;
  }
  const auto error = gnss_time - its_wall(now);
  if (std::chrono::abs(error) > kResyncThreshold) {
    ++resyncs_;
    set_rate(now, 1.0);
    last_fix_ = fix;
    rate_start_ = fix;
    return;
  }
  const bool gap = now - last_fix_->host > kMaxFixGap;
  last_fix_ = fix;
  if (gap) {
    rate_start_ = fix;  // a feed that paused (the simulation waiting for drivers) is no rate
    return;
  }
  const auto host_span = now - rate_start_->host;
  if (host_span < kRateWindow)
    return;
  const double measured = std::chrono::duration<double>(gnss_time - rate_start_->gnss).count() /
                          std::chrono::duration<double>(host_span).count();
  rate_start_ = fix;
  if (!(measured >= 1.0 / kMaxRate && measured <= kMaxRate))
    return;
  set_rate(now, measured);
}

TimerId GnssDisciplinedRuntime::schedule_at(SteadyTime when, TimerCallback cb) {
  if (!anchored_)
    return host_.schedule_at(when, std::move(cb));
  const auto its_ahead = when - steady_anchor_its_;
  const Duration host_ahead = rate_ == 1.0 ? its_ahead : times(its_ahead, 1.0 / rate_);
  return host_.schedule_at(steady_anchor_host_ + host_ahead, std::move(cb));
}

}  // namespace tb::clock
