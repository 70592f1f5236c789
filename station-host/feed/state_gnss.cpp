#include "station-host/feed/state_gnss.hpp"

#include <algorithm>
#include <cmath>

namespace tb::host {

namespace facilities = its::facilities;

facilities::GpsdReport gpsd_report_of(const emu::gnss::Fix& fix) {
  facilities::GpsdReport r;
  std::size_t used = 0;
  for (const emu::gnss::SatelliteView& s : fix.sky)
    used += s.used ? 1 : 0;
  // The same rule as the agent's GSA: mode 1 without a fix, 3 with four satellites or more.
  if (!fix.valid) {
    r.mode = facilities::GpsdMode::kNoFix;
    return r;
  }
  r.mode = used >= 4 ? facilities::GpsdMode::k3D : facilities::GpsdMode::k2D;
  r.time = fix.time;
  r.latitude_deg = fix.position.latitude_deg;
  r.longitude_deg = fix.position.longitude_deg;
  // GGA carries the altitude with a geoid separation of 0, so gpsd's altHAE is that altitude.
  r.altitude_hae_m = fix.position.altitude_m;
  r.speed_mps = fix.speed_mps;
  // RMC and VTG round the course to 0.01° and never write 360.00.
  r.track_deg = fix.course_deg >= 359.995 ? 0.0 : fix.course_deg;
  r.hdop = fix.hdop;
  r.eph_m = fix.hdop * facilities::gnss_model::kGpsdHorizontalUereM;
  r.epv_m = fix.vdop * kGpsdVerticalUereM;
  // GST: the agent's error ellipse is aligned with north and east (nmea.cpp).
  facilities::GpsdGst gst;
  gst.semi_major_sigma_m = std::max(fix.sigma_lat_m, fix.sigma_lon_m);
  gst.semi_minor_sigma_m = std::min(fix.sigma_lat_m, fix.sigma_lon_m);
  gst.orientation_deg = fix.sigma_lat_m >= fix.sigma_lon_m ? 0.0 : 90.0;
  gst.altitude_sigma_m = fix.sigma_alt_m;
  r.gst = gst;
  return r;
}

namespace {

// The fix is read from the agent, not from its sentences.
emu::gnss::AgentConfig without_sentences(emu::gnss::AgentConfig c) {
  c.write_sentences = false;
  return c;
}

}  // namespace

StateGnssReceiver::StateGnssReceiver(const emu::gnss::AgentConfig& config,
                                     const geodesy::Georeferencing& frame, clock::Runtime& runtime,
                                     clock::Duration stale_after)
    : agent_(without_sentences(config), frame), runtime_(runtime), stale_after_(stale_after) {}

StateGnssReceiver::~StateGnssReceiver() {
  if (stale_timer_ != 0)
    runtime_.cancel(stale_timer_);
}

void StateGnssReceiver::on_state(const wire::VehicleState& state) {
  // No NMEA text: the agent's last_fix() is what its sentences would say.
  if (!agent_.on_state(state))
    return;
  facilities::PositionFix fix;
  switch (assembler_.on_report(gpsd_report_of(agent_.last_fix()), runtime_.steady_now(), fix)) {
    case facilities::FixAssembler::Outcome::kFix:
      publish(fix);
      rearm_stale_timer();
      break;
    case facilities::FixAssembler::Outcome::kLoss:
      publish_loss();
      break;
    case facilities::FixAssembler::Outcome::kNone:
      break;
  }
}

void StateGnssReceiver::rearm_stale_timer() {
  if (stale_timer_ != 0)
    runtime_.cancel(stale_timer_);
  stale_timer_ = runtime_.schedule_in(stale_after_, [this] {
    stale_timer_ = 0;
    publish_loss();
  });
}

}  // namespace tb::host
