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
#include <memory>
#include <optional>
#include <random>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "common/clock/clock.hpp"
#include "common/scenario/channel_range.hpp"
#include "common/scenario/scenario.hpp"
#include "common/wire/vehicle_state.hpp"
#include "network-emulator/radio/spatial_grid.hpp"

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
  /// Appends to @p out (not cleared) every station within @p radius_m of @p p and returns
  /// true, if the source keeps an index that answers this without looking at every station;
  /// false (nothing appended) if not: then every station is a candidate.
  virtual bool stations_within(const std::array<double, 3>& p, double radius_m,
                               std::vector<StationId>& out) const {
    (void)p, (void)radius_m, (void)out;
    return false;
  }
};

/// The latest position of every station, fed from vehicle states. Not thread-safe: the
/// emulator updates and reads it from one io_context.
class PositionTable final : public PositionSource {
 public:
  PositionTable() = default;
  /// Keeps a SpatialGrid of @p cell_m wide cells (> 0) over the positions, for
  /// stations_within(): one channel's maximum range wide (Channel::max_range_m()).
  explicit PositionTable(double cell_m) { index_cells(cell_m); }
  /// Starts (or rebuilds) the grid with @p cell_m wide cells; 0 stops it.
  void index_cells(double cell_m);

  void set(StationId id, const StationPosition& p);
  /// Keeps the state only if it is not older than the one held: UDP may reorder datagrams.
  /// Returns whether it was taken.
  bool update(const wire::VehicleState& s);
  std::optional<StationPosition> position(StationId id) const override;
  bool stations_within(const std::array<double, 3>& p, double radius_m,
                       std::vector<StationId>& out) const override;
  std::size_t size() const { return table_.size(); }

 private:
  std::map<StationId, StationPosition> table_;
  std::unique_ptr<SpatialGrid> grid_;
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

  /// How far a frame can get (common/scenario/channel_range.hpp); empty for the ideal channel,
  /// which reaches everyone.
  const std::optional<double>& max_range_m() const { return max_range_m_; }
  /// The stations a frame from @p from can reach at all (within max_range_m(), @p from itself
  /// among them), appended to @p out (cleared first), when the positions can tell without
  /// looking at every station: false when the channel is ideal, @p from's position is unknown
  /// or the positions keep no index. Stations without a position are never in @p out.
  bool reachable(StationId from, std::vector<StationId>& out) const;
  bool has_position(StationId id) const { return positions_.position(id).has_value(); }
  /// Receivers that were not offered a frame because they were beyond max_range_m() (range
  /// culling, Medium): not links, so not in the links' counts; reported as "culled".
  void count_culled(std::uint64_t n) { culled_ += n; }
  std::uint64_t culled() const { return culled_; }

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
  std::optional<double> max_range_m_;
  std::uint64_t culled_ = 0;
};

}  // namespace tb::emu::radio
