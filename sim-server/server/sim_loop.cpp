#include "sim-server/server/sim_loop.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <spdlog/fmt/ranges.h>

#include <cmath>

#include "common/trace/tracer.hpp"

namespace tb::server {

SimLoop::SimLoop(clock::Runtime& runtime, physics::World& world, Hub* hub, Options options,
                 Post post, std::function<void()> on_finished)
    : rt_(runtime),
      world_(world),
      hub_(hub),
      options_(options),
      post_(std::move(post)),
      on_finished_(std::move(on_finished)),
      step_(std::chrono::nanoseconds(std::llround(world.step_s() * 1e9))) {
  if (hub_ != nullptr && options_.fast)
    hub_->on_drivers_changed([this] { drivers_changed(); });
}

SimLoop::~SimLoop() {
  *alive_ = false;
  if (hub_ != nullptr && options_.fast)
    hub_->on_drivers_changed({});
  stop();
}

void SimLoop::start() {
  if (running_)
    return;
  running_ = true;
  starting_ = true;
  waiting_since_ = rt_.steady_now();
  next_wait_log_ = waiting_since_;
  wait_for_drivers();
}

void SimLoop::wait_for_drivers() {
  if (!running_)
    return;
  const auto missing =
      hub_ != nullptr ? hub_->scripted_without_driver() : std::vector<std::string>{};
  const auto now = rt_.steady_now();
  const auto waited = std::chrono::duration_cast<std::chrono::milliseconds>(now - waiting_since_);
  if (!missing.empty() && options_.start_timeout.count() > 0 && waited < options_.start_timeout) {
    if (now >= next_wait_log_) {
      spdlog::info("waiting for the driver of {} (scripted) before the first step",
                   fmt::join(missing, ", "));
      next_wait_log_ = now + kWaitLogEvery;
    }
    timer_ = rt_.schedule_at(now + kDriverPoll, [this] {
      timer_.reset();
      wait_for_drivers();
    });
    return;
  }
  if (!missing.empty() && options_.start_timeout.count() > 0) {
    spdlog::warn("no driver for {} after {} s: starting without (they brake to a stop)",
                 fmt::join(missing, ", "), waited.count() / 1000.0);
  } else if (waited.count() > 0) {
    spdlog::info("every scripted vehicle has its driver (after {} ms)", waited.count());
  }
  begin_stepping();
}

void SimLoop::begin_stepping() {
  starting_ = false;
  if (world_.warming_up()) {
    spdlog::info(
        "warm-up: sim time from {:.2f} s, every vehicle held on its run-up to its spawn "
        "pose; the physics starts at sim time 0",
        static_cast<double>(world_.sim_time_ns()) * 1e-9);
  }
  start_ = rt_.steady_now();
  scheduled_ = 0;
  schedule_next();
}

void SimLoop::stop() {
  running_ = false;
  if (timer_) {
    rt_.cancel(*timer_);
    timer_.reset();
  }
}

void SimLoop::schedule_next() {
  if (!running_)
    return;
  if (options_.fast) {
    if (!drivers_ready()) {
      // Lockstep: the drivers' controls for the state just sent go into the next step. Past
      // the driver timeout, so that the step that follows brakes a silent driver's car and
      // later steps do not wait for it.
      waiting_ = true;
      timer_ = rt_.schedule_at(rt_.steady_now() + std::chrono::duration_cast<clock::Duration>(
                                                      Hub::kDriverTimeout + kWaitMargin),
                               [this] {
                                 timer_.reset();
                                 if (!waiting_)
                                   return;
                                 waiting_ = false;
                                 ++waits_;
                                 step();
                               });
      return;
    }
    post_step();
    return;
  }
  ++scheduled_;
  clock::SteadyTime due = start_ + static_cast<std::int64_t>(scheduled_) * step_;
  const auto now = rt_.steady_now();
  if (now - due > kMaxLag) {
    ++resyncs_;
    spdlog::warn("physics fell {} ms behind real time: restarting the schedule",
                 std::chrono::duration_cast<std::chrono::milliseconds>(now - due).count());
    start_ = now;
    scheduled_ = 0;
    due = now;
  }
  timer_ = rt_.schedule_at(due, [this, due] {
    timer_.reset();
    if (rt_.steady_now() - due > step_)
      ++late_steps_;
    step();
  });
}

void SimLoop::post_step() {
  post_([this, alive = std::weak_ptr<bool>(alive_)] {
    if (alive.lock() && running_)
      step();
  });
}

bool SimLoop::drivers_ready() const {
  if (hub_ == nullptr)
    return true;
  return hub_->drivers_answered();
}

void SimLoop::drivers_changed() {
  if (starting_ || !waiting_ || !running_ || !drivers_ready())
    return;
  waiting_ = false;
  if (timer_) {
    rt_.cancel(*timer_);
    timer_.reset();
  }
  post_step();
}

std::string describe(const physics::OffRoadEvent& e) {
  std::string s = fmt::format("vehicle {} (station {}) at ({:.1f}, {:.1f}, {:.1f})", e.vehicle,
                              e.station_id, e.x, e.y, e.z);
  if (!e.last_road.empty()) {
    s += fmt::format(", {} road {} lane {} s {:.1f}", e.left ? "last on" : "on", e.last_road,
                     e.last_lane, e.last_s);
  }
  return s;
}

std::string off_road_list(const physics::World& world) {
  const auto& m = world.off_road();
  std::string out;
  for (std::size_t i = 0; i < world.size(); ++i) {
    if (m.off(i))
      out += (out.empty() ? ": " : "; ") + describe(m.where(i));
  }
  return out;
}

void report_off_road(physics::World& world, trace::Tracer& tracer, std::int64_t at_ns) {
  for (const auto& e : world.off_road().take_events()) {
    if (e.left) {
      spdlog::warn("{} left every drivable lane; {} vehicle(s) off the road now", describe(e),
                   world.off_road().off_now());
    } else {
      spdlog::info("{} is back on a drivable lane", describe(e));
    }
    if (tracer.enabled()) {
      tracer.record_at(at_ns, "server.off_road",
                       {{"station", e.station_id},
                        {"tick", e.tick},
                        {"left", e.left},
                        {"x", e.x},
                        {"y", e.y},
                        {"z", e.z}});
    }
  }
}

void SimLoop::step() {
  if (!running_)
    return;
  // A warm-up step computes nothing and applies no controls: neither the hub's nor a p1 record.
  const bool physics = !world_.warming_up();
  if (hub_ && physics)
    hub_->before_step();
  auto& tracer = trace::global();
  const std::uint64_t tick = world_.tick() + 1;
  const std::int64_t start_ns = clock::to_unix_ns(rt_.wall_now());
  world_.step(start_ns);
  if (!physics && !world_.warming_up())
    spdlog::info("sim time 0 at tick {}: the physics starts", world_.tick());
  // p1 of the delay table (docs/tracing.md): the step's start and how long it took.
  if (physics && tracer.enabled()) {
    tracer.record_at(start_ns, "server.step",
                     {{"tick", tick},
                      {"dur_ns", clock::to_unix_ns(rt_.wall_now()) - start_ns},
                      {"vehicles", world_.size()}});
  }
  report_off_road(world_, tracer, start_ns);
  if (hub_)
    hub_->after_step();
  if (options_.duration_s && world_.sim_time_ns() >= std::llround(*options_.duration_s * 1e9)) {
    running_ = false;
    spdlog::info("scenario duration reached after {} steps", world_.tick());
    if (on_finished_)
      on_finished_();
    return;
  }
  schedule_next();
}

}  // namespace tb::server
