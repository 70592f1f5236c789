#include "sim-client/v2x/signal_panel.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace tb::client::v2x {

std::optional<SignalPanel> signal_panel(const V2xPicture& picture, std::uint32_t station) {
  const LaneSignal* s = picture.signal_for(station);
  if (s == nullptr)
    return std::nullopt;
  SignalPanel p;
  p.station = s->station;
  p.intersection_id = s->intersection_id;
  p.signal_group = s->signal_group;
  p.lane_id = s->lane_id;
  p.light = s->light;
  p.red = s->light == SignalLight::kRed || s->light == SignalLight::kRedAmber;
  p.amber = s->light == SignalLight::kAmber || s->light == SignalLight::kRedAmber;
  p.green = s->light == SignalLight::kGreen;
  const std::optional<double> t =
      s->likely_time_to_change_s ? s->likely_time_to_change_s : s->time_to_change_s;
  if (t) {
    // A time already past (a late message) counts as the change being due: 0.
    p.countdown_s = static_cast<int>(std::ceil(std::max(0.0, *t)));
    p.countdown_is_likely = s->likely_time_to_change_s.has_value();
    p.countdown = fmt::format("{} s", *p.countdown_s);
  }
  p.distance = fmt::format("{:.0f} m", std::max(0.0, s->distance_to_stop_line_m));
  if (s->advice) {
    const double lo = std::ceil(s->advice->min_kmh), hi = std::floor(s->advice->max_kmh);
    if (lo < hi)
      p.advice = fmt::format("{:.0f}–{:.0f} km/h", lo, hi);
    else
      p.advice =
          fmt::format("{:.0f} km/h", std::round((s->advice->min_kmh + s->advice->max_kmh) / 2));
  }
  p.caption = fmt::format("group {} · lane {}", s->signal_group, s->lane_id);
  return p;
}

std::string rlvw_banner(const V2xPicture& picture, std::uint32_t station) {
  const RlvwAlert* a = picture.rlvw_for(station);
  if (a == nullptr)
    return {};
  const std::string when = a->time_to_red_s && *a->time_to_red_s > 0.0
                               ? fmt::format("red in {:.1f} s", *a->time_to_red_s)
                               : std::string("red");
  return fmt::format("RED LIGHT WARNING · {} · stop line {:.0f} m", when,
                     std::max(0.0, a->distance_to_stop_line_m));
}

}  // namespace tb::client::v2x
