#pragma once
/// @file The position errors of a GPS agent (scenario "gnss" section).
///
/// Horizontal error per axis = bias + white noise. The bias is a random walk of intensity
/// bias_walk_m (m/√s): each epoch adds N(0, bias_walk_m·√dt). White noise is N(0,
/// white_noise_m) per axis; vertical error N(0, vertical_noise_m). `ideal` gives no error.
/// Seeded, so a run is reproducible.

#include <cstdint>
#include <optional>
#include <random>

#include "common/geodesy/local_frame.hpp"
#include "common/scenario/scenario.hpp"

namespace tb::emu::gnss {

struct ErrorSample {
  geodesy::Enu offset;  ///< metres, added to the true position
  double sigma_east = 0.0, sigma_north = 0.0, sigma_up = 0.0;  ///< the model's 1-sigma now
  bool fix = true;                                             ///< false inside a fix-loss window
};

class ErrorModel {
 public:
  ErrorModel(const scenario::GnssErrors& config, std::uint64_t seed);
  /// The error at sim time @p sim_time_ns; call with non-decreasing times.
  ErrorSample sample(std::int64_t sim_time_ns);
  bool in_fix_loss(std::int64_t sim_time_ns) const;

 private:
  scenario::GnssErrors config_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  double bias_east_ = 0.0, bias_north_ = 0.0;
  std::optional<std::int64_t> first_ns_, last_ns_;
};

/// SplitMix64: turns (run seed, station id) into well-spread per-station seeds.
std::uint64_t mix_seed(std::uint64_t seed, std::uint64_t stream);

}  // namespace tb::emu::gnss
