#include "its-station/rsu/spatem_builder.hpp"

#include <chrono>

namespace tb::its::rsu {

namespace msg = messages;

namespace {

constexpr std::int64_t kHourMs = 3'600'000;

std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  return a / b - ((a % b != 0) && ((a < 0) != (b < 0)) ? 1 : 0);
}

// MinuteOfTheYear and DSecond (ISO TS 19091 DE_MinuteOfTheYear, DE_DSecond) of a UTC instant.
void minute_of_year(std::int64_t utc_ms, msg::MinuteOfTheYear& moy, msg::DSecond& dsecond) {
  using namespace std::chrono;
  const sys_days day{days{floor_div(utc_ms, 86'400'000)}};
  const year_month_day ymd{day};
  const sys_days year_start{ymd.year() / January / 1};
  const std::int64_t since_year =
      utc_ms - duration_cast<milliseconds>(year_start.time_since_epoch()).count();
  moy = static_cast<msg::MinuteOfTheYear>(since_year / 60'000);
  dsecond = static_cast<msg::DSecond>(since_year % 60'000);
}

}  // namespace

msg::TimeMark time_mark(std::int64_t at_ms, std::int64_t now_ms) {
  if (at_ms == 0)
    return msg::kTimeMarkUnknown;
  // An end an hour or more ahead cannot be told apart from one in the current hour (DE_TimeMark
  // "36000 indicates time > 3600 seconds").
  if (at_ms - now_ms >= kHourMs)
    return msg::kTimeMarkLeapSecond;
  return msg::time_mark_from_utc_ms(at_ms);
}

bool same_states(const wire::sim::SignalStates& a, const wire::sim::SignalStates& b) {
  if (a.groups.size() != b.groups.size())
    return false;
  for (std::size_t i = 0; i < a.groups.size(); ++i) {
    const wire::sim::SignalGroupState& x = a.groups[i];
    const wire::sim::SignalGroupState& y = b.groups[i];
    if (x.intersection_id != y.intersection_id || x.signal_group != y.signal_group ||
        x.state != y.state)
      return false;
  }
  return true;
}

SpatemBuilder::SpatemBuilder(std::uint16_t intersection_id)
    : intersection_id_(intersection_id),
      spatem_(std::make_unique<msg::Spatem>()),
      buffer_(msg::kSpatemMaxEncodedSize) {}

SpatemBuilder::~SpatemBuilder() = default;

Expected<std::span<const std::uint8_t>, SpatemBuilder::Error> SpatemBuilder::build(
    const wire::sim::SignalStates& states, std::int64_t now_ms) {
  msg::Spatem& s = *spatem_;
  s.spat.timeStamp.reset();
  s.spat.name.reset();
  s.spat.intersections.clear();
  msg::IntersectionState& is = s.spat.intersections.emplace_back();
  is.id.region.reset();
  is.id.id = intersection_id_;
  // The feed carries fixed-time plans (scenario `signals`, docs/scenario.md).
  is.status = msg::intersection_status::kFixedTimeOperation;
  msg::MinuteOfTheYear moy = 0;
  msg::DSecond dsecond = 0;
  minute_of_year(now_ms, moy, dsecond);
  is.moy = moy;
  is.timeStamp = dsecond;

  std::vector<wire::sim::SignalGroupState> mine;
  for (const wire::sim::SignalGroupState& g : states.groups)
    if (g.intersection_id == intersection_id_ && is.states.size() < msg::kMovementStatesMax) {
      mine.push_back(g);
      msg::MovementState& ms = is.states.emplace_back();
      ms.signalGroup = g.signal_group;
      msg::MovementEvent& ev = ms.state_time_speed.emplace_back();
      ev.eventState = static_cast<msg::MovementPhaseState>(g.state);
      msg::TimeChangeDetails t;
      t.minEndTime = time_mark(g.next_change_ms, now_ms);
      if (g.likely_change_ms != 0)
        t.likelyTime = time_mark(g.likely_change_ms, now_ms);
      ev.timing = t;
    }
  if (mine.empty())
    return Unexpected{Error::kNoGroups};
  bool changed = mine.size() != previous_.size();
  for (std::size_t i = 0; !changed && i < mine.size(); ++i)
    changed =
        mine[i].signal_group != previous_[i].signal_group || mine[i].state != previous_[i].state;
  if (changed && !previous_.empty())
    revision_ = static_cast<msg::MsgCount>((revision_ + 1) % 128);
  previous_ = std::move(mine);
  is.revision = revision_;

  const auto n = msg::encode(s, buffer_);
  if (!n)
    return Unexpected{Error::kEncode};
  return std::span<const std::uint8_t>(buffer_.data(), *n);
}

}  // namespace tb::its::rsu
