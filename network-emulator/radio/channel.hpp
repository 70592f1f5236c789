#pragma once
/// @file The radio channel model: per-frame delivery decisions from sender–receiver distance.
///
/// Used by the veth stand-in medium and by the hwsim frame handler alike, so that both media
/// lose, delay and count frames the same way. Positions come from a PositionSource that the
/// emulator feeds from the vehicle-state stream.

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <random>
#include <string_view>
#include <utility>

#include <nlohmann/json_fwd.hpp>

#include "common/clock/clock.hpp"
#include "common/scenario/channel_range.hpp"
#include "common/scenario/scenario.hpp"
#include "common/wire/vehicle_state.hpp"

namespace tb::emu::radio {

/// The ETSI StationID of a vehicle (scenario "station_id").
using StationId = std::uint32_t;

struct StationPosition {
  std::array<double, 3> position{};  ///< local ENU frame, m
  std::int64_t sim_time_ns = 0;      ///< sim time of the state the position came from
};

/// Where each station is now.
class PositionSource {
 public:
  virtual ~PositionSource() = default;
  virtual std::optional<StationPosition> position(StationId id) const = 0;
};

/// The latest position of every station, fed from vehicle states. Not thread-safe: the
/// emulator updates and reads it from one io_context.
class PositionTable final : public PositionSource {
 public:
  void set(StationId id, const StationPosition& p) { table_[id] = p; }
  /// Keeps the state only if it is not older than the one held: UDP may reorder datagrams.
  /// Returns whether it was taken.
  bool update(const wire::VehicleState& s);
  std::optional<StationPosition> position(StationId id) const override;
  std::size_t size() const { return table_.size(); }

 private:
  std::map<StationId, StationPosition> table_;
};

enum class DropReason : std::uint8_t {
  kOutOfRange,        ///< range model: farther than range_m
  kBelowSensitivity,  ///< path-loss models: received power under sensitivity_dbm
  kPacketError,       ///< random loss at packet_error_rate on a link that is in range
  kUnknownPosition,   ///< no position yet for the sender or the receiver
};
inline constexpr std::size_t kDropReasonCount = 4;
std::string_view to_string(DropReason r);
std::string_view to_string(scenario::ChannelModel::Kind k);

struct Decision {
  bool deliver = false;
  DropReason reason = DropReason::kOutOfRange;  ///< meaningful only when !deliver
  std::optional<double> distance_m;             ///< empty when a position is unknown
  std::optional<double> rx_power_dbm;           ///< path-loss models only
  clock::Duration delay{};                      ///< delay_ms plus jitter, when delivered
};

/// Counters of one directed link (sender → receiver). sent == delivered + sum(dropped).
struct LinkStats {
  std::uint64_t sent = 0;
  std::uint64_t delivered = 0;
  std::array<std::uint64_t, kDropReasonCount> dropped{};

  std::uint64_t dropped_total() const;
  LinkStats& operator+=(const LinkStats& o);
};

/// Path loss in dB for the log-distance or two-ray model (common/scenario/channel_range.hpp, one
/// definition with the range the operator's view draws).
using scenario::path_loss_db;

/// Decides, for each frame and receiver, whether the frame arrives and after what delay, and
/// counts the outcome per link. Reproducible: the same seed and the same sequence of calls give
/// the same decisions on every platform.
class Channel {
 public:
  /// @throws std::invalid_argument naming the field when the model's numbers cannot be used.
  Channel(const scenario::ChannelModel& model, const PositionSource& positions, std::uint64_t seed);

  /// Decides one frame from @p from to @p to and records the outcome in that link's stats.
  Decision decide(StationId from, StationId to);

  /// Sees every decision as it is made (radio-medium writes them as `medium.frame` trace
  /// records, docs/tracing.md). Called from decide(); must not call back into the channel.
  using Observer = std::function<void(StationId from, StationId to, const Decision&)>;
  void set_observer(Observer o) { observer_ = std::move(o); }

  const scenario::ChannelModel& model() const { return model_; }
  const std::map<std::pair<StationId, StationId>, LinkStats>& links() const { return links_; }
  LinkStats totals() const;
  /// {"model":..., "seed":..., "links":[{"from","to","sent","delivered","dropped":{reason:n}}],
  ///  "totals":{...}} — the format the report tools read (README, "Radios").
  nlohmann::json stats_json() const;

 private:
  double uniform();  // [0, 1)
  Decision judge(StationId from, StationId to);

  scenario::ChannelModel model_;
  const PositionSource& positions_;
  std::uint64_t seed_;
  std::mt19937_64 rng_;
  std::map<std::pair<StationId, StationId>, LinkStats> links_;
  Observer observer_;
};

}  // namespace tb::emu::radio
