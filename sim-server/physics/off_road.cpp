#include "sim-server/physics/off_road.hpp"

#include <algorithm>

namespace tb::server::physics {

OffRoadMonitor::OffRoadMonitor(const map::ScenarioMap& map, std::uint64_t period)
    : map_(map), period_(std::max<std::uint64_t>(1, period)) {}

void OffRoadMonitor::update(std::uint64_t tick, std::span<const wire::VehicleState> states) {
  if (status_.size() < states.size())
    status_.resize(states.size());
  // Vehicle i is due when (i + tick) % period == 0: i = (period - tick % period) % period, then
  // every period-th.
  for (std::size_t i = (period_ - tick % period_) % period_; i < states.size(); i += period_)
    check(i, tick, states[i]);
}

void OffRoadMonitor::check(std::size_t i, std::uint64_t tick, const wire::VehicleState& s) {
  Status& st = status_[i];
  const auto& net = map_.network();
  const std::span<const map::odr::LaneRef> prefer =
      st.lane.road >= 0 ? std::span<const map::odr::LaneRef>(&st.lane, 1)
                        : std::span<const map::odr::LaneRef>();
  const auto at = map_.locator().locate(s.position[0], s.position[1], s.position[2], prefer);
  bool drivable = false;
  if (at) {
    const auto& road = net.roads[static_cast<std::size_t>(at->ref.road)];
    const auto* lane = road.sections[at->section].lane(at->ref.lane);
    drivable = lane != nullptr && lane->drivable;
  }
  if (drivable) {
    st.lane = at->ref;
    st.s = at->s;
  }
  const bool off = !drivable;
  if (st.seen && off == st.off)
    return;
  const bool first = !st.seen;
  st.seen = true;
  if (first && !off)
    return;  // on the road from the start: nothing to say
  st.off = off;
  OffRoadEvent e;
  e.vehicle = i;
  e.station_id = s.station_id;
  e.left = off;
  e.tick = tick;
  e.x = s.position[0];
  e.y = s.position[1];
  e.z = s.position[2];
  if (st.lane.road >= 0) {
    e.last_road = net.roads[static_cast<std::size_t>(st.lane.road)].id;
    e.last_lane = st.lane.lane;
    e.last_s = st.s;
  }
  if (off) {
    ++off_now_;
    ++departures_;
    st.last_event = e;
  } else {
    --off_now_;
  }
  events_.push_back(std::move(e));
}

std::vector<OffRoadEvent> OffRoadMonitor::take_events() {
  std::vector<OffRoadEvent> out;
  out.swap(events_);
  return out;
}

}  // namespace tb::server::physics
