#pragma once
/// @file The vehicle's signals from its CAN bus, decoded with the project's DBC
/// (common/can/vehicle.dbc), with alive-counter and checksum checks.

#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string_view>

#include "common/can/can_bus.hpp"
#include "common/can/dbc.hpp"
#include "common/clock/clock.hpp"
#include "common/util/expected.hpp"
#include "its-station/facilities/vehicle_data.hpp"

namespace tb::its::facilities {

/// What became of one frame.
enum class CanFrameResult : std::uint8_t {
  kAccepted,
  kUnknownId,        ///< not a message of the database (ignored, not an error)
  kWrongLength,      ///< DLC differs from the database's
  kBadChecksum,      ///< CRC-8 SAE J1850 over the other bytes does not match
  kRepeatedCounter,  ///< the same alive counter again: a stale or replayed frame
  kCounterJump,      ///< counter jumped by more than kMaxCounterGap: resynchronised, dropped
};
std::string_view to_string(CanFrameResult r);

/// Missing DBC messages or signals the decoder needs.
struct CanSchemaError {
  std::string detail;  ///< "message Dynamics has no signal YawRate"
};

/// Pure decoder: frames in, VehicleData out. Keeps per-message alive-counter state.
class CanVehicleDecoder {
 public:
  /// Up to this many lost frames in a row are tolerated (the counter moved by at most 1 + it).
  static constexpr unsigned kMaxCounterGap = 3;

  /// @p db must outlive the decoder: it keeps pointers to its messages and signals.
  static Expected<CanVehicleDecoder, CanSchemaError> create(const can::Database& db);

  /// Applies @p frame to the current state. @returns what happened to it.
  CanFrameResult apply(const can::CanFrame& frame, clock::SteadyTime now);
  const VehicleData& state() const { return state_; }

  struct Counters {
    std::uint64_t accepted = 0;
    std::uint64_t unknown = 0;
    std::uint64_t bad_length = 0;
    std::uint64_t bad_checksum = 0;
    std::uint64_t bad_counter = 0;
    std::uint64_t lost = 0;  ///< frames missing according to the alive counters
  };
  const Counters& counters() const { return counters_; }

 private:
  enum class Kind { kSpeed, kDynamics, kSteering, kPowertrain, kLights };
  struct Entry {
    const can::Message* message = nullptr;
    Kind kind{};
    const can::Signal* counter = nullptr;
    const can::Signal* checksum = nullptr;
    std::array<const can::Signal*, 8> signals{};
    /// Signals a DBC may leave out (a car without light bar and siren): null when absent.
    std::array<const can::Signal*, 2> optional_signals{};
    int last_counter = -1;
  };

  explicit CanVehicleDecoder(std::map<std::uint32_t, Entry> entries)
      : entries_(std::move(entries)) {}
  void decode(const Entry& e, std::span<const std::uint8_t> data);

  std::map<std::uint32_t, Entry> entries_;  ///< by CAN id (with the extended flag)
  VehicleData state_;
  Counters counters_;
};

/// VehicleDataProvider over a CanBus (SocketCAN or the UDP stand-in). The bus is read on
/// demand (CanBus::start_on_demand): current() takes in every frame queued since the last
/// read, at most once per kPollInterval, and the bus reads by itself every kBackstop. The
/// station needs its vehicle data only when it makes a CAM or evaluates LCRW (a few times per
/// fix), so it is no longer woken by each of the 100 frames a second (issue 33). Each accepted
/// frame updates the state and notifies the listeners when it is taken in.
class CanVehicleDataProvider final : public VehicleDataProvider {
 public:
  /// Reads closer together than this mostly find no new frame (they come every 10 ms at
  /// 100 Hz, and a read that finds none is a wasted system call); it bounds the reads of a
  /// burst of LCRW evaluations, one per received CAM, to a few per burst. The state is then
  /// at most this much older than the newest frame, against a CAM every 100 ms or more.
  static constexpr clock::Duration kPollInterval = std::chrono::milliseconds{5};
  /// The longest a frame waits in the socket when nobody asks (before the first fix, say).
  static constexpr std::chrono::milliseconds kBackstop{250};

  CanVehicleDataProvider(can::CanBus& bus, CanVehicleDecoder decoder, const clock::Clock& clock);
  void start();
  const CanVehicleDecoder& decoder() const { return decoder_; }
  /// Reads of the bus made by current() so far.
  std::uint64_t polls() const { return polls_; }

 private:
  void take_in() const override;
  void on_frame(const can::CanFrame& frame);

  can::CanBus& bus_;
  CanVehicleDecoder decoder_;
  const clock::Clock& clock_;
  bool warned_bad_ = false;
  mutable std::optional<clock::SteadyTime> last_poll_;
  mutable std::uint64_t polls_ = 0;
  mutable bool polling_ = false;
};

}  // namespace tb::its::facilities
