#include <gtest/gtest.h>

#include "its-station/geonet/tests/network_topology.hpp"

namespace tb::its::geonet {
namespace {

using namespace std::chrono_literals;
using namespace testing;

// Five stations on a line, 100 m apart, radio range 150 m: each hears only its direct
// neighbours. Simple GeoBroadcast forwarding inside areas, so that a dispatch shows every hop
// at once (contention-based forwarding, the default, has its own tests below).
class LineTopology : public ::testing::Test {
 protected:
  void SetUp() override {
    RouterConfig config;
    config.area_forwarding = RouterConfig::AreaForwarding::kSimple;
    for (std::uint8_t i = 0; i < 5; ++i)
      net.add_station(i, at(100.0 * i, 0), config);
    net.advance_time(4s);  // everyone has beaconed at least once
  }
  std::vector<std::size_t> deliveries() {
    std::vector<std::size_t> n;
    for (std::uint8_t i = 0; i < 5; ++i)
      n.push_back(net.station(i).received.size());
    return n;
  }

  NetworkTopology net{150.0};
  const Bytes payload{0x07, 0xd2, 0x00, 0x00, 0x42};
};

TEST_F(LineTopology, BeaconsTeachEachStationItsNeighbours) {
  int neighbours_of_2 = 0;
  net.station(2).router->location_table().for_each_neighbour(
      net.runtime().steady_now(), [&](const LocationTableEntry& e) {
        ++neighbours_of_2;
        EXPECT_TRUE(e.address.mid == mac(1) || e.address.mid == mac(3));
      });
  EXPECT_EQ(neighbours_of_2, 2);
}

TEST_F(LineTopology, ShbReachesOnlyTheDirectNeighbours) {
  ASSERT_EQ(net.station(2).router->request(DataRequest::single_hop(), payload),
            DataConfirm::kAccepted);
  net.dispatch();
  EXPECT_EQ(deliveries(), (std::vector<std::size_t>{0, 1, 0, 1, 0}));
  EXPECT_EQ(net.station(1).received[0].payload, payload);
}

TEST_F(LineTopology, TsbTravelsAsManyHopsAsItsHopLimitAndIsDeliveredOnce) {
  ASSERT_EQ(net.station(0).router->request(DataRequest::topologically_scoped(3), payload),
            DataConfirm::kAccepted);
  net.dispatch();
  EXPECT_EQ(deliveries(), (std::vector<std::size_t>{0, 1, 1, 1, 0}));
  EXPECT_EQ(net.station(3).received[0].indication.remaining_hop_limit, 1);
  EXPECT_EQ(net.station(3).received[0].indication.sender, mac(2));
  EXPECT_EQ(net.station(3).received[0].indication.source.mid, mac(0));
  // Rebroadcasts heard by the stations that already had the packet are duplicates.
  EXPECT_EQ(net.station(1).dropped(DropReason::kDuplicate), 1u);
  EXPECT_EQ(net.station(0).dropped(DropReason::kOwnPacket), 1u);
  EXPECT_EQ(net.station(3).dropped(DropReason::kNotForwardedHopLimit), 1u);
}

TEST_F(LineTopology, GbcFromOutsideTheAreaIsForwardedGreedilyThenFloodedInside) {
  // Circle of 120 m around station 4: stations 3 and 4 are inside.
  const GeoArea area = circle_at(at(400, 0), 120);
  const std::size_t before = net.frames_sent();
  ASSERT_EQ(net.station(0).router->request(DataRequest::geo_broadcast(area), payload),
            DataConfirm::kAccepted);
  net.dispatch();
  EXPECT_EQ(deliveries(), (std::vector<std::size_t>{0, 0, 0, 1, 1}));
  // 0→1→2→3 unicast, then 3 and 4 rebroadcast inside the area: five frames in all.
  EXPECT_EQ(net.frames_sent() - before, 5u);
  EXPECT_EQ(net.station(4).received[0].indication.destination_area, area);
  // Station 2 hears 3's broadcast from inside the area and leaves it alone.
  EXPECT_EQ(net.station(2).dropped(DropReason::kNoForwardingNeighbour), 0u);
  EXPECT_EQ(net.station(4).received[0].payload, payload);
}

TEST_F(LineTopology, GbcFromInsideTheAreaReachesEveryStationInIt) {
  const GeoArea area = circle_at(at(200, 0), 150);  // stations 1, 2 and 3
  ASSERT_EQ(net.station(2).router->request(DataRequest::geo_broadcast(area), payload),
            DataConfirm::kAccepted);
  net.dispatch();
  EXPECT_EQ(deliveries(), (std::vector<std::size_t>{0, 1, 0, 1, 0}));
  EXPECT_EQ(net.station(0).dropped(DropReason::kOutsideArea), 1u);
  EXPECT_EQ(net.station(4).dropped(DropReason::kOutsideArea), 1u);
}

TEST_F(LineTopology, GbcStopsWhereNoNeighbourLeadsTowardsTheArea) {
  net.set_blocked(2, 3, true);
  net.advance_time(21s);  // 2 forgets 3 once its location table entry expires
  ASSERT_EQ(net.station(0).router->request(DataRequest::geo_broadcast(circle_at(at(400, 0), 50)),
                                           payload),
            DataConfirm::kAccepted);
  net.dispatch();
  // Annex E.2: 2 is a local optimum and broadcasts; 3 does not hear it, 1 drops the copy.
  EXPECT_EQ(deliveries(), (std::vector<std::size_t>{0, 0, 0, 0, 0}));
  EXPECT_EQ(net.station(2).dropped(DropReason::kNoForwardingNeighbour), 0u);
  EXPECT_EQ(net.station(1).dropped(DropReason::kDuplicate), 1u);

  // With store-carry-forward the packet would wait in a buffer this router does not have.
  auto scf = DataRequest::geo_broadcast(circle_at(at(400, 0), 50));
  scf.traffic_class.store_carry_forward = true;
  ASSERT_EQ(net.station(0).router->request(scf, payload), DataConfirm::kAccepted);
  net.dispatch();
  EXPECT_EQ(net.station(2).dropped(DropReason::kNoForwardingNeighbour), 1u);
}

// Stations 1 and 2 both hear the source 0; only 2 hears 3. With contention-based forwarding 2,
// being farther from 0, rebroadcasts first and 1 stands down; with simple forwarding both do.
class ContentionTopology : public ::testing::TestWithParam<RouterConfig::AreaForwarding> {
 protected:
  void SetUp() override {
    RouterConfig config;
    config.area_forwarding = GetParam();
    net.add_station(0, at(0, 0), config);
    net.add_station(1, at(50, 0), config);
    net.add_station(2, at(100, 0), config);
    net.add_station(3, at(200, 0), config);
    net.advance_time(4s, 1ms);
  }
  NetworkTopology net{120.0};
};

TEST_P(ContentionTopology, EveryStationInTheAreaGetsThePacketOnce) {
  ASSERT_EQ(net.station(0).router->request(DataRequest::geo_broadcast(circle_at(at(100, 0), 500)),
                                           Bytes{1, 2, 3}),
            DataConfirm::kAccepted);
  net.dispatch();
  net.advance_time(300ms, 1ms);
  for (std::uint8_t i = 1; i <= 3; ++i)
    EXPECT_EQ(net.station(i).received.size(), 1u) << int{i};
  const bool cbf = GetParam() == RouterConfig::AreaForwarding::kContentionBased;
  std::uint64_t rebroadcasts = 0;
  for (std::uint8_t i = 1; i <= 3; ++i)
    rebroadcasts += net.station(i).router->stats().forwarded;
  EXPECT_EQ(rebroadcasts, cbf ? 2u : 3u);
  EXPECT_EQ(net.station(1).router->stats().forwarded, cbf ? 0u : 1u);
  EXPECT_EQ(net.station(1).dropped(DropReason::kContentionLost), cbf ? 1u : 0u);
  EXPECT_EQ(net.station(2).router->stats().forwarded, 1u);
}

INSTANTIATE_TEST_SUITE_P(AreaForwarding, ContentionTopology,
                         ::testing::Values(RouterConfig::AreaForwarding::kSimple,
                                           RouterConfig::AreaForwarding::kContentionBased));

}  // namespace
}  // namespace tb::its::geonet
