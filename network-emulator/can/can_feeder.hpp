#pragma once
/// @file CanFeeder: one station's CAN bus traffic, encoded as the DBC file describes.
///
/// Each DBC message is sent periodically in sim time (like GpsAgent's epochs): a message is
/// due on the first state at or after its next period boundary, and describes that state.
/// Messages whose GenMsgCycleTime is under 100 ms form the "dynamics" group, the others the
/// "body" group; the scenario's rates.can_dynamics_hz / can_body_hz set each group's rate.
/// Every message's AliveCounter goes up by one per frame and its Checksum is CRC-8 SAE J1850
/// over the other bytes (common/can/vehicle.dbc). No sockets: the caller sends the frames.

#include <array>
#include <cstdint>
#include <memory>
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

/// One signal's encoding worked out once, from the signal's own tb::can::Signal::insert_raw:
/// which bits of which bytes its raw value goes to, and its raw range. At 100k states/s the
/// feeder encodes 2.5 million signals a second; per bit and recomputing the range each time,
/// that was a tenth of the emulator's CPU. Gives the bytes and raw values of
/// tb::can::Signal::encode exactly (tests/can_feeder_test.cpp).
class SignalPlan {
 public:
  /// For frames of @p dlc bytes.
  SignalPlan(const tb::can::Signal& signal, std::size_t dlc);
  /// As tb::can::Signal::to_raw.
  std::int64_t to_raw(double physical) const;
  /// As tb::can::Signal::insert_raw.
  void insert_raw(std::int64_t raw, std::span<std::uint8_t> data) const;
  void encode(double physical, std::span<std::uint8_t> data) const {
    insert_raw(to_raw(physical), data);
  }
  std::int64_t raw_max() const { return hi_; }

 private:
  /// Bits [shift, shift + bits) of one byte take bits [raw_shift, raw_shift + bits) of raw.
  struct Piece {
    std::uint8_t byte, shift, raw_shift, bits;
  };
  // In place, not on the heap: 64 bits touch at most 9 bytes, one piece per byte.
  std::array<Piece, 9> pieces_{};
  std::size_t piece_count_ = 0;
  bool clamp_;
  double minimum_, maximum_, offset_, factor_;
  std::int64_t lo_, hi_;
  double lo_d_, hi_d_;
};

class CanFeeder {
 public:
  /// Checks that every signal of every message has a source in a VehicleState.
  static Expected<CanFeeder, FeederError> create(const tb::can::Database& db,
                                                 const FeederConfig& config);
  /// A feeder for another vehicle with the same database and rates, sharing this one's
  /// messages and encodings (read only), with its own counters and due times; @p config's
  /// rates must be this feeder's. With 1000 stations one shared copy stays in the cache where
  /// 1000 copies did not.
  CanFeeder sibling(const FeederConfig& config) const;
  bool same_rates(const FeederConfig& config) const {
    return config.dynamics_hz == config_.dynamics_hz && config.body_hz == config_.body_hz;
  }

  /// Frames due at this state's sim time (valid until the next call); often none.
  std::span<const tb::can::CanFrame> on_state(const wire::VehicleState& state);

  std::int64_t period_ns(std::string_view message) const;
  std::uint64_t frames() const { return frames_total_; }

 private:
  using Source = double (*)(const wire::VehicleState&, const FeederConfig&);
  struct Field {
    SignalPlan plan;
    Source source;
  };
  /// A message as the feeder sends it; the same for every feeder of one database and rates.
  struct Schedule {
    const tb::can::Message* message;
    std::int64_t period_ns;
    std::vector<Field> fields;
    std::optional<SignalPlan> counter;
    const tb::can::Signal* checksum = nullptr;
  };
  /// A message's state in one feeder.
  struct Due {
    std::optional<std::int64_t> next_due_ns;
    std::uint8_t alive = 0;
  };

  CanFeeder() = default;
  void encode(const Schedule& s, Due& d, const wire::VehicleState& state,
              tb::can::CanFrame& out) const;

  FeederConfig config_;
  std::shared_ptr<const std::vector<Schedule>> schedules_;
  std::vector<Due> due_state_;
  std::vector<tb::can::CanFrame> due_;
  std::uint64_t frames_total_ = 0;
};

}  // namespace tb::emu::can
