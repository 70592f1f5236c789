#pragma once
/// @file Paces the physics: one World step every step_s of real time, or back to back.
///
/// Real-time steps are scheduled against absolute instants (start + n·step), so that late
/// callbacks do not accumulate drift: a late step is followed by the next one on time, and a
/// step that overran makes the following ones run at once until the schedule is met again.
/// Only when the loop falls more than kMaxLag behind (a suspended process, a debugger) does it
/// give up on catching up and restart the schedule from now, logging how much it skipped.
///
/// The first step waits until every scripted vehicle has a driver (Hub::scripted_without_driver,
/// at most Options::start_timeout), so that a scenario's scripts start with its time however
/// late their client comes. Then the World's warm-up steps (negative sim time, vehicles held on
/// their run-ups) go out like any other, but apply no controls and trace no `server.step`: the
/// drivers' latest controls go into the first physics step, after sim time 0.

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "common/clock/runtime.hpp"
#include "common/trace/tracer.hpp"
#include "sim-server/physics/world.hpp"
#include "sim-server/server/hub.hpp"

namespace tb::server {

/// A vehicle leaving (or regaining) the drivable lanes, for the log: index, station, where,
/// the lane it was last on.
std::string describe(const physics::OffRoadEvent& e);
/// The vehicles off the road now, for the final status line ("" when none).
std::string off_road_list(const physics::World& world);
/// Logs (warning when leaving) and traces (`server.off_road`) what the world's off-road
/// monitor saw in the last step.
void report_off_road(physics::World& world, trace::Tracer& tracer, std::int64_t at_ns);

class SimLoop {
 public:
  struct Options {
    /// As fast as possible instead of real time; each step waits (at most the driver timeout)
    /// until every driver has answered the previous State frame (Hub lockstep).
    bool fast = false;
    std::optional<double> duration_s;  ///< stop after this much sim time
    /// How long the first step waits for a driver on every scripted vehicle; zero: not at all.
    std::chrono::milliseconds start_timeout{0};
  };
  /// Runs @p fn soon, after pending I/O (asio::post in the program). Fast mode uses it, since
  /// a timer due "now" would starve the sockets.
  using Post = std::function<void(std::function<void()>)>;

  static constexpr std::chrono::seconds kMaxLag{1};
  /// While waiting for drivers: how often to look, and to say who is missing.
  static constexpr std::chrono::milliseconds kDriverPoll{10};
  /// Fast mode waits for a silent driver this much longer than the driver timeout.
  static constexpr std::chrono::milliseconds kWaitMargin{10};
  static constexpr std::chrono::seconds kWaitLogEvery{5};

  SimLoop(clock::Runtime& runtime, physics::World& world, Hub* hub, Options options, Post post,
          std::function<void()> on_finished = {});
  ~SimLoop();

  /// Starts stepping, once the scripted vehicles have their drivers.
  void start();
  void stop();
  bool running() const { return running_; }
  /// Started, but waiting for the drivers of scripted vehicles.
  bool waiting_for_drivers() const { return running_ && starting_; }
  /// Steps that started later than their scheduled instant by more than one step.
  std::uint64_t late_steps() const { return late_steps_; }
  std::uint64_t resyncs() const { return resyncs_; }
  /// Fast mode: steps that gave up waiting for a driver's controls.
  std::uint64_t driver_waits_timed_out() const { return waits_; }

 private:
  void wait_for_drivers();
  void begin_stepping();
  void step();
  void schedule_next();
  void post_step();
  bool drivers_ready() const;
  void drivers_changed();

  clock::Runtime& rt_;
  physics::World& world_;
  Hub* hub_;
  Options options_;
  Post post_;
  std::function<void()> on_finished_;
  clock::Duration step_;
  clock::SteadyTime start_{};
  std::uint64_t scheduled_ = 0;  ///< steps since start_
  std::uint64_t late_steps_ = 0;
  std::uint64_t resyncs_ = 0;
  bool running_ = false;
  bool starting_ = false;  ///< waiting for the scripted vehicles' drivers before the first step
  bool waiting_ = false;   ///< fast mode: a step waits for the drivers' controls
  std::uint64_t waits_ = 0;
  clock::SteadyTime waiting_since_{};
  clock::SteadyTime next_wait_log_{};
  std::optional<clock::TimerId> timer_;
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
};

}  // namespace tb::server
