#pragma once
/// @file The hand-over between the program's thread (Asio loop: server session, input, MQTT
/// picture) and the render thread: the world, the state frames as they arrive (timed on
/// arrival, for the interpolation) and the view's choices go in; the render thread takes out
/// one FrameInput per frame, interpolated at the moment it draws.

#include <memory>
#include <mutex>

#include "common/clock/clock.hpp"
#include "common/wire/sim_protocol.hpp"
#include "sim-client/v2x/monitor.hpp"
#include "sim-client/view3d/frame_input.hpp"
#include "sim-client/view3d/interpolation.hpp"

namespace tb::client::view3d {

class ViewFeed {
 public:
  /// @p monitor (may be null: no --mqtt) is read by the render thread; it is thread-safe.
  explicit ViewFeed(const v2x::V2xMonitor* monitor = nullptr) : monitor_(monitor) {}

  void set_world(std::shared_ptr<const World> world);
  std::shared_ptr<const World> world() const;
  void push_frame(const wire::sim::StateFrame& frame, clock::SteadyTime arrival);
  void set_view(int own, const ViewChoice& choice, const HudStatus& status);
  /// The latest traffic lights (every junction's groups), drawn from the next frame on.
  void set_signals(std::vector<wire::sim::SignalGroupState> signals);

  /// What to draw at @p now. @p fps is the render thread's measured rate, for the HUD.
  FrameInput frame_at(clock::SteadyTime now, double fps) const;

 private:
  const v2x::V2xMonitor* monitor_;
  mutable std::mutex mu_;
  std::shared_ptr<const World> world_;
  StateInterpolator interpolator_;
  int own_ = -1;
  ViewChoice choice_;
  HudStatus status_;
  std::vector<wire::sim::SignalGroupState> signals_;
};

}  // namespace tb::client::view3d
