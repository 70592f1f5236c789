// MapData / SPAT frames (as decoded from the air) into the signal application's model. The
// messages are built here and sent through the codec; expected positions come from the
// geometry the test lays out (and the WGS84 frame for node-LatLon), times from the UTC clock.
#include "its-station/apps/signal/dsrc_convert.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <memory>

#include "common/clock/utc.hpp"
#include "common/geodesy/local_frame.hpp"
#include "its-station/messages/mapem.hpp"
#include "its-station/messages/spatem.hpp"

namespace tb::its::apps::signal {
namespace {

namespace m = messages;
using namespace std::chrono_literals;

constexpr double kRefLat = 48.137154;
constexpr double kRefLon = 11.576124;

m::NodeXY node(std::int32_t x_cm, std::int32_t y_cm) {
  m::NodeXY n;
  n.delta = m::node_xy(x_cm, y_cm);
  return n;
}

// An ingress lane from the south, 1.5 m west of the centre line: stop line 10 m south of the
// refPoint, nodes every 20 m upstream; one egress lane leaving north; laneWidth 3.2 m.
std::unique_ptr<m::Mapem> hand_made_mapem() {
  auto mapem = std::make_unique<m::Mapem>();
  mapem->header.stationID = 5001;
  auto& g = mapem->map.intersections.emplace().emplace_back();
  g.id.id = 100;
  g.revision = 3;
  g.refPoint.lat = static_cast<m::Latitude>(std::lround(kRefLat * 1e7));
  g.refPoint.long_ = static_cast<m::Longitude>(std::lround(kRefLon * 1e7));
  g.laneWidth = 320;
  g.speedLimits.emplace().push_back({m::SpeedLimitType::vehicleMaxSpeed, 695});  // 13.9 m/s

  auto& in = g.laneSet.emplace_back();
  in.laneID = 1;
  in.laneAttributes.directionalUse = m::lane_direction::kIngressPath;
  m::NodeSetXY nodes;
  nodes.push_back(node(-150, -1000));  // from the refPoint: the stop line
  nodes.push_back(node(0, -2000));     // each next one from the node before
  nodes.push_back(node(0, -2000));
  nodes.push_back(node(300, -2000));  // a kink 3 m east
  in.nodeList = nodes;
  in.connectsTo.emplace().push_back({{2, m::allowed_maneuvers::kManeuverStraightAllowed},
                                     std::nullopt,
                                     std::uint8_t{7},
                                     std::nullopt,
                                     std::nullopt});

  auto& out = g.laneSet.emplace_back();
  out.laneID = 2;
  out.laneAttributes.directionalUse = m::lane_direction::kEgressPath;
  m::NodeSetXY out_nodes;
  out_nodes.push_back(node(-150, 1000));
  // node-LatLon: an absolute position, 30 m north of the refPoint and 1.5 m west.
  const geodesy::LocalFrame frame({kRefLat, kRefLon, 0.0});
  const auto far = frame.to_geodetic({-1.5, 30.0, 0.0});
  m::NodeXY ll;
  ll.delta.choice = m::NodeOffsetPointXY::Choice::node_LatLon;
  ll.delta.x = static_cast<std::int32_t>(std::lround(far.longitude_deg * 1e7));
  ll.delta.y = static_cast<std::int32_t>(std::lround(far.latitude_deg * 1e7));
  out_nodes.push_back(ll);
  out_nodes.push_back(node(0, 500));  // 5 m on from the absolute node
  out.nodeList = out_nodes;
  return mapem;
}

TEST(SignalDsrcConvert, NodeOffsetsAccumulateFromTheRefPoint) {
  const auto sent = hand_made_mapem();
  const auto bytes = m::encode(*sent);
  ASSERT_TRUE(bytes) << asn1::to_string(bytes.error());
  auto rx = std::make_unique<m::Mapem>();
  ASSERT_TRUE(m::decode(*bytes, *rx));
  const auto received = clock::WallTime{1'795'000'000'000ms};
  const auto t = topology_from_geometry((*rx->map.intersections)[0], received);
  ASSERT_TRUE(t) << t.error().message;
  EXPECT_EQ(t->intersection_id, 100);
  EXPECT_EQ(t->revision, 3);
  EXPECT_EQ(t->received_at, received);
  EXPECT_NEAR(t->ref_latitude_deg, kRefLat, 1e-7);
  EXPECT_NEAR(t->ref_longitude_deg, kRefLon, 1e-7);
  ASSERT_TRUE(t->speed_limit_mps);
  EXPECT_NEAR(*t->speed_limit_mps, 13.9, 1e-9);
  EXPECT_FALSE(validate(*t)) << validate(*t)->message;

  const GenericLane* in = t->lane(1);
  ASSERT_NE(in, nullptr);
  EXPECT_TRUE(in->ingress);
  EXPECT_FALSE(in->egress);
  EXPECT_DOUBLE_EQ(in->lane_width_m, 3.2);
  // Laid out above: stop line 10 m south, then 20 m steps south, the last one 3 m east too.
  const double xs[] = {-1.5, -1.5, -1.5, 1.5};
  const double ys[] = {-10.0, -30.0, -50.0, -70.0};
  ASSERT_EQ(in->nodes.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(in->nodes[i].x, xs[i], 1e-9) << "node " << i;
    EXPECT_NEAR(in->nodes[i].y, ys[i], 1e-9) << "node " << i;
  }
  ASSERT_EQ(in->connects_to.size(), 1u);
  EXPECT_EQ(in->connects_to[0].connecting_lane, 2);
  EXPECT_EQ(in->connects_to[0].signal_group, 7);

  const GenericLane* out = t->lane(2);
  ASSERT_NE(out, nullptr);
  EXPECT_TRUE(out->egress);
  EXPECT_FALSE(out->ingress);
  ASSERT_EQ(out->nodes.size(), 3u);
  EXPECT_NEAR(out->nodes[0].y, 10.0, 1e-9);
  // The absolute node comes back where it was put (0.1 µdeg is 1.1 cm of latitude).
  EXPECT_NEAR(out->nodes[1].x, -1.5, 0.02);
  EXPECT_NEAR(out->nodes[1].y, 30.0, 0.02);
  EXPECT_NEAR(out->nodes[2].x, -1.5, 0.02);
  EXPECT_NEAR(out->nodes[2].y, 35.0, 0.02);
}

TEST(SignalDsrcConvert, DirectionalUseBothWaysAndWidthFromFirstNode) {
  auto mapem = hand_made_mapem();
  auto& g = (*mapem->map.intersections)[0];
  g.laneSet[0].laneAttributes.directionalUse =
      m::lane_direction::kIngressPath | m::lane_direction::kEgressPath;
  auto& first = std::get<m::NodeSetXY>(g.laneSet[0].nodeList)[0];
  first.attributes.emplace().dWidth = -20;
  g.laneWidth.reset();
  g.speedLimits.reset();
  const auto t = topology_from_geometry(g, {});
  ASSERT_TRUE(t);
  EXPECT_TRUE(t->lanes[0].ingress);
  EXPECT_TRUE(t->lanes[0].egress);
  EXPECT_DOUBLE_EQ(t->lanes[0].lane_width_m, kDefaultLaneWidthM - 0.2);
  EXPECT_DOUBLE_EQ(t->lanes[1].lane_width_m, kDefaultLaneWidthM);
  EXPECT_FALSE(t->speed_limit_mps);
}

TEST(SignalDsrcConvert, ComputedLaneIsRefusedByName) {
  auto mapem = hand_made_mapem();
  auto& g = (*mapem->map.intersections)[0];
  m::ComputedLane c;
  c.referenceLaneId = 1;
  g.laneSet[1].nodeList = c;
  const auto t = topology_from_geometry(g, {});
  ASSERT_FALSE(t);
  EXPECT_NE(t.error().message.find("lane 2"), std::string::npos) << t.error().message;
  EXPECT_NE(t.error().message.find("computed"), std::string::npos) << t.error().message;
}

// A light turning red 15 s after 11:59:50 UTC: its TimeMarks count from the next hour (150),
// and the receiver must place them there, not 59:45 minutes back.
TEST(SignalDsrcConvert, TimeMarksBecomeUtcNearTheOwnClockAcrossTheHour) {
  const auto now = clock::parse_utc("2026-11-27T11:59:50Z");
  ASSERT_TRUE(now);
  const std::int64_t now_ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(now->time_since_epoch()).count();
  auto spatem = std::make_unique<m::Spatem>();
  auto& is = spatem->spat.intersections.emplace_back();
  is.id.id = 100;
  is.revision = 1;
  auto& ms = is.states.emplace_back();
  ms.signalGroup = 7;
  auto& green = ms.state_time_speed.emplace_back();
  green.eventState = m::MovementPhaseState::protected_Movement_Allowed;
  green.timing.emplace();
  green.timing->startTime = m::time_mark_from_utc_ms(now_ms - 20'000);
  green.timing->minEndTime = m::time_mark_from_utc_ms(now_ms + 12'000);
  green.timing->likelyTime = m::time_mark_from_utc_ms(now_ms + 12'000);
  green.timing->maxEndTime = m::kTimeMarkUnknown;
  auto& amber = ms.state_time_speed.emplace_back();
  amber.eventState = m::MovementPhaseState::protected_clearance;
  amber.timing.emplace();
  amber.timing->minEndTime = m::time_mark_from_utc_ms(now_ms + 15'000);
  auto& other = is.states.emplace_back();
  other.signalGroup = 8;
  other.state_time_speed.emplace_back().eventState = m::MovementPhaseState::stop_And_Remain;

  const auto bytes = m::encode(*spatem);
  ASSERT_TRUE(bytes);
  auto rx = std::make_unique<m::Spatem>();
  ASSERT_TRUE(m::decode(*bytes, *rx));
  const auto phases = phases_from_state(rx->spat.intersections[0], *now, *now);
  ASSERT_EQ(phases.size(), 2u);
  const SignalPhase& p = phases[0];
  EXPECT_EQ(p.signal_group, 7);
  EXPECT_EQ(p.received_at, *now);
  EXPECT_EQ(p.current.state, MovementPhaseState::kProtectedMovementAllowed);
  ASSERT_TRUE(p.current.start_time && p.current.min_end_time && p.current.likely_time);
  EXPECT_EQ(*p.current.start_time, *now - 20s);
  EXPECT_EQ(*p.current.min_end_time, *now + 12s);
  EXPECT_EQ(*p.current.likely_time, *now + 12s);
  EXPECT_FALSE(p.current.max_end_time);  // 36001: unknown
  ASSERT_EQ(p.upcoming.size(), 1u);
  EXPECT_EQ(p.upcoming[0].state, MovementPhaseState::kProtectedClearance);
  EXPECT_EQ(*p.upcoming[0].min_end_time, *now + 15s);
  EXPECT_EQ(phases[1].signal_group, 8);
  EXPECT_EQ(phases[1].current.state, MovementPhaseState::kStopAndRemain);
  EXPECT_FALSE(phases[1].current.min_end_time);
}

}  // namespace
}  // namespace tb::its::apps::signal
