// The only file that includes <gps.h>: every libgps API difference is handled here.
#include <gps.h>

#include <cerrno>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

#include "its-station/facilities/gpsd_session.hpp"

#if GPSD_API_MAJOR_VERSION < 7
#error "libgps API 7 or newer is needed (gps_read with a message buffer)"
#endif

namespace tb::its::facilities {

struct GpsdSession::Impl {
  gps_data_t data{};
  bool open = false;
};

namespace {

#if GPSD_API_MAJOR_VERSION >= 9
// API 9 made fix.time a timespec.
std::optional<clock::WallTime> fix_time(const gps_data_t& d) {
  if (!(d.set & TIME_SET) || (d.fix.time.tv_sec == 0 && d.fix.time.tv_nsec == 0))
    return std::nullopt;
  return clock::from_unix_ns(std::int64_t{d.fix.time.tv_sec} * 1'000'000'000 + d.fix.time.tv_nsec);
}
double altitude_hae(const gps_data_t& d) {
  return d.fix.altHAE;
}
#else
std::optional<clock::WallTime> fix_time(const gps_data_t& d) {
  if (!(d.set & TIME_SET) || !std::isfinite(d.fix.time))
    return std::nullopt;
  return clock::from_unix_ns(static_cast<std::int64_t>(std::llround(d.fix.time * 1e9)));
}
// Before API 9 only one altitude existed, above mean sea level.
double altitude_hae(const gps_data_t& d) {
  return d.fix.altitude;
}
#endif

GpsdMode to_mode(int m) {
  switch (m) {
    case MODE_2D:
      return GpsdMode::k2D;
    case MODE_3D:
      return GpsdMode::k3D;
    case MODE_NO_FIX:
      return GpsdMode::kNoFix;
    default:
      return GpsdMode::kNotSeen;
  }
}

}  // namespace

GpsdSession::GpsdSession(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

GpsdSession::~GpsdSession() {
  if (impl_ && impl_->open) {
    gps_stream(&impl_->data, WATCH_DISABLE, nullptr);
    gps_close(&impl_->data);
  }
}

Expected<std::unique_ptr<GpsdSession>, std::string> GpsdSession::open(const std::string& host,
                                                                      const std::string& port) {
  auto impl = std::make_unique<Impl>();
  errno = 0;
  if (gps_open(host.c_str(), port.c_str(), &impl->data) != 0) {
    const int err = errno;
    return Unexpected{fmt::format("cannot connect to gpsd at {}:{}: {}", host, port,
                                  err != 0 ? gps_errstr(err) : "unknown error")};
  }
  impl->open = true;
  if (gps_stream(&impl->data, WATCH_ENABLE | WATCH_JSON, nullptr) != 0) {
    gps_close(&impl->data);
    impl->open = false;
    return Unexpected{fmt::format("gpsd at {}:{} refused the watch request", host, port)};
  }
  return std::unique_ptr<GpsdSession>(new GpsdSession(std::move(impl)));
}

int GpsdSession::fd() const {
  return impl_->data.gps_fd;
}

bool GpsdSession::waiting() {
  return gps_waiting(&impl_->data, 0);
}

bool GpsdSession::read(GpsdReport& out) {
  gps_data_t& d = impl_->data;
  d.set = 0;
  if (gps_read(&d, nullptr, 0) < 0)
    return false;
  out = GpsdReport{};
  if (d.set & MODE_SET) {
    out.mode = to_mode(d.fix.mode);
    out.time = fix_time(d);
    out.latitude_deg = d.fix.latitude;
    out.longitude_deg = d.fix.longitude;
    out.altitude_hae_m = altitude_hae(d);
    out.speed_mps = d.fix.speed;
    out.track_deg = d.fix.track;
    out.eph_m = d.fix.eph;
    out.epx_m = d.fix.epx;
    out.epy_m = d.fix.epy;
    out.epv_m = d.fix.epv;
  }
  if (d.set & DOP_SET)
    out.hdop = d.dop.hdop;
  if (d.set & GST_SET) {
    GpsdGst g;
    g.semi_major_sigma_m = d.gst.smajor_deviation;
    g.semi_minor_sigma_m = d.gst.sminor_deviation;
    g.orientation_deg = d.gst.smajor_orientation;
    g.altitude_sigma_m = d.gst.alt_err_deviation;
    out.gst = g;
  }
  return true;
}

}  // namespace tb::its::facilities
