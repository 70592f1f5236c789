// libFuzzer target: the signal application on arbitrary intersections, SPAT groups and fixes,
// as a broken or hostile MAPEM/SPATEM could bring them after decoding (the decoders bound the
// values; this target does not even rely on that). It must never crash, and what it publishes
// must be finite and within the contract: a status on a lane has a finite distance at or
// before the stop line, an advice a range within its limits.
//
// Input: lanes count, then per lane id, flags, width (dm), node count, nodes (int16 dm, or
// NaN / ∞ when the flags say so), connections (lane, group); SPAT groups (group, state, which
// times, int16 ds offsets); then fixes (int16 dm x/y, heading in 0.01°, speed in 0.25 m/s,
// age and clock step in 10 ms), each byte read through a bounds-checked ByteReader.

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <span>
#include <vector>

#include "common/clock/clock.hpp"
#include "common/geodesy/local_frame.hpp"
#include "common/util/bytes.hpp"
#include "its-station/apps/signal/signal_app.hpp"

namespace {

using namespace tb::its::apps::signal;

double coordinate(tb::ByteReader& r, std::uint8_t flags) {
  const double v = r.le<std::int16_t>() / 10.0;
  if ((flags & 0x40) != 0 && v > 3000.0) {
    return (flags & 0x80) != 0 ? std::numeric_limits<double>::quiet_NaN()
                               : std::numeric_limits<double>::infinity();
  }
  return v;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  tb::ByteReader r(std::span<const std::uint8_t>(data, size));
  tb::clock::ManualClock clk;
  const auto now = [&] { return clk.wall_now(); };
  const auto ds = [&](std::int16_t v) {
    return now() + std::chrono::milliseconds{std::int64_t{v} * 100};
  };

  IntersectionTopology t;
  t.intersection_id = r.le<std::uint16_t>();
  t.revision = r.le<std::uint8_t>();
  t.ref_latitude_deg = 48.0;
  t.ref_longitude_deg = 11.0;
  if (const std::uint8_t limit = r.le<std::uint8_t>(); limit != 0) {
    t.speed_limit_mps = limit / 4.0 - 1.0;  // 0 and negatives included: refused
  }
  const int lanes = r.le<std::uint8_t>() % 12;
  for (int i = 0; i < lanes && r.ok(); ++i) {
    GenericLane l;
    l.lane_id = r.le<std::uint8_t>();
    const std::uint8_t flags = r.le<std::uint8_t>();
    l.ingress = (flags & 1) != 0;
    l.egress = (flags & 2) != 0;
    l.lane_width_m = r.le<std::uint8_t>() / 10.0;
    if ((flags & 4) != 0) {
      l.speed_limit_mps = r.le<std::uint8_t>() / 4.0;
    }
    const int nodes = r.le<std::uint8_t>() % 24;
    for (int n = 0; n < nodes && r.ok(); ++n) {
      const double x = coordinate(r, flags);
      const double y = coordinate(r, flags);
      l.nodes.push_back({x, y});
    }
    const int connections = r.le<std::uint8_t>() % 4;
    for (int c = 0; c < connections && r.ok(); ++c) {
      Connection conn;
      conn.connecting_lane = r.le<std::uint8_t>();
      if (const std::uint8_t g = r.le<std::uint8_t>(); (flags & 8) == 0 || g != 0) {
        conn.signal_group = g;
      }
      l.connects_to.push_back(conn);
    }
    t.lanes.push_back(l);
  }

  std::vector<SignalPhase> groups;
  const int n_groups = r.le<std::uint8_t>() % 6;
  for (int i = 0; i < n_groups && r.ok(); ++i) {
    SignalPhase p;
    p.signal_group = r.le<std::uint8_t>();
    const int events = 1 + r.le<std::uint8_t>() % 4;
    for (int e = 0; e < events && r.ok(); ++e) {
      MovementEvent ev;
      ev.state = movement_phase_state(r.le<std::uint8_t>() % 10).value();
      const std::uint8_t which = r.le<std::uint8_t>();
      if ((which & 1) != 0)
        ev.start_time = ds(r.le<std::int16_t>());
      if ((which & 2) != 0)
        ev.min_end_time = ds(r.le<std::int16_t>());
      if ((which & 4) != 0)
        ev.max_end_time = ds(r.le<std::int16_t>());
      if ((which & 8) != 0)
        ev.likely_time = ds(r.le<std::int16_t>());
      if (e == 0) {
        p.current = ev;
      } else {
        p.upcoming.push_back(ev);
      }
    }
    p.received_at = now();
    groups.push_back(p);
  }
  if (!r.ok()) {
    return 0;
  }

  SignalAppConfig cfg;
  auto check_status = [&](const SignalStatus& s) {
    if (!s.on_lane) {
      return;
    }
    if (!std::isfinite(s.distance_to_stop_line_m) || s.distance_to_stop_line_m < 0.0) {
      std::abort();  // published on a lane it is not before the stop line of
    }
    if (s.time_to_change_s && !(*s.time_to_change_s >= 0.0)) {
      std::abort();
    }
    if (s.advice && !(s.advice->min_speed_mps <= s.advice->max_speed_mps &&
                      s.advice->min_speed_mps >= cfg.glosa.min_speed_mps &&
                      std::isfinite(s.advice->max_speed_mps))) {
      std::abort();
    }
  };
  auto check_warning = [&](const RlvwWarning& w) {
    if (!std::isfinite(w.stopping_distance_m) || w.stopping_distance_m < 0.0 ||
        (w.time_to_red_s && !(*w.time_to_red_s >= 0.0))) {
      std::abort();
    }
  };
  SignalApplication app(clk, cfg, check_status, check_warning);
  (void)app.on_map(t);
  app.on_spat(t.intersection_id, groups);

  const tb::geodesy::LocalFrame frame({48.0, 11.0, 0.0});
  while (r.remaining() >= 8) {
    const double x = r.le<std::int16_t>() / 10.0;
    const double y = r.le<std::int16_t>() / 10.0;
    const tb::geodesy::Geodetic g = frame.to_geodetic({x, y, 0.0});
    OwnKinematics own;
    own.station_id = 1;
    own.latitude_deg = g.latitude_deg;
    own.longitude_deg = g.longitude_deg;
    own.heading_deg = r.le<std::uint16_t>() / 100.0;
    own.speed_mps = r.le<std::uint8_t>() / 4.0;
    own.time = now() - std::chrono::milliseconds{r.le<std::uint8_t>() * 10};
    app.update(own);
    if (r.remaining() >= 1) {
      clk.advance(std::chrono::milliseconds{r.le<std::uint8_t>() * 10});
    }
    if (r.remaining() >= 1 && (r.rest()[0] & 0x80) != 0) {
      r.skip(1);
      app.on_spat(t.intersection_id, groups);  // the same SPAT again, later
    }
  }
  return 0;
}
