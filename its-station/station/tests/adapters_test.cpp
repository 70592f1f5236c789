// The station's layers joined as the program joins them, with in-memory links: two stations
// exchange CAMs (GN SHB) and DENMs (GN GBC) through the real router and BTP, and each sees the
// other in its LDM.

#include <gtest/gtest.h>

#include <memory>

#include "common/clock/runtime.hpp"
#include "common/geodesy/local_frame.hpp"
#include "its-station/facilities/ca_service.hpp"
#include "its-station/link/test_link.hpp"
#include "its-station/station/adapters.hpp"

namespace tb::its::station {
namespace {

using namespace std::chrono_literals;

const geodesy::LocalFrame kFrame{{48.0, 11.0, 500.0}};

facilities::DenConfig den_config(std::uint32_t id) {
  facilities::DenConfig c;
  c.station_id = id;
  return c;
}

struct Station {
  Station(clock::ManualRuntime& rt, std::uint32_t id, link::MacAddress mac)
      : link(mac),
        gn_position(position),
        router(rt, link, gn_position),
        btp(router),
        sender(btp),
        ldm(rt),
        ca(rt, position, nullptr, sender, ldm, ca_config(id)),
        den(rt, sender, ldm, den_config(id)),
        port(den, 100ms, 1s) {
    btp.register_port(facilities::kBtpPortCam,
                      [this](const btp::Indication& ind, std::span<const std::uint8_t> p) {
                        ca.receive(p, ind.gn->rx_time);
                      });
    btp.register_port(facilities::kBtpPortDenm,
                      [this](const btp::Indication& ind, std::span<const std::uint8_t> p) {
                        den.receive(p, den_reception(ind));
                      });
  }
  static facilities::CaConfig ca_config(std::uint32_t id) {
    facilities::CaConfig c;
    c.station_id = id;
    c.vehicle_length_m = 4.5;
    c.vehicle_width_m = 1.8;
    return c;
  }
  void move_to(clock::ManualRuntime& rt, double east, double north, double heading, double speed) {
    facilities::PositionFix f;
    const auto g = kFrame.to_geodetic({east, north, 0.0});
    f.time = rt.wall_now();
    f.received = rt.steady_now();
    f.latitude_deg = g.latitude_deg;
    f.longitude_deg = g.longitude_deg;
    f.heading_deg = heading;
    f.speed_mps = speed;
    f.position_confidence = facilities::PositionFix::Ellipse{3.0, 3.0, 0.0};
    position.inject(f);
  }

  link::TestLink link;
  facilities::InjectedPositionProvider position;
  GnPositionAdapter gn_position;
  geonet::Router router;
  btp::Dispatcher btp;
  BtpMessageSender sender;
  facilities::Ldm ldm;
  facilities::CaService ca;
  facilities::DenService den;
  DenPortAdapter port;
};

class TwoStations : public ::testing::Test {
 protected:
  void SetUp() override {
    a = std::make_unique<Station>(rt, 1001, link::MacAddress{2, 0, 0, 0, 0, 1});
    b = std::make_unique<Station>(rt, 1002, link::MacAddress{2, 0, 0, 0, 0, 2});
    connect(*a, *b);
    connect(*b, *a);
  }
  void connect(Station& from, Station& to) {
    from.link.set_send_observer([this, &from, &to](const link::TestLink::SentFrame& f) {
      to.link.inject(from.link.address(), f.destination, f.ethertype, f.payload, rt.wall_now());
    });
  }
  clock::ManualRuntime rt;
  std::unique_ptr<Station> a, b;
};

TEST_F(TwoStations, CamsReachTheOtherLdmWithPositionAndSpeed) {
  a->move_to(rt, 0, 0, 90, 13.9);
  b->move_to(rt, 100, 3.5, 270, 8.0);
  a->ca.start();
  b->ca.start();
  for (int k = 1; k <= 20; ++k) {
    rt.advance(100ms);
    a->move_to(rt, 1.39 * k, 0, 90, 13.9);
    b->move_to(rt, 100 - 0.8 * k, 3.5, 270, 8.0);
  }
  const auto* seen_by_b = b->ldm.neighbour(1001);
  const auto* seen_by_a = a->ldm.neighbour(1002);
  ASSERT_NE(seen_by_b, nullptr);
  ASSERT_NE(seen_by_a, nullptr);
  EXPECT_NEAR(*seen_by_b->latest().speed_mps, 13.9, 0.01);
  EXPECT_NEAR(*seen_by_b->latest().heading_deg, 90.0, 0.1);
  EXPECT_NEAR(*seen_by_a->latest().speed_mps, 8.0, 0.01);
  // The position is that of the last CAM's fix: within one CAM's travel of the current one.
  const auto enu =
      kFrame.to_enu({seen_by_b->latest().latitude_deg, seen_by_b->latest().longitude_deg, 500.0});
  EXPECT_NEAR(enu.north, 0.0, 0.05);
  EXPECT_GT(enu.east, 27.8 - 5.0);
  EXPECT_LE(enu.east, 27.8 + 0.05);
  EXPECT_GE(b->ca.counters().received, 4u);
  EXPECT_EQ(b->ca.counters().decode_errors, 0u);
  // Every CAM on the air: GN SHB with traffic class 2 and a lifetime of 1 s.
  std::size_t cams = 0;
  for (const auto& f : a->link.sent()) {
    const auto p = geonet::parse_packet(f.payload);
    ASSERT_TRUE(p);
    if (p->common.type != geonet::PacketType::kSingleHopBroadcast)
      continue;
    ++cams;
    EXPECT_EQ(p->common.traffic_class, (geonet::TrafficClass{false, false, 2}));
    EXPECT_EQ(p->basic.lifetime.duration(), 1s);
  }
  EXPECT_GE(cams, 4u);

  // The LCRW view of the neighbour: bounding-box centre half a length behind the reference.
  const auto k = neighbour_kinematics(*seen_by_b);
  EXPECT_NEAR(*k.length_m, 4.5, 1e-9);
  const auto v = lcrw_kinematics(1001, k, seen_by_b->latest().generation_time, kFrame);
  EXPECT_NEAR(v.x, enu.east - 2.25, 0.05);
}

TEST_F(TwoStations, DenmFromTheAppPortIsGeoBroadcastAndCancelled) {
  a->move_to(rt, 0, 0, 90, 10.0);
  b->move_to(rt, 50, 0, 270, 10.0);
  apps::DenEventRequest r;
  const auto g = kFrame.to_geodetic({10.0, 0.0, 0.0});
  r.event_position = g;
  r.detection_time = rt.wall_now();
  r.relevance_distance = apps::RelevanceDistance::kLessThan100m;
  r.validity_duration = std::chrono::seconds{10};
  r.traffic_class = 0;  // as LCRW asks
  auto id = a->port.trigger(r);
  ASSERT_TRUE(id);
  const auto* e = b->ldm.event({id->originating_station_id, id->sequence_number});
  ASSERT_NE(e, nullptr);  // B at 40 m from the event is inside the 100 m circle
  EXPECT_EQ(e->denm.denm.situation->eventType.causeCode, apps::kCauseCollisionRisk);
  const auto view = denm_view(e->denm);
  EXPECT_NEAR(view.event_latitude_deg, g.latitude_deg, 1e-7);
  EXPECT_EQ(view.relevance_distance, apps::RelevanceDistance::kLessThan100m);
  EXPECT_EQ(view.validity_duration_s, 10u);
  // On the air: a GBC with traffic class 0.
  bool seen_gbc = false;
  for (const auto& f : a->link.sent()) {
    const auto p = geonet::parse_packet(f.payload);
    ASSERT_TRUE(p);
    if (p->common.type == geonet::PacketType::kGeoBroadcastCircle) {
      seen_gbc = true;
      EXPECT_EQ(p->common.traffic_class, (geonet::TrafficClass{false, false, 0}));
    }
  }
  EXPECT_TRUE(seen_gbc);
  rt.advance(300ms);
  ASSERT_TRUE(a->port.terminate(*id));
  EXPECT_EQ(b->ldm.event({id->originating_station_id, id->sequence_number}), nullptr);
  EXPECT_FALSE(a->port.update(*id, r));
}

TEST(Adapters, PositionForTheRouter) {
  facilities::InjectedPositionProvider p;
  GnPositionAdapter gn(p);
  EXPECT_FALSE(gn.current_position());
  facilities::PositionFix f;
  f.latitude_deg = 48.0;
  f.longitude_deg = 11.0;
  f.speed_mps = 3.0;
  f.heading_deg = 45.0;
  f.position_confidence = facilities::PositionFix::Ellipse{90.0, 10.0, 0.0};
  p.inject(f);
  auto e = gn.current_position();
  ASSERT_TRUE(e);
  EXPECT_DOUBLE_EQ(e->speed_mps, 3.0);
  EXPECT_DOUBLE_EQ(e->heading_deg, 45.0);
  EXPECT_FALSE(e->accurate);  // 90 m > itsGnPaiInterval
  f.position_confidence->semi_major_m = 5.0;
  p.inject(f);
  EXPECT_TRUE(gn.current_position()->accurate);
}

TEST(Adapters, SendResultsFromDataConfirm) {
  EXPECT_EQ(to_send_result(geonet::DataConfirm::kAccepted), facilities::SendResult::kSent);
  EXPECT_EQ(to_send_result(geonet::DataConfirm::kNoPosition), facilities::SendResult::kNoPosition);
  EXPECT_EQ(to_send_result(geonet::DataConfirm::kMaxSduSizeExceeded),
            facilities::SendResult::kTooLarge);
  EXPECT_EQ(to_send_result(geonet::DataConfirm::kLinkError), facilities::SendResult::kLinkError);
}

}  // namespace
}  // namespace tb::its::station

namespace tb::its::station {
namespace {

// LCRW's path prediction takes the neighbour's yaw rate and curvature from its CAM (issue 22):
// YawRate in 0.01 °/s, Curvature in 1/10000 m⁻¹ (protocolVersion 2) or 1/30000 m⁻¹ (version 1).
TEST(Adapters, NeighbourYawRateAndCurvatureFromTheCam) {
  facilities::Neighbour n;
  n.history.push_front({});
  auto cam = std::make_shared<messages::Cam>();
  n.last_cam = cam;
  auto& hf = (*messages::vehicle_hf(cam->cam.camParameters));
  hf.yawRate.yawRateValue = 764;     // 7.64 °/s
  hf.curvature.curvatureValue = 67;  // 0.0067 m⁻¹, radius 149 m
  auto k = neighbour_kinematics(n);
  ASSERT_TRUE(k.yaw_rate_dps);
  EXPECT_DOUBLE_EQ(*k.yaw_rate_dps, 7.64);
  ASSERT_TRUE(k.curvature_per_m);
  EXPECT_DOUBLE_EQ(*k.curvature_per_m, 0.0067);
  cam->header.protocolVersion = messages::kProtocolVersion1;
  hf.curvature.curvatureValue = 200;  // 200 / 30000 m⁻¹, radius 150 m
  k = neighbour_kinematics(n);
  EXPECT_DOUBLE_EQ(*k.curvature_per_m, 200.0 / 30000.0);
  hf.curvature.curvatureValue = messages::kCurvatureValueUnavailableV1;
  hf.yawRate.yawRateValue = messages::kYawRateValueUnavailable;
  k = neighbour_kinematics(n);
  EXPECT_FALSE(k.curvature_per_m);
  EXPECT_FALSE(k.yaw_rate_dps);
  cam->header.protocolVersion = messages::kProtocolVersion;
  hf.curvature.curvatureValue = messages::kCurvatureValueUnavailable;
  EXPECT_FALSE(neighbour_kinematics(n).curvature_per_m);
  // Into LCRW's kinematics unchanged.
  hf.yawRate.yawRateValue = -382;
  hf.curvature.curvatureValue = -67;
  const geodesy::LocalFrame frame({41.1, 29.0, 0.0});
  const auto v = lcrw_kinematics(7, neighbour_kinematics(n), clock::WallTime{}, frame);
  EXPECT_DOUBLE_EQ(*v.yaw_rate_dps, -3.82);
  EXPECT_DOUBLE_EQ(*v.curvature_per_m, -0.0067);
}

}  // namespace
}  // namespace tb::its::station
