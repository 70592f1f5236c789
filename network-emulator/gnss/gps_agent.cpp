#include "network-emulator/gnss/gps_agent.hpp"

#include <cmath>
#include <stdexcept>

#include "network-emulator/gnss/sky.hpp"

namespace tb::emu::gnss {

namespace {
/// Below this speed a single-antenna receiver's course is noise; it keeps the last one.
constexpr double kCourseMinSpeed = 0.2;  // m/s
}  // namespace

GpsAgent::GpsAgent(const AgentConfig& config, const geodesy::Georeferencing& frame)
    : config_(config),
      frame_(frame),
      errors_(config.errors, mix_seed(config.seed, config.station_id)),
      period_ns_(config.rate_hz > 0 ? static_cast<std::int64_t>(std::llround(1e9 / config.rate_hz))
                                    : 0) {
  if (period_ns_ <= 0)
    throw std::invalid_argument("GNSS rate must be positive");
  if (config.epoch_offset.count() < 0 || config.epoch_offset.count() >= period_ns_)
    throw std::invalid_argument("GNSS epoch offset must lie within one period");
  sky_ = make_sky(config.errors.satellites, config.errors.hdop,
                  mix_seed(config.seed ^ 0x5157, config.station_id));
  fix_.sky = sky_;
  fix_.hdop = config.errors.hdop;
  fix_.vdop = config.errors.vdop;
  fix_.pdop = std::sqrt(fix_.hdop * fix_.hdop + fix_.vdop * fix_.vdop);
  out_.reserve(1024);
}

std::optional<std::string_view> GpsAgent::on_state(const wire::VehicleState& s) {
  if (next_epoch_ns_ && s.sim_time_ns < *next_epoch_ns_)
    return std::nullopt;
  // The next epoch is the next point of the grid (whole periods + offset) after this state.
  const std::int64_t t = s.sim_time_ns;
  const std::int64_t offset = config_.epoch_offset.count();
  const std::int64_t rel = t - offset;
  const std::int64_t floor_rel =
      (rel >= 0 ? rel / period_ns_ : (rel - period_ns_ + 1) / period_ns_) * period_ns_;
  next_epoch_ns_ = floor_rel + offset + period_ns_;

  const ErrorSample e = errors_.sample(t);
  fix_.time = config_.start_time + std::chrono::duration_cast<std::chrono::system_clock::duration>(
                                       std::chrono::nanoseconds(t));
  fix_.valid = e.fix;
  // The physics reports the bounding-box centre; the receiver sees its antenna.
  const double cy = std::cos(s.yaw), sy = std::sin(s.yaw);
  const double ax = s.position[0] + config_.antenna.forward_m * cy - config_.antenna.left_m * sy;
  const double ay = s.position[1] + config_.antenna.forward_m * sy + config_.antenna.left_m * cy;
  // Altitude: the state's z, which follows the road's elevation (sim-server's road surface).
  const geodesy::Enu antenna{ax, ay, s.position[2]};
  fix_.position =
      frame_.to_geodetic({ax + e.offset.east, ay + e.offset.north, s.position[2] + e.offset.up});
  // Course over ground is the direction of motion, as a receiver measures it from Doppler: out
  // of the tail while reversing. The station turns it into the orientation (it knows the gear).
  const double vx = s.velocity[0], vy = s.velocity[1];
  fix_.speed_mps = std::hypot(vx, vy);
  // Headings are from true north: on a projected map grid north differs (the convergence).
  if (fix_.speed_mps >= kCourseMinSpeed)
    course_deg_ = frame_.heading_deg(antenna, std::atan2(vy, vx));
  else if (!course_deg_)
    course_deg_ = frame_.heading_deg(antenna, s.yaw);
  fix_.course_deg = *course_deg_;
  fix_.sigma_lat_m = e.sigma_north;
  fix_.sigma_lon_m = e.sigma_east;
  fix_.sigma_alt_m = e.sigma_up;
  fix_.range_rms_m = e.sigma_north;  // the residuals' RMS follows the noise level

  out_.clear();
  if (config_.write_sentences)
    append_epoch(fix_, out_);
  ++epochs_;
  return std::string_view(out_);
}

}  // namespace tb::emu::gnss
