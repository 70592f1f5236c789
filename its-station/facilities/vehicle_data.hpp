#pragma once
/// @file The vehicle's own signals (speed, yaw rate, accelerations, steering, pedals, lights),
/// as the CA service needs them, and the interface it takes them from.

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "common/clock/clock.hpp"

namespace tb::its::facilities {

/// Bits of VehicleData::exterior_lights, in the order of CDD ExteriorLights (TS 102 894-2).
namespace lights {
inline constexpr std::uint8_t kLowBeam = 1 << 0;
inline constexpr std::uint8_t kHighBeam = 1 << 1;
inline constexpr std::uint8_t kLeftTurnSignal = 1 << 2;
inline constexpr std::uint8_t kRightTurnSignal = 1 << 3;
inline constexpr std::uint8_t kDaytimeRunning = 1 << 4;
inline constexpr std::uint8_t kReverse = 1 << 5;
inline constexpr std::uint8_t kFog = 1 << 6;
inline constexpr std::uint8_t kParking = 1 << 7;
}  // namespace lights

/// SI units; signs as in the CDD (positive to the left, forward, up). Unknown = empty.
struct VehicleData {
  clock::SteadyTime received{};
  std::optional<double> speed_mps;  ///< wheel-based, negative when reversing
  std::optional<double> yaw_rate_dps;
  std::optional<double> longitudinal_acceleration_mps2;
  std::optional<double> lateral_acceleration_mps2;
  std::optional<double> steering_wheel_angle_deg;
  std::optional<bool> brake_pedal;
  std::optional<bool> gas_pedal;
  std::optional<bool> reversing;
  std::optional<std::uint8_t> exterior_lights;  ///< lights:: bits
  /// A special vehicle's light bar and siren (CDD LightBarSirenInUse); empty when the vehicle's
  /// bus does not carry them.
  std::optional<bool> light_bar;
  std::optional<bool> siren;
};

/// Source of VehicleData: the CAN reader in the station, a test's hand in unit tests.
class VehicleDataProvider {
 public:
  using Listener = std::function<void(const VehicleData&)>;
  virtual ~VehicleDataProvider() = default;
  /// The newest vehicle data. A provider that reads its source on demand takes in what the
  /// source has received first (take_in), so the answer is as fresh as at arrival.
  const std::optional<VehicleData>& current() const {
    take_in();
    return current_;
  }
  /// Listeners of a provider that reads on demand hear of updates when current() or the
  /// provider's own schedule takes them in, not at their arrival.
  void on_update(Listener l) { listeners_.push_back(std::move(l)); }

 protected:
  /// Reads what the source has received and publish()es it; called by current(). A provider
  /// whose source is read this way (CanVehicleDataProvider) is not woken for each update.
  /// Logically const: current() answers the source's newest state either way.
  virtual void take_in() const {}

  void publish(const VehicleData& d) {
    current_ = d;
    for (auto& l : listeners_)
      l(d);
  }

 private:
  std::optional<VehicleData> current_;
  std::vector<Listener> listeners_;
};

class InjectedVehicleDataProvider final : public VehicleDataProvider {
 public:
  void inject(const VehicleData& d) { publish(d); }
};

}  // namespace tb::its::facilities
