#pragma once
/// @file What a driver commands: the controls plus the lights the driver switches.

#include <cstdint>

#include "common/wire/vehicle_state.hpp"

namespace tb::client {

struct DriverCommand {
  wire::Controls controls;
  std::uint16_t lights = 0;  ///< tb::wire::Light bits switched by the driver
  bool operator==(const DriverCommand&) const = default;
};

/// Toggles one of the driver's light switches. Indicators and hazard exclude each other as on
/// a real stalk; high beam needs nothing else on.
void toggle_light(std::uint16_t& lights, wire::Light which);

}  // namespace tb::client
