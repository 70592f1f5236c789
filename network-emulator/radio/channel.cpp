#include "network-emulator/radio/channel.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

namespace tb::emu::radio {

using Kind = scenario::ChannelModel::Kind;

std::string_view to_string(DropReason r) {
  switch (r) {
    case DropReason::kOutOfRange:
      return "out_of_range";
    case DropReason::kBelowSensitivity:
      return "below_sensitivity";
    case DropReason::kPacketError:
      return "packet_error";
    case DropReason::kUnknownPosition:
      return "unknown_position";
  }
  return "unknown";
}

std::string_view to_string(Kind k) {
  switch (k) {
    case Kind::kIdeal:
      return "ideal";
    case Kind::kRange:
      return "range";
    case Kind::kLogDistance:
      return "log_distance";
    case Kind::kTwoRay:
      return "two_ray";
  }
  return "unknown";
}

void PositionTable::index_cells(double cell_m) {
  grid_.reset();
  if (cell_m == 0.0)
    return;
  grid_ = std::make_unique<SpatialGrid>(cell_m);
  for (const auto& [id, p] : table_)
    grid_->place(id, p.position);
}

void PositionTable::set(StationId id, const StationPosition& p) {
  table_[id] = p;
  if (grid_)
    grid_->place(id, p.position);
}

bool PositionTable::update(const wire::VehicleState& s) {
  auto it = table_.find(s.station_id);
  if (it != table_.end() && it->second.sim_time_ns > s.sim_time_ns)
    return false;
  set(s.station_id, StationPosition{s.position, s.sim_time_ns});
  return true;
}

bool PositionTable::stations_within(const std::array<double, 3>& p, double radius_m,
                                    std::vector<StationId>& out) const {
  if (!grid_)
    return false;
  grid_->within(p, radius_m, out);
  return true;
}

std::optional<StationPosition> PositionTable::position(StationId id) const {
  auto it = table_.find(id);
  if (it == table_.end())
    return std::nullopt;
  return it->second;
}

std::uint64_t LinkStats::dropped_total() const {
  std::uint64_t n = 0;
  for (auto d : dropped)
    n += d;
  return n;
}

LinkStats& LinkStats::operator+=(const LinkStats& o) {
  sent += o.sent;
  delivered += o.delivered;
  for (std::size_t i = 0; i < kDropReasonCount; ++i)
    dropped[i] += o.dropped[i];
  return *this;
}

namespace {
void require(bool ok, const char* field, double value, const char* what) {
  if (!ok)
    throw std::invalid_argument("channel model: " + std::string(field) + " = " +
                                std::to_string(value) + ": " + what);
}
}  // namespace

Channel::Channel(const scenario::ChannelModel& model, const PositionSource& positions,
                 std::uint64_t seed)
    : model_(model), positions_(positions), seed_(seed), rng_(seed) {
  require(model.packet_error_rate >= 0.0 && model.packet_error_rate <= 1.0, "packet_error_rate",
          model.packet_error_rate, "must be in [0, 1]");
  require(model.delay_ms >= 0.0, "delay_ms", model.delay_ms, "must not be negative");
  require(model.jitter_ms >= 0.0, "jitter_ms", model.jitter_ms, "must not be negative");
  if (model.kind == Kind::kRange)
    require(model.range_m > 0.0, "range_m", model.range_m, "must be positive");
  if (model.kind == Kind::kTwoRay) {
    require(model.antenna_height_m > 0.0, "antenna_height_m", model.antenna_height_m,
            "must be positive");
    require(model.frequency_mhz > 0.0, "frequency_mhz", model.frequency_mhz, "must be positive");
  }
  max_range_m_ = scenario::max_range_m(model);
}

bool Channel::reachable(StationId from, std::vector<StationId>& out) const {
  out.clear();
  if (!max_range_m_)
    return false;
  const auto p = positions_.position(from);
  if (!p)
    return false;
  // A hair beyond the range, so that rounding never culls a link judge() would deliver: one
  // just beyond is offered and dropped by judge() as it always was.
  return positions_.stations_within(p->position, *max_range_m_ * (1.0 + 1e-9) + 1e-6, out);
}

double Channel::uniform() {
  // 53 random bits scaled by 2^-53: unlike std::uniform_real_distribution this gives the same
  // numbers with every standard library, so a seed reproduces a run anywhere.
  return static_cast<double>(rng_() >> 11) * 0x1.0p-53;
}

Decision Channel::judge(StationId from, StationId to) {
  Decision d;
  if (model_.kind != Kind::kIdeal) {
    const auto a = positions_.position(from);
    const auto b = positions_.position(to);
    if (!a || !b) {
      d.reason = DropReason::kUnknownPosition;
      return d;
    }
    const double dx = a->position[0] - b->position[0];
    const double dy = a->position[1] - b->position[1];
    const double dz = a->position[2] - b->position[2];
    d.distance_m = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (model_.kind == Kind::kRange) {
      if (*d.distance_m > model_.range_m) {
        d.reason = DropReason::kOutOfRange;
        return d;
      }
    } else {
      d.rx_power_dbm = model_.tx_power_dbm - path_loss_db(model_, *d.distance_m);
      if (*d.rx_power_dbm < model_.sensitivity_dbm) {
        d.reason = DropReason::kBelowSensitivity;
        return d;
      }
    }
    // The ideal model stays lossless (the thesis's behaviour); the others add random loss on
    // links that are in range.
    if (model_.packet_error_rate > 0.0 && uniform() < model_.packet_error_rate) {
      d.reason = DropReason::kPacketError;
      return d;
    }
  }
  d.deliver = true;
  double delay_ms = model_.delay_ms;
  if (model_.jitter_ms > 0.0)
    delay_ms += uniform() * model_.jitter_ms;
  d.delay = std::chrono::duration_cast<clock::Duration>(
      std::chrono::duration<double, std::milli>(delay_ms));
  return d;
}

Decision Channel::decide(StationId from, StationId to) {
  Decision d = judge(from, to);
  LinkStats& s = links_[{from, to}];
  ++s.sent;
  if (d.deliver)
    ++s.delivered;
  else
    ++s.dropped[static_cast<std::size_t>(d.reason)];
  if (observer_)
    observer_(from, to, d);
  return d;
}

LinkStats Channel::totals() const {
  LinkStats t;
  for (const auto& [link, s] : links_)
    t += s;
  return t;
}

namespace {
nlohmann::json to_json(const LinkStats& s) {
  nlohmann::json dropped = nlohmann::json::object();
  for (std::size_t i = 0; i < kDropReasonCount; ++i)
    dropped[std::string(to_string(static_cast<DropReason>(i)))] = s.dropped[i];
  return {{"sent", s.sent}, {"delivered", s.delivered}, {"dropped", dropped}};
}
}  // namespace

nlohmann::json Channel::stats_json() const {
  nlohmann::json links = nlohmann::json::array();
  for (const auto& [link, s] : links_) {
    nlohmann::json j = to_json(s);
    j["from"] = link.first;
    j["to"] = link.second;
    links.push_back(std::move(j));
  }
  return {{"model", std::string(to_string(model_.kind))},
          {"seed", seed_},
          {"links", std::move(links)},
          {"totals", to_json(totals())},
          {"culled", culled_}};
}

}  // namespace tb::emu::radio
