#pragma once
// The world of the station's signal tests and benchmark (issue 34): a junction at kOrigin with
// a northbound ingress lane, an RSU side (a real GN router and BTP over its own test link) that
// sends the junction's MAPEM and SPATEM, and a car's Station over fake ports driving up to the
// light at 10 Hz fixes.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/clock/gnss_disciplined_runtime.hpp"
#include "common/clock/runtime.hpp"
#include "common/geodesy/local_frame.hpp"
#include "common/mqtt/sink.hpp"
#include "its-station/btp/dispatcher.hpp"
#include "its-station/facilities/transport.hpp"
#include "its-station/geonet/router.hpp"
#include "its-station/link/test_link.hpp"
#include "its-station/messages/mapem.hpp"
#include "its-station/messages/spatem.hpp"
#include "its-station/station/adapters.hpp"
#include "its-station/station/station.hpp"

namespace tb::its::station::testing {

namespace m = messages;
using namespace std::chrono_literals;

inline const geodesy::Geodetic kOrigin{48.1351, 11.5820, 0.0};  // the intersection's refPoint
constexpr double kLaneX = 1.75;                                 // the northbound lane's centre line
constexpr double kStopLineY = -12.0;                            // 12 m south of the refPoint
constexpr std::uint8_t kGroup = 1;
constexpr double kReactionS = 1.0;     // issue 34's RLVW rule
constexpr double kComfortDecel = 3.0;  // m/s²
// The light: green until 3 s, amber until 6 s, red until 26 s (from the start of the run).
constexpr double kAmberAtS = 3.0;
constexpr double kRedAtS = 6.0;
constexpr double kGreenAgainAtS = 26.0;

inline link::MacAddress mac_of(std::uint32_t id) {
  return {0x02,
          0x00,
          static_cast<std::uint8_t>(id >> 24),
          static_cast<std::uint8_t>(id >> 16),
          static_cast<std::uint8_t>(id >> 8),
          static_cast<std::uint8_t>(id)};
}

inline std::int64_t unix_ms(clock::WallTime t) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(t.time_since_epoch()).count();
}

class RecordingSink final : public tb::mqtt::MqttSink {
 public:
  void publish(std::string_view topic, std::string payload, tb::mqtt::Qos, bool) override {
    // The station's envelope (origin, timestamp, type) around the application's message.
    published.push_back(
        {std::string(topic), nlohmann::json::parse(payload).at("message"), fix_index});
  }
  struct Message {
    std::string topic;
    nlohmann::json payload;
    int fix_index;  ///< the last fix given before it was published
  };
  std::vector<Message> on(const std::string& topic) const {
    std::vector<Message> r;
    for (const auto& p : published)
      if (p.topic == topic)
        r.push_back(p);
    return r;
  }
  std::vector<Message> published;
  int fix_index = -1;
};

inline m::NodeXY node(std::int32_t x_cm, std::int32_t y_cm) {
  return {m::node_xy(x_cm, y_cm), std::nullopt};
}

/// The MAPEM of a junction at kOrigin: a northbound ingress lane (1) whose stop line is 12 m
/// south of the centre, reaching 250 m upstream, connected to the northbound egress lane (2)
/// under signal group 1.
inline std::vector<std::uint8_t> mapem() {
  auto msg = std::make_unique<m::Mapem>();
  msg->header.stationID = 5001;
  auto& g = msg->map.intersections.emplace().emplace_back();
  g.id.id = 100;
  g.revision = 1;
  g.refPoint.lat = static_cast<m::Latitude>(std::lround(kOrigin.latitude_deg * 1e7));
  g.refPoint.long_ = static_cast<m::Longitude>(std::lround(kOrigin.longitude_deg * 1e7));
  g.laneWidth = 350;
  auto& in = g.laneSet.emplace_back();
  in.laneID = 1;
  in.laneAttributes.directionalUse = m::lane_direction::kIngressPath;
  m::NodeSetXY nodes;
  nodes.push_back(node(175, -1200));  // the stop line, from the refPoint
  for (int i = 0; i < 5; ++i)
    nodes.push_back(node(0, -5000));  // upstream, each from the node before
  in.nodeList = nodes;
  in.connectsTo.emplace().push_back({{2, m::allowed_maneuvers::kManeuverStraightAllowed},
                                     std::nullopt,
                                     kGroup,
                                     std::nullopt,
                                     std::nullopt});
  auto& out = g.laneSet.emplace_back();
  out.laneID = 2;
  out.laneAttributes.directionalUse = m::lane_direction::kEgressPath;
  m::NodeSetXY out_nodes;
  out_nodes.push_back(node(175, 1200));
  out_nodes.push_back(node(0, 5000));
  out.nodeList = out_nodes;
  return *m::encode(*msg);
}

/// The SPATEM at world time @p now of a run that started at @p start.
inline std::vector<std::uint8_t> spatem(clock::WallTime start, clock::WallTime now) {
  const double t = std::chrono::duration<double>(now - start).count();
  const auto at = [&](double s) {
    return m::time_mark_from_utc_ms(unix_ms(start) + std::llround(s * 1000));
  };
  auto msg = std::make_unique<m::Spatem>();
  msg->header.stationID = 5001;
  auto& is = msg->spat.intersections.emplace_back();
  is.id.id = 100;
  auto& ms = is.states.emplace_back();
  ms.signalGroup = kGroup;
  auto& e = ms.state_time_speed.emplace_back();
  e.timing.emplace();
  if (t < kAmberAtS) {
    e.eventState = m::MovementPhaseState::protected_Movement_Allowed;
    e.timing->startTime = at(-20.0);
    e.timing->minEndTime = at(kAmberAtS);
    e.timing->likelyTime = at(kAmberAtS);
  } else if (t < kRedAtS) {
    e.eventState = m::MovementPhaseState::protected_clearance;
    e.timing->startTime = at(kAmberAtS);
    e.timing->minEndTime = at(kRedAtS);
    e.timing->likelyTime = at(kRedAtS);
  } else {
    e.eventState = m::MovementPhaseState::stop_And_Remain;
    e.timing->startTime = at(kRedAtS);
    e.timing->minEndTime = at(kGreenAgainAtS);
    e.timing->likelyTime = at(kGreenAgainAtS);
  }
  return *m::encode(*msg);
}

/// The road-side unit's sending side: a GN router and BTP over a test link of its own, at the
/// junction, on the world's clock.
struct Rsu {
  explicit Rsu(clock::ManualRuntime& host)
      : its_clock(host),
        gn_position(gnss),
        link(mac_of(5001)),
        router(its_clock, link, gn_position, config()),
        btp(router),
        sender(btp) {}
  static geonet::RouterConfig config() {
    geonet::RouterConfig c;
    c.station_type = geonet::StationType::kRoadSideUnit;
    return c;
  }
  void fix(const clock::ManualRuntime& host, clock::WallTime world) {
    its_clock.on_fix(world);
    facilities::PositionFix f;
    f.time = world;
    f.received = host.steady_now();
    f.latitude_deg = kOrigin.latitude_deg;
    f.longitude_deg = kOrigin.longitude_deg;
    f.speed_mps = 0.0;
    f.course_deg = 0.0;
    f.heading_deg = 0.0;
    gnss.inject(f);
  }
  clock::GnssDisciplinedRuntime its_clock;
  facilities::InjectedPositionProvider gnss;
  GnPositionAdapter gn_position;
  link::TestLink link;
  geonet::Router router;
  btp::Dispatcher btp;
  BtpMessageSender sender;
};

/// The car's station and the RSU, and a run of fixes at 10 Hz along the lane.
struct SignalRun {
  explicit SignalRun(bool signals = true)
      : vehicle(make_vehicle(signals)),
        its_clock(host),
        link(mac_of(1001)),
        rsu(host),
        station(StationPorts{host, its_clock, gnss, nullptr, link, nullptr, &sink},
                make_station_config(1001, nullptr, &vehicle, StationOverrides{})) {
    station.start();
  }
  static scenario::Vehicle make_vehicle(bool signals) {
    scenario::Vehicle v;
    v.id = "car";
    v.station_id = 1001;
    v.station_signals = signals;
    v.station_lcrw = false;
    return v;
  }
  /// The world's time: the host's clock, as with an unpinned scenario.
  clock::WallTime world() const { return host.wall_now(); }
  /// Distance from the car's centre (the antenna) forward to its front, the CAM reference
  /// point the distances count from.
  double front_offset() const {
    return vehicle.model.length_m / 2.0 - vehicle.model.antenna.forward_m;
  }
  /// The car's receiver fix with the front @p d metres before the stop line, northbound.
  void fix(double d, double speed) {
    const double centre_y = kStopLineY - d - front_offset();
    const auto g = geodesy::LocalFrame(kOrigin).to_geodetic({kLaneX, centre_y, 0.0});
    facilities::PositionFix f;
    f.time = world();
    f.received = host.steady_now();
    f.latitude_deg = g.latitude_deg;
    f.longitude_deg = g.longitude_deg;
    f.speed_mps = speed;
    f.course_deg = 0.0;
    f.heading_deg = 0.0;
    f.position_confidence = facilities::PositionFix::Ellipse{2.0, 2.0, 0.0};
    f.speed_confidence_mps = 0.1;
    f.heading_confidence_deg = 1.0;
    ++sink.fix_index;
    gnss.inject(f);
  }
  /// The RSU sends @p bytes on @p port; the frame reaches the car.
  void air(std::uint16_t port, const std::vector<std::uint8_t>& bytes) {
    rsu.fix(host, world());
    rsu.link.sent().clear();
    if (rsu.sender.send_single_hop(port, bytes) != facilities::SendResult::kSent) {
      std::fprintf(stderr, "the RSU side could not send on port %u\n", unsigned{port});
      std::abort();
    }
    for (const auto& f : rsu.link.sent())
      link.inject(rsu.link.address(), f.destination, f.ethertype, f.payload, host.wall_now());
  }
  /// Drives at @p speed(t) from @p d0 metres before the line for @p seconds: at each 100 ms the
  /// SPATEM (and each second the MAPEM), then the fix. Returns the front's distance at each fix.
  template <typename Speed>
  std::vector<double> drive(double d0, double seconds, Speed speed) {
    std::vector<double> at_fix;
    const auto start = world();
    double d = d0;
    for (int i = 0; i * 0.1 <= seconds + 1e-9; ++i) {
      const double t = i * 0.1;
      const double v = speed(t);
      if (i > 0) {
        host.advance(100ms);
        d -= (v + speed(t - 0.1)) / 2.0 * 0.1;  // trapezoid: exact for constant deceleration
      }
      at_fix.push_back(d);
      fix(d, v);
      if (i % 10 == 0)
        air(facilities::kBtpPortMapem, mapem());
      air(facilities::kBtpPortSpatem, spatem(start, world()));
    }
    return at_fix;
  }

  clock::ManualRuntime host;
  scenario::Vehicle vehicle;
  clock::GnssDisciplinedRuntime its_clock;
  facilities::InjectedPositionProvider gnss;
  link::TestLink link;
  RecordingSink sink;
  Rsu rsu;
  Station station;
};

}  // namespace tb::its::station::testing
