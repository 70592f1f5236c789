#pragma once
/// @file CanFeeder: one station's CAN bus traffic, encoded as the DBC file describes.
///
/// Each DBC message is sent periodically in sim time (like GpsAgent's epochs): a message is
/// due on the first state at or after its next period boundary, and describes that state.
/// Messages whose GenMsgCycleTime is under 100 ms form the "dynamics" group, the others the
/// "body" group; the scenario's rates.can_dynamics_hz / can_body_hz set each group's rate.
/// Every message's AliveCounter goes up by one per frame and its Checksum is CRC-8 SAE J1850
/// over the other bytes (common/can/vehicle.dbc). No sockets: the caller sends the frames.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/can/dbc.hpp"
#include "common/can/frame.hpp"
#include "common/util/expected.hpp"
#include "common/wire/vehicle_state.hpp"

namespace tb::emu::can {

struct FeederConfig {
  double dynamics_hz = 100.0;
  double body_hz = 10.0;
  double steering_ratio = 14.8;  ///< steering-wheel angle / road-wheel angle
};

enum class FeederErrc { kUnknownSignal, kNoCycleTime, kBadChecksumSignal, kBadRate };
std::string_view to_string(FeederErrc e);

struct FeederError {
  FeederErrc code;
  std::string detail;  ///< names the message and signal
  std::string message() const;
};

/// Signals the feeder knows how to fill from a VehicleState, for documentation and checks.
std::span<const std::string_view> known_signals();

class CanFeeder {
 public:
  /// Checks that every signal of every message has a source in a VehicleState.
  static Expected<CanFeeder, FeederError> create(const tb::can::Database& db,
                                                 const FeederConfig& config);

  /// Frames due at this state's sim time (valid until the next call); often none.
  std::span<const tb::can::CanFrame> on_state(const wire::VehicleState& state);

  std::int64_t period_ns(std::string_view message) const;
  std::uint64_t frames() const { return frames_total_; }

 private:
  using Source = double (*)(const wire::VehicleState&, const FeederConfig&);
  struct Field {
    const tb::can::Signal* signal;
    Source source;
  };
  struct Schedule {
    const tb::can::Message* message;
    std::int64_t period_ns;
    std::optional<std::int64_t> next_due_ns;
    std::vector<Field> fields;
    const tb::can::Signal* counter = nullptr;
    const tb::can::Signal* checksum = nullptr;
    std::uint8_t alive = 0;
  };

  CanFeeder() = default;
  void encode(Schedule& s, const wire::VehicleState& state, tb::can::CanFrame& out);

  FeederConfig config_;
  std::vector<Schedule> schedules_;
  std::vector<tb::can::CanFrame> due_;
  std::uint64_t frames_total_ = 0;
};

}  // namespace tb::emu::can
