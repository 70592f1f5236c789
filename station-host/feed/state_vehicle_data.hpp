#pragma once
/// @file A pooled station's vehicle signals, taken from the state stream instead of a CAN bus.

#include <cstdint>
#include <optional>

#include "common/clock/clock.hpp"
#include "common/wire/vehicle_state.hpp"
#include "its-station/facilities/vehicle_data.hpp"

namespace tb::host {

/// What a full station's CanVehicleDecoder makes of the frames the emulator's CAN feeder
/// encodes from @p state (network-emulator/can/can_feeder.cpp), without the DBC's
/// quantisation: the same signals, units, signs and standstill rule. @p steering_ratio turns the
/// road-wheel angle into the steering-wheel angle, as the feeder does with the vehicle model's.
its::facilities::VehicleData vehicle_data_of(const wire::VehicleState& state, double steering_ratio,
                                             clock::SteadyTime received);

/// VehicleDataProvider of one pooled station: publishes at the scenario's CAN dynamics rate, on
/// whole periods of sim time (as the feeder sends its dynamics frames).
class StateVehicleData final : public its::facilities::VehicleDataProvider {
 public:
  /// @throws std::invalid_argument for a rate ≤ 0.
  StateVehicleData(double rate_hz, double steering_ratio, const clock::Clock& clock);
  void on_state(const wire::VehicleState& state);
  std::uint64_t updates() const { return updates_; }

 private:
  std::int64_t period_ns_;
  double steering_ratio_;
  const clock::Clock& clock_;
  std::optional<std::int64_t> next_ns_;
  std::uint64_t updates_ = 0;
};

}  // namespace tb::host
