#include "sim-client/view3d/feed.hpp"

namespace tb::client::view3d {

void ViewFeed::set_world(std::shared_ptr<const World> world) {
  std::lock_guard lock(mu_);
  world_ = std::move(world);
  interpolator_.clear();
}

std::shared_ptr<const World> ViewFeed::world() const {
  std::lock_guard lock(mu_);
  return world_;
}

void ViewFeed::push_frame(const wire::sim::StateFrame& frame, clock::SteadyTime arrival) {
  std::lock_guard lock(mu_);
  interpolator_.push(frame, arrival);
}

void ViewFeed::set_view(int own, const ViewChoice& choice, const HudStatus& status) {
  std::lock_guard lock(mu_);
  own_ = own;
  choice_ = choice;
  status_ = status;
}

void ViewFeed::set_signals(std::vector<wire::sim::SignalGroupState> signals) {
  std::lock_guard lock(mu_);
  signals_ = std::move(signals);
}

FrameInput ViewFeed::frame_at(clock::SteadyTime now, double fps) const {
  FrameInput in;
  {
    std::lock_guard lock(mu_);
    in.world = world_;
    in.own = own_;
    in.choice = choice_;
    in.status = status_;
    in.signals = signals_;
    if (auto s = interpolator_.sample(now)) {
      in.vehicles = std::move(s->vehicles);
      in.sim_time_ns = s->sim_time_ns;
    }
  }
  if (in.world && in.vehicles.size() > in.world->vehicles.size())
    in.vehicles.resize(in.world->vehicles.size());
  if (monitor_ != nullptr) {
    in.v2x_enabled = true;
    in.v2x = monitor_->picture(now);
  }
  in.fps = fps;
  return in;
}

}  // namespace tb::client::view3d
