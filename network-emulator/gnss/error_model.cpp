#include "network-emulator/gnss/error_model.hpp"

#include <cmath>

namespace tb::emu::gnss {

std::uint64_t mix_seed(std::uint64_t seed, std::uint64_t stream) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ull * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

ErrorModel::ErrorModel(const scenario::GnssErrors& config, std::uint64_t seed)
    : config_(config), rng_(seed) {}

bool ErrorModel::in_fix_loss(std::int64_t sim_time_ns) const {
  const double t = static_cast<double>(sim_time_ns) * 1e-9;
  for (const auto& w : config_.fix_loss)
    if (t >= w.from_s && t < w.to_s)
      return true;
  return false;
}

ErrorSample ErrorModel::sample(std::int64_t sim_time_ns) {
  ErrorSample s;
  s.fix = !in_fix_loss(sim_time_ns);
  if (config_.ideal)
    return s;
  if (!first_ns_)
    first_ns_ = sim_time_ns;
  const double dt =
      last_ns_ ? std::max<double>(0.0, static_cast<double>(sim_time_ns - *last_ns_) * 1e-9) : 0.0;
  last_ns_ = sim_time_ns;
  const double step = config_.bias_walk_m * std::sqrt(dt);
  bias_east_ += step * normal_(rng_);
  bias_north_ += step * normal_(rng_);
  s.offset.east = bias_east_ + config_.white_noise_m * normal_(rng_);
  s.offset.north = bias_north_ + config_.white_noise_m * normal_(rng_);
  s.offset.up = config_.vertical_noise_m * normal_(rng_);
  // The random walk's spread grows with the time since it started.
  const double elapsed = static_cast<double>(sim_time_ns - *first_ns_) * 1e-9;
  const double h = std::sqrt(config_.white_noise_m * config_.white_noise_m +
                             config_.bias_walk_m * config_.bias_walk_m * elapsed);
  s.sigma_east = s.sigma_north = h;
  s.sigma_up = config_.vertical_noise_m;
  return s;
}

}  // namespace tb::emu::gnss
