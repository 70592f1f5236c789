// libFuzzer target: the vehicle's reception of MAPEM and SPATEM as the station wires it (issue
// 34): payloads into the facilities' IntersectionReceiver and store, each intersection
// converted into the signal application's model (dsrc_convert.hpp) and given to the
// application, with own fixes in between. Never a crash; what the conversion makes must hold
// what the application relies on: finite node positions, and every SPAT time within half an
// hour of the station's clock (a TimeMark means the instant nearest to it).
//
// Input: records of a kind byte — 0: MAPEM, 1: SPATEM (then a 2-byte length and the payload),
// 2: a fix (int16 dm east/north of the refPoint, heading in 0.01°, speed in 0.25 m/s), 3: the
// clock moves on by a byte's 10 ms steps — each read through a bounds-checked ByteReader.

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <vector>

#include "common/clock/clock.hpp"
#include "common/geodesy/local_frame.hpp"
#include "common/util/bytes.hpp"
#include "its-station/apps/signal/dsrc_convert.hpp"
#include "its-station/apps/signal/signal_app.hpp"
#include "its-station/facilities/intersection_receiver.hpp"

namespace {

using namespace tb::its;
using namespace std::chrono_literals;

void check_time(const std::optional<tb::clock::WallTime>& t, tb::clock::WallTime now) {
  if (t && (*t - now > 30min + 1s || now - *t > 30min + 1s))
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  tb::ByteReader r(std::span<const std::uint8_t>(data, size));
  tb::clock::ManualClock clk;
  facilities::IntersectionStore store(clk);
  facilities::IntersectionReceiver rx(store);
  apps::signal::SignalApplication app(
      clk, {}, [](const apps::signal::SignalStatus&) {}, [](const apps::signal::RlvwWarning&) {});
  std::optional<tb::geodesy::LocalFrame> frame;
  rx.on_map([&](const facilities::IntersectionEntry& e, facilities::MapOutcome) {
    auto t = apps::signal::topology_from_geometry(*e.map, clk.wall_now());
    if (!t)
      return;
    for (const auto& l : t->lanes)
      for (const auto& n : l.nodes)
        if (!std::isfinite(n.x) || !std::isfinite(n.y))
          std::abort();
    frame.emplace(tb::geodesy::Geodetic{t->ref_latitude_deg, t->ref_longitude_deg, 0.0});
    (void)app.on_map(std::move(*t));
  });
  rx.on_spat([&](const facilities::IntersectionEntry& e) {
    const auto now = clk.wall_now();
    const auto phases = apps::signal::phases_from_state(*e.spat, now, now);
    for (const auto& p : phases) {
      for (const auto* ev : {&p.current}) {
        check_time(ev->start_time, now);
        check_time(ev->min_end_time, now);
        check_time(ev->max_end_time, now);
        check_time(ev->likely_time, now);
      }
      for (const auto& ev : p.upcoming) {
        check_time(ev.start_time, now);
        check_time(ev.min_end_time, now);
        check_time(ev.max_end_time, now);
        check_time(ev.likely_time, now);
      }
    }
    app.on_spat(e.id, phases);
  });

  std::vector<std::uint8_t> payload;
  while (r.remaining() > 0 && r.ok()) {
    const std::uint8_t kind = r.le<std::uint8_t>() % 4;
    if (kind <= 1) {
      payload.resize(std::min<std::size_t>(r.le<std::uint16_t>(), r.remaining()));
      if (!r.read(payload))
        break;
      if (kind == 0)
        rx.receive_mapem(payload);
      else
        rx.receive_spatem(payload);
    } else if (kind == 2) {
      const double east = r.le<std::int16_t>() / 10.0;
      const double north = r.le<std::int16_t>() / 10.0;
      const double heading = r.le<std::uint16_t>() / 100.0;
      const double speed = r.le<std::uint8_t>() / 4.0;
      if (!r.ok() || !frame)
        break;
      const auto g = frame->to_geodetic({east, north, 0.0});
      apps::signal::OwnKinematics own;
      own.station_id = 1;
      own.latitude_deg = g.latitude_deg;
      own.longitude_deg = g.longitude_deg;
      own.heading_deg = std::fmod(heading, 360.0);
      own.speed_mps = speed;
      own.time = clk.wall_now();
      app.update(own);
    } else {
      clk.advance(std::chrono::milliseconds{10} * r.le<std::uint8_t>());
      store.expire();
    }
  }
  return 0;
}
