// Two routers on the real AF_PACKET link: two network namespaces joined by a veth pair whose
// ends are both named wlan0, as the radio stand-in gives each station. One process opens each
// station's packet socket inside its namespace (setns on this thread, then back); the sockets
// stay bound to their namespaces, and one io_context drives both stations.

#include <gtest/gtest.h>

#include "common/clock/asio_runtime.hpp"
#include "its-station/btp/dispatcher.hpp"
#include "its-station/geonet/tests/netns_fixture.hpp"
#include "its-station/geonet/tests/router_fixture.hpp"

namespace tb::its {
namespace {

using namespace std::chrono_literals;
using geonet::testing::at;
using Bytes = std::vector<std::uint8_t>;

void set_fix(geonet::StaticPositionProvider& p, const clock::Runtime& rt, geonet::GeoPoint g) {
  p.set({rt.wall_now(), g.latitude_deg, g.longitude_deg, 5.0, 45.0, true});
}

using VethPair = testing::VethPair;

TEST_F(VethPair, TwoStationsExchangeBeaconsShbAndGbcOverAfPacket) {
  auto link_a = open_in(*a_);
  auto link_b = open_in(*b_);
  ASSERT_TRUE(link_a && link_b);
  EXPECT_NE(link_a->address(), link_b->address());
  EXPECT_EQ(link_a->driver(), "veth");
  EXPECT_EQ(link_a->interface(), "wlan0");

  clock::AsioRuntime rt{io};
  geonet::StaticPositionProvider pos_a, pos_b;
  set_fix(pos_a, rt, at(0, 0));
  set_fix(pos_b, rt, at(60, 0));
  geonet::RouterConfig fast;
  fast.beacon_interval = 100ms;
  fast.beacon_max_jitter = 20ms;
  geonet::Router router_a{rt, *link_a, pos_a, fast}, router_b{rt, *link_b, pos_b, fast};
  btp::Dispatcher btp_a{router_a}, btp_b{router_b};

  // Beacons over the wire teach each router its neighbour.
  ASSERT_TRUE(run_until([&] {
    return router_b.location_table().find(router_a.address().mid_key(), rt.steady_now()) &&
           router_a.location_table().find(router_b.address().mid_key(), rt.steady_now());
  }));
  EXPECT_GT(router_a.stats().beacons_sent, 0u);

  std::vector<Bytes> cams;
  geonet::DataIndication cam_gn;
  btp_b.register_port(btp::kPortCam, [&](const btp::Indication& i, auto payload) {
    cams.emplace_back(payload.begin(), payload.end());
    cam_gn = *i.gn;
  });
  const Bytes cam = {0x02, 0x02, 0x00, 0x00, 0x30, 0x39};
  set_fix(pos_a, rt, at(0, 0));
  const auto sent_at = rt.wall_now();
  ASSERT_EQ(btp_a.send_b(geonet::DataRequest::single_hop({}, 1s), btp::kPortCam, 0, cam),
            geonet::DataConfirm::kAccepted);
  ASSERT_TRUE(run_until([&] { return !cams.empty(); }));
  EXPECT_EQ(cams[0], cam);
  EXPECT_EQ(cam_gn.sender, link_a->address());
  EXPECT_EQ(cam_gn.source.mid, link_a->address());
  EXPECT_EQ(cam_gn.packet_type, geonet::PacketType::kSingleHopBroadcast);
  // The kernel's receive stamp lies between sending and now.
  EXPECT_GE(cam_gn.rx_time, sent_at);
  EXPECT_LE(cam_gn.rx_time, rt.wall_now());
  EXPECT_GT(cam_gn.remaining_lifetime, 500ms);

  std::vector<Bytes> denms;
  std::optional<geonet::GeoArea> denm_area;
  btp_a.register_port(btp::kPortDenm, [&](const btp::Indication& i, auto payload) {
    denms.emplace_back(payload.begin(), payload.end());
    denm_area = i.gn->destination_area;
  });
  const auto area = geonet::testing::circle_at(at(20, 0), 200);
  set_fix(pos_b, rt, at(60, 0));
  ASSERT_EQ(btp_b.send_b(geonet::DataRequest::geo_broadcast(area), btp::kPortDenm, 0, Bytes{7, 7}),
            geonet::DataConfirm::kAccepted);
  ASSERT_TRUE(run_until([&] { return !denms.empty(); }));
  EXPECT_EQ(denms[0], (Bytes{7, 7}));
  EXPECT_EQ(denm_area, area);
  // A rebroadcast the GBC inside the area; B dropped that copy of its own packet.
  ASSERT_TRUE(run_until([&] { return router_b.stats().dropped(geonet::DropReason::kOwnPacket); }));
  EXPECT_EQ(router_a.stats().forwarded, 1u);
  EXPECT_EQ(link_b->stats().delivered, router_b.stats().received);
  EXPECT_EQ(link_a->stats().truncated + link_a->stats().receive_errors, 0u);
  EXPECT_EQ(router_a.stats().dropped(geonet::DropReason::kParseError), 0u);
}

}  // namespace
}  // namespace tb::its
