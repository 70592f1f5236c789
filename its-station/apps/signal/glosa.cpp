#include "its-station/apps/signal/glosa.hpp"

#include <algorithm>
#include <cmath>

namespace tb::its::apps::signal {

std::vector<GreenWindow> green_windows(const std::vector<PhaseInterval>& timeline) {
  std::vector<GreenWindow> out;
  bool extend = false;  // the previous phase was green too
  for (const PhaseInterval& p : timeline) {
    if (aspect(p.state) != Aspect::kGo) {
      extend = false;
      continue;
    }
    if (extend) {
      out.back().end_s = p.end_s;
    } else {
      out.push_back(GreenWindow{p.start_s, p.end_s});
    }
    extend = true;
  }
  std::erase_if(out, [](const GreenWindow& w) { return w.end_s <= 0.0; });
  return out;
}

std::optional<SpeedAdvice> glosa_advice(double distance_m, std::optional<double> speed_limit_mps,
                                        const std::vector<PhaseInterval>& timeline,
                                        const GlosaConfig& cfg) {
  if (!(distance_m > 0.0)) {
    return std::nullopt;
  }
  const double v_limit = speed_limit_mps.value_or(cfg.default_max_speed_mps);
  for (const GreenWindow& w : green_windows(timeline)) {
    // Earliest and latest arrival inside the window; a green under way needs no wait.
    const double t_first = std::max(0.0, w.start_s + cfg.margin_s);
    const double t_last = w.end_s - cfg.margin_s;
    if (!(t_last > t_first)) {
      continue;
    }
    const double v_high = t_first > 0.0 ? distance_m / t_first : v_limit;
    const double v_low = std::isfinite(t_last) ? distance_m / t_last : 0.0;
    SpeedAdvice a;
    a.min_speed_mps = std::max(v_low, cfg.min_speed_mps);
    a.max_speed_mps = std::min(v_high, v_limit);
    a.window = w;
    if (a.min_speed_mps <= a.max_speed_mps) {
      return a;
    }
  }
  return std::nullopt;
}

}  // namespace tb::its::apps::signal
