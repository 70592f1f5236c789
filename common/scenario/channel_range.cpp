#include "common/scenario/channel_range.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tb::scenario {
namespace {

using Kind = ChannelModel::Kind;
constexpr double kSpeedOfLight = 299'792'458.0;

double wavelength_m(const ChannelModel& m) {
  return kSpeedOfLight / (m.frequency_mhz * 1e6);
}

// Friis free-space loss between isotropic antennas.
double free_space_db(double d, double lambda) {
  return 20.0 * std::log10(4.0 * std::numbers::pi * d / lambda);
}

double crossover_m(const ChannelModel& m) {
  const double h = m.antenna_height_m;
  return 4.0 * std::numbers::pi * h * h / wavelength_m(m);
}

}  // namespace

double path_loss_db(const ChannelModel& m, double distance_m) {
  const double d = std::max(distance_m, 1.0);
  if (m.kind == Kind::kLogDistance)
    return m.reference_loss_db + 10.0 * m.path_loss_exponent * std::log10(d);
  // Two-ray ground reflection with equal antenna heights: free space up to the crossover
  // distance d_c = 4π h_t h_r / λ, then 40 log10(d) − 20 log10(h_t h_r); the two meet at d_c.
  const double lambda = wavelength_m(m);
  const double h = m.antenna_height_m;
  if (d <= crossover_m(m))
    return free_space_db(d, lambda);
  return 40.0 * std::log10(d) - 20.0 * std::log10(h * h);
}

std::optional<double> max_range_m(const ChannelModel& m) {
  switch (m.kind) {
    case Kind::kIdeal:
      return std::nullopt;
    case Kind::kRange:
      return m.range_m;
    case Kind::kLogDistance: {
      // tx − (L0 + 10 n log10 d) = sensitivity, solved for d.
      const double budget = m.tx_power_dbm - m.sensitivity_dbm;
      if (m.path_loss_exponent <= 0.0)
        return std::nullopt;
      return std::max(
          1.0, std::pow(10.0, (budget - m.reference_loss_db) / (10.0 * m.path_loss_exponent)));
    }
    case Kind::kTwoRay: {
      const double budget = m.tx_power_dbm - m.sensitivity_dbm;
      const double lambda = wavelength_m(m);
      const double dc = crossover_m(m);
      // Both branches rise with distance and meet at the crossover: the budget is used up
      // before it when the free-space loss there already exceeds it.
      if (free_space_db(std::max(dc, 1.0), lambda) >= budget)
        return std::max(1.0, std::pow(10.0, budget / 20.0) * lambda / (4.0 * std::numbers::pi));
      const double h = m.antenna_height_m;
      return std::pow(10.0, (budget + 20.0 * std::log10(h * h)) / 40.0);
    }
  }
  return std::nullopt;
}

}  // namespace tb::scenario
