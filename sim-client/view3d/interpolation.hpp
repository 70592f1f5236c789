#pragma once
/// @file Smooth motion between physics steps: the view renders at the display rate and draws
/// each vehicle between the last two states the server sent, never past the latest one.
///
/// Which instant to draw: arrivals are mapped onto sim time by the smallest (arrival − sim
/// time) seen over the last second — the delay of the luckiest frame, so network and scheduling
/// jitter only ever make a frame late, never early. The drawn instant is one physics step
/// behind that estimate of "now" in sim time, clamped to [previous, latest]: at most one step
/// behind, and when a frame is late the view holds at the latest state instead of guessing.

#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "common/clock/clock.hpp"
#include "common/wire/sim_protocol.hpp"

namespace tb::client::view3d {

/// @p a + (b − a)·alpha for every continuous field; the discrete ones (controls, lights, gear,
/// tick) are @p b's. Yaw takes the short way round.
wire::VehicleState interpolate(const wire::VehicleState& a, const wire::VehicleState& b,
                               double alpha);

class StateInterpolator {
 public:
  explicit StateInterpolator(clock::Duration offset_window = std::chrono::seconds{1})
      : window_(offset_window) {}

  /// A state frame that arrived at @p arrival. A frame whose sim time does not advance (a
  /// server that restarted, a reconnection) starts the history afresh.
  void push(const wire::sim::StateFrame& frame, clock::SteadyTime arrival);
  void clear();

  struct Sample {
    std::int64_t sim_time_ns = 0;  ///< the instant drawn
    double alpha = 1.0;            ///< 0 = previous frame, 1 = latest
    std::uint64_t latest_tick = 0;
    std::vector<wire::VehicleState> vehicles;
  };
  /// The vehicles as they were at the instant to draw at @p now; empty before any frame.
  std::optional<Sample> sample(clock::SteadyTime now) const;

 private:
  struct Offset {
    clock::SteadyTime arrival;
    std::int64_t ns;  ///< arrival (steady ns) − sim time
  };
  clock::Duration window_;
  std::optional<wire::sim::StateFrame> previous_;
  std::optional<wire::sim::StateFrame> latest_;
  std::deque<Offset> min_;  ///< increasing ns: front is the window's minimum
};

}  // namespace tb::client::view3d
