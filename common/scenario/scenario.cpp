#include "common/scenario/scenario.hpp"

#include <algorithm>

namespace tb::scenario {

double SignalPlan::cycle_s() const {
  double total = 0.0;
  for (const SignalPhase& p : phases)
    total += p.duration_s + amber_s + all_red_s + red_amber_s;
  return total;
}

const Vehicle* Scenario::find_vehicle(std::string_view id) const {
  const auto it =
      std::find_if(vehicles.begin(), vehicles.end(), [&](const Vehicle& v) { return v.id == id; });
  return it == vehicles.end() ? nullptr : &*it;
}

const Vehicle* Scenario::find_station(std::uint32_t station_id) const {
  const auto it = std::find_if(vehicles.begin(), vehicles.end(),
                               [&](const Vehicle& v) { return v.station_id == station_id; });
  return it == vehicles.end() ? nullptr : &*it;
}

const Rsu* Scenario::find_rsu(std::uint32_t station_id) const {
  const auto it = std::find_if(rsus.begin(), rsus.end(),
                               [&](const Rsu& r) { return r.station_id == station_id; });
  return it == rsus.end() ? nullptr : &*it;
}

}  // namespace tb::scenario
