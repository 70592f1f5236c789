#include <gtest/gtest.h>

#include <memory>
#include <set>

#include "its-station/geonet/router.hpp"
#include "its-station/geonet/tests/router_fixture.hpp"
#include "its-station/link/test_link.hpp"

namespace tb::its::geonet {
namespace {

using namespace std::chrono_literals;
using namespace testing;

class RouterTest : public ::testing::Test {
 protected:
  void start(RouterConfig config = {}) {
    router = std::make_unique<Router>(rt, link, position, config);
    router->set_indication_handler([this](const DataIndication& ind, auto payload) {
      delivered.push_back({ind, Bytes(payload.begin(), payload.end())});
    });
    router->set_drop_hook([this](const DropEvent& e) { drops.push_back(e); });
  }
  void set_position(const GeoPoint& p) {
    position.set({rt.wall_now(), p.latitude_deg, p.longitude_deg, 13.89, 90.0, true});
  }
  Timestamp now_tst() const { return to_timestamp(rt.wall_now()); }
  void receive(const Bytes& bytes, link::MacAddress from, link::MacAddress to = link::kBroadcastMac,
               std::uint16_t ethertype = link::kEtherTypeGeoNetworking) {
    link.inject(from, to, ethertype, bytes, rt.wall_now());
  }
  std::vector<DropReason> drop_reasons() const {
    std::vector<DropReason> r;
    for (const auto& d : drops)
      r.push_back(d.reason);
    return r;
  }
  Packet sent_packet(std::size_t i) {
    auto p = parse_packet(link.sent().at(i).payload);
    EXPECT_TRUE(p);
    return *p;
  }

  clock::ManualRuntime rt;
  link::TestLink link{mac(1)};
  StaticPositionProvider position;
  std::unique_ptr<Router> router;
  std::vector<std::pair<DataIndication, Bytes>> delivered;
  std::vector<DropEvent> drops;
};

TEST_F(RouterTest, ShbCarriesTheEgoPositionVectorAndTheGnAddress) {
  start();
  const clock::WallTime fix_time = rt.wall_now() - 40ms;
  position.set({fix_time, 48.15, -1.6, 13.89, 90.0, true});
  const Bytes payload = {0x07, 0xd1, 0, 0, 1, 2, 3};
  ASSERT_EQ(router->request(DataRequest::single_hop({false, false, 2}, 1s), payload),
            DataConfirm::kAccepted);
  ASSERT_EQ(link.sent().size(), 1u);
  EXPECT_EQ(link.sent()[0].destination, link::kBroadcastMac);
  EXPECT_EQ(link.sent()[0].ethertype, link::kEtherTypeGeoNetworking);
  const Packet p = sent_packet(0);
  EXPECT_EQ(p.common.type, PacketType::kSingleHopBroadcast);
  EXPECT_EQ(p.basic.remaining_hop_limit, 1);
  EXPECT_EQ(p.common.maximum_hop_limit, 1);
  EXPECT_EQ(p.basic.lifetime.duration(), 1s);
  EXPECT_EQ(p.common.traffic_class.id, 2);
  const auto& pv = source_position(p.extended);
  EXPECT_EQ(pv.address, (GnAddress{false, StationType::kPassengerCar, mac(1)}));
  EXPECT_EQ(pv.timestamp, to_timestamp(fix_time));
  EXPECT_EQ(pv.latitude, 481'500'000);
  EXPECT_EQ(pv.longitude, -16'000'000);
  EXPECT_EQ(pv.speed, 1389);
  EXPECT_EQ(pv.heading, 900);
  EXPECT_TRUE(pv.position_accurate);
  EXPECT_EQ(Bytes(p.payload.begin(), p.payload.end()), payload);
}

TEST_F(RouterTest, ConfigurationsThatCannotWorkAreRefused) {
  auto make = [&](auto change) {
    RouterConfig c;
    change(c);
    Router r{rt, link, position, c};
  };
  EXPECT_THROW(make([](RouterConfig& c) { c.beacon_interval = 0ms; }), std::invalid_argument);
  EXPECT_THROW(make([](RouterConfig& c) { c.beacon_max_jitter = -1ms; }), std::invalid_argument);
  EXPECT_THROW(make([](RouterConfig& c) { c.location_entry_lifetime = 0s; }),
               std::invalid_argument);
  EXPECT_THROW(make([](RouterConfig& c) { c.default_hop_limit = 0; }), std::invalid_argument);
  EXPECT_THROW(make([](RouterConfig& c) { c.default_lifetime = 601s; }), std::invalid_argument);
  EXPECT_THROW(make([](RouterConfig& c) { c.cbf_max_time = 0ms; }), std::invalid_argument);
  EXPECT_THROW(make([](RouterConfig& c) { c.max_location_entries = 0; }), std::invalid_argument);
  EXPECT_THROW(make([](RouterConfig& c) { c.max_communication_range_m = 0; }),
               std::invalid_argument);
  EXPECT_NO_THROW(make([](RouterConfig&) {}));
  EXPECT_EQ(rt.pending(), 0u);  // the routers made cancelled their beacon timers
}

TEST_F(RouterTest, RequestsThatCannotBeSentSayWhy) {
  RouterConfig config;
  config.station_type = StationType::kRoadSideUnit;
  start(config);
  const Bytes small = {1};
  EXPECT_EQ(router->request({}, small), DataConfirm::kNoPosition);
  set_position(at(0, 0));
  DataRequest no_area;
  no_area.transport = TransportType::kGeoBroadcast;
  EXPECT_EQ(router->request(no_area, small), DataConfirm::kMissingArea);
  EXPECT_EQ(router->request({}, Bytes(1399)), DataConfirm::kMaxSduSizeExceeded);
  DataRequest too_long;
  too_long.lifetime = 601s;
  EXPECT_EQ(router->request(too_long, small), DataConfirm::kMaxLifetimeExceeded);
  EXPECT_TRUE(link.sent().empty());
  link.fail_sends_with(std::make_error_code(std::errc::network_down));
  EXPECT_EQ(router->request({}, small), DataConfirm::kLinkError);
  link.fail_sends_with({});
  EXPECT_EQ(router->request({}, Bytes(1398)), DataConfirm::kAccepted);
  EXPECT_EQ(source_position(sent_packet(0).extended).address.station_type,
            StationType::kRoadSideUnit);
}

TEST_F(RouterTest, MultiHopPacketsGetConsecutiveSequenceNumbersAndHopLimits) {
  start();
  set_position(at(0, 0));
  const Bytes data = {9};
  ASSERT_EQ(router->request(DataRequest::topologically_scoped(), data), DataConfirm::kAccepted);
  const auto gbc = DataRequest::geo_broadcast(
      GeoArea{AreaShape::kRectangle, 481'500'000, -16'000'000, 100, 50, 30}, 4);
  ASSERT_EQ(router->request(gbc, data), DataConfirm::kAccepted);
  const Packet a = sent_packet(0);
  const Packet b = sent_packet(1);
  EXPECT_EQ(a.basic.remaining_hop_limit, 10);  // itsGnDefaultHopLimit
  EXPECT_EQ(a.common.maximum_hop_limit, 10);
  EXPECT_EQ(a.basic.lifetime.duration(), 60s);  // itsGnDefaultPacketLifetime
  EXPECT_EQ(b.common.type, PacketType::kGeoBroadcastRectangle);
  EXPECT_EQ(b.basic.remaining_hop_limit, 4);
  EXPECT_EQ(std::get<GbcHeader>(b.extended).area, *gbc.area);
  EXPECT_EQ(std::get<GbcHeader>(b.extended).sequence_number,
            static_cast<std::uint16_t>(std::get<TsbHeader>(a.extended).sequence_number + 1));
}

TEST_F(RouterTest, BeaconsGoOutEveryIntervalUnlessAnShbWasSent) {
  RouterConfig config;
  config.beacon_max_jitter = 0ms;
  start(config);
  set_position(at(0, 0));
  rt.run_due();  // the first beacon, after a jitter of 0
  ASSERT_EQ(link.sent().size(), 1u);
  EXPECT_EQ(sent_packet(0).common.type, PacketType::kBeacon);
  EXPECT_EQ(sent_packet(0).common.payload_length, 0);
  rt.advance(2999ms);
  EXPECT_EQ(link.sent().size(), 1u);
  rt.advance(1ms);  // t = 3 s
  ASSERT_EQ(link.sent().size(), 2u);
  rt.advance(1s);  // t = 4 s: an SHB postpones the next beacon to 7 s
  ASSERT_EQ(router->request({}, Bytes{1}), DataConfirm::kAccepted);
  rt.advance(2999ms);
  ASSERT_EQ(link.sent().size(), 3u);
  rt.advance(1ms);
  ASSERT_EQ(link.sent().size(), 4u);
  EXPECT_EQ(sent_packet(3).common.type, PacketType::kBeacon);
  EXPECT_EQ(router->stats().beacons_sent, 3u);
  // TSB does not reset the timer (clause 10.3.10.2 names SHB only).
  rt.advance(2s);
  ASSERT_EQ(router->request(DataRequest::topologically_scoped(), Bytes{1}), DataConfirm::kAccepted);
  rt.advance(999ms);  // t = 9.999 s
  EXPECT_EQ(link.sent().size(), 5u);
  rt.advance(1ms);  // t = 10 s, 3 s after the last beacon
  ASSERT_EQ(link.sent().size(), 6u);
  EXPECT_EQ(sent_packet(5).common.type, PacketType::kBeacon);
}

TEST_F(RouterTest, NoBeaconWithoutPositionAndJitteredIntervalsOtherwise) {
  start();  // default jitter 750 ms
  rt.advance(10s);
  EXPECT_TRUE(link.sent().empty());
  set_position(at(0, 0));
  std::vector<clock::SteadyTime> times;
  link.set_send_observer([&](const auto&) { times.push_back(rt.steady_now()); });
  rt.advance(80s);
  ASSERT_GE(times.size(), 20u);
  std::set<clock::Duration> distinct;
  for (std::size_t i = 1; i < times.size(); ++i) {
    const auto gap = times[i] - times[i - 1];
    EXPECT_GE(gap, 3000ms);
    EXPECT_LE(gap, 3750ms);
    distinct.insert(gap);
  }
  EXPECT_GT(distinct.size(), 3u);
}

TEST_F(RouterTest, ReceivedShbIsDeliveredWithIndicationData) {
  start();
  rt.advance(100ms);
  set_position(at(0, 0));
  PacketSpec s;
  s.source = remote_pv(2, at(50, 0), now_tst() - 300);  // 300 ms older than our own fix
  s.lifetime = 1s;  // passed up as received: the lifetime is not aged by timestamps
  receive(make_packet(s), mac(2));
  ASSERT_EQ(delivered.size(), 1u);
  const auto& [ind, payload] = delivered[0];
  EXPECT_EQ(ind.upper_protocol, UpperProtocol::kBtpB);
  EXPECT_EQ(ind.packet_type, PacketType::kSingleHopBroadcast);
  EXPECT_EQ(ind.source.mid, mac(2));
  EXPECT_EQ(ind.source_position, s.source);
  EXPECT_EQ(ind.remaining_lifetime, 1s);
  EXPECT_EQ(ind.remaining_hop_limit, 1);
  EXPECT_EQ(ind.sender, mac(2));
  EXPECT_EQ(ind.rx_time, rt.wall_now());
  EXPECT_FALSE(ind.destination_area);
  EXPECT_EQ(payload, s.payload);
  const auto* entry = router->location_table().find(s.source.address.mid_key(), rt.steady_now());
  ASSERT_NE(entry, nullptr);
  EXPECT_TRUE(entry->is_neighbour);
  EXPECT_EQ(entry->position, s.source);
}

TEST_F(RouterTest, ShbsWithTheSameOrAnOlderTimestampAreAllPassedUp) {
  // EN 302 636-4-1 V1.3.1+ clause 10.3.10.3: SHB reception has no duplicate packet detection.
  // A stack whose position source updates once a second (Vanetza's socktap) sends ten CAMs in
  // a row with one source timestamp; every one of them is a new packet.
  start();
  PacketSpec s;
  s.source = remote_pv(2, at(50, 0), now_tst());
  const Bytes first = make_packet(s);
  receive(first, mac(2));
  receive(first, mac(2));
  const LongPositionVector newest = s.source;
  s.source.timestamp -= 100;  // older, and elsewhere
  s.source.latitude += 1000;
  receive(make_packet(s), mac(2));
  EXPECT_EQ(delivered.size(), 3u);
  EXPECT_TRUE(drops.empty());
  // Clause C.2: only a newer timestamp updates the location table entry.
  const auto* entry = router->location_table().find(newest.address.mid_key(), rt.steady_now());
  ASSERT_NE(entry, nullptr);
  EXPECT_EQ(entry->position, newest);
  s.source.timestamp += 200;
  receive(make_packet(s), mac(2));
  EXPECT_EQ(delivered.size(), 4u);
  EXPECT_EQ(entry->position, s.source);
}

TEST_F(RouterTest, BeaconsWithTheSameTimestampStillMakeTheSourceANeighbour) {
  start();
  PacketSpec b;
  b.type = PacketType::kBeacon;
  b.source = remote_pv(2, at(50, 0), now_tst());
  receive(make_packet(b), mac(2));
  rt.advance(15s);
  receive(make_packet(b), mac(2));  // same fix: the entry's lifetime still restarts
  rt.advance(15s);
  const auto* entry = router->location_table().find(b.source.address.mid_key(), rt.steady_now());
  ASSERT_NE(entry, nullptr);
  EXPECT_TRUE(entry->is_neighbour);
  EXPECT_TRUE(drops.empty());
}

TEST_F(RouterTest, EveryDropReasonOfTheReceivePath) {
  start();
  set_position(at(0, 0));
  PacketSpec s;
  s.source = remote_pv(2, at(50, 0), now_tst());
  const Bytes good = make_packet(s);

  receive(good, mac(2), link::kBroadcastMac, 0x0800);
  Bytes v2 = good;
  v2[0] = 0x21;
  receive(v2, mac(2));
  receive(Bytes(good.begin(), good.begin() + 20), mac(2));
  ASSERT_EQ(drops.size(), 3u);
  EXPECT_EQ(drops[0].reason, DropReason::kWrongEtherType);
  EXPECT_EQ(drops[1].reason, DropReason::kParseError);
  EXPECT_EQ(drops[1].parse_error, ParseError::kUnsupportedVersion);
  EXPECT_EQ(drops[2].parse_error, ParseError::kTruncatedExtendedHeader);
  drops.clear();

  PacketSpec own = s;
  own.source = remote_pv(1, at(0, 0), now_tst());
  receive(make_packet(own), mac(3));  // our packet, relayed back
  PacketSpec zero = s;
  zero.rhl = 0;
  receive(make_packet(zero), mac(2));
  PacketSpec over = s;
  over.type = PacketType::kTopologicallyScopedBroadcast;
  over.rhl = 5;
  over.mhl = 4;
  receive(make_packet(over), mac(2));
  PacketSpec no_life = s;
  no_life.lifetime = 0s;
  receive(make_packet(no_life), mac(2));
  EXPECT_EQ(drop_reasons(),
            (std::vector{DropReason::kOwnPacket, DropReason::kHopLimitZero,
                         DropReason::kHopLimitExceedsMaximum, DropReason::kLifetimeExpired}));
  EXPECT_TRUE(delivered.empty());
  EXPECT_EQ(router->stats().received, 7u);
  EXPECT_EQ(router->stats().dropped(DropReason::kLifetimeExpired), 1u);
  EXPECT_EQ(router->location_table().size(), 0u);  // nothing bad got into the table
}

TEST_F(RouterTest, NoPacketIsDroppedForTheAgeItsTimestampSuggests) {
  // Peers stamp TSTs in UTC (Vanetza: 5 s behind TAI) or in TAI, from clocks we cannot check;
  // the lifetime governs buffering and forwarding only (clause 10.3.10.3, 10.3.11.3).
  start();
  set_position(at(0, 0));
  PacketSpec s;
  s.source = remote_pv(2, at(50, 0), now_tst() - 5000);  // a UTC peer's fix, as we read it
  s.lifetime = 1s;
  receive(make_packet(s), mac(2));
  s.type = PacketType::kTopologicallyScopedBroadcast;
  s.rhl = 2;
  s.mhl = 2;
  s.sn = 1;
  s.source.timestamp -= 3'600'000;  // an hour behind
  receive(make_packet(s), mac(2));
  ASSERT_EQ(delivered.size(), 2u);
  EXPECT_EQ(delivered[0].first.remaining_lifetime, 1s);
  EXPECT_EQ(delivered[1].first.remaining_lifetime, 1s);
  EXPECT_EQ(router->stats().forwarded, 1u);
  EXPECT_TRUE(drops.empty());
}

TEST_F(RouterTest, TsbIsDeliveredAndRebroadcastWithOneHopLess) {
  start();
  set_position(at(0, 0));
  PacketSpec s;
  s.type = PacketType::kTopologicallyScopedBroadcast;
  s.source = remote_pv(2, at(500, 0), now_tst());
  s.rhl = 3;
  s.mhl = 3;
  s.sn = 77;
  const Bytes in = make_packet(s);
  Bytes padded = in;
  padded.resize(in.size() + 6, 0);  // link padding is not forwarded
  receive(padded, mac(3));
  ASSERT_EQ(delivered.size(), 1u);
  EXPECT_EQ(delivered[0].first.remaining_hop_limit, 3);
  EXPECT_EQ(delivered[0].first.sender, mac(3));
  ASSERT_EQ(link.sent().size(), 1u);
  Bytes expected = in;
  expected[3] = 2;
  EXPECT_EQ(link.sent()[0].payload, expected);
  EXPECT_EQ(link.sent()[0].destination, link::kBroadcastMac);
  EXPECT_EQ(router->stats().forwarded, 1u);

  receive(in, mac(4));  // the same packet over another path
  EXPECT_EQ(drop_reasons(), std::vector{DropReason::kDuplicate});

  s.sn = 78;
  s.rhl = 1;
  receive(make_packet(s), mac(3));
  EXPECT_EQ(delivered.size(), 2u);
  EXPECT_EQ(link.sent().size(), 1u);
  EXPECT_EQ(drops.back().reason, DropReason::kNotForwardedHopLimit);
}

TEST_F(RouterTest, GbcInsideTheAreaIsDeliveredAndRebroadcastAfterContentionByDefault) {
  start();  // Annex H: itsGnAreaForwardingAlgorithm is CBF by default
  set_position(at(0, 0));
  PacketSpec s;
  s.type = PacketType::kGeoBroadcastCircle;
  s.source = remote_pv(2, at(800, 0), now_tst());
  s.area = circle_at(at(30, 0), 100);
  s.rhl = 5;
  s.mhl = 10;
  receive(make_packet(s), mac(3));
  ASSERT_EQ(delivered.size(), 1u);
  EXPECT_EQ(delivered[0].first.destination_area, s.area);
  EXPECT_EQ(delivered[0].first.packet_type, PacketType::kGeoBroadcastCircle);
  EXPECT_TRUE(link.sent().empty());  // contending: the sender's position is unknown, 100 ms
  rt.advance(99ms);
  EXPECT_TRUE(link.sent().empty());
  rt.advance(1ms);
  ASSERT_EQ(link.sent().size(), 1u);
  EXPECT_EQ(link.sent()[0].destination, link::kBroadcastMac);
  EXPECT_EQ(link.sent()[0].payload[3], 4);
}

class CbfRouterTest : public RouterTest {
 protected:
  void SetUp() override {
    RouterConfig config;
    config.area_forwarding = RouterConfig::AreaForwarding::kContentionBased;
    start(config);
    set_position(at(0, 0));
  }
  Bytes gbc_from(std::uint8_t source, std::uint16_t sn) {
    PacketSpec s;
    s.type = PacketType::kGeoBroadcastCircle;
    s.source = remote_pv(source, at(-900, 0), now_tst());
    s.area = circle_at(at(0, 0), 2000);
    s.rhl = 5;
    s.mhl = 5;
    s.sn = sn;
    return make_packet(s);
  }
  void hear_shb_from(std::uint8_t station, const GeoPoint& where) {
    PacketSpec n;
    n.source = remote_pv(station, where, now_tst());
    receive(make_packet(n), mac(station));
  }
};

TEST_F(CbfRouterTest, RebroadcastsAfterATimeoutThatShrinksWithTheSendersDistance) {
  hear_shb_from(3, at(-500, 0));  // the forwarder, 500 m away
  receive(gbc_from(2, 1), mac(3));
  ASSERT_EQ(delivered.size(), 2u);  // the SHB and the GBC, at once
  EXPECT_TRUE(link.sent().empty());
  EXPECT_EQ(router->stats().cbf_buffered, 1u);
  // TO = 100 ms − 99 ms × 500 / 1000 = 50.5 ms.
  rt.advance(50ms);
  EXPECT_TRUE(link.sent().empty());
  rt.advance(1ms);
  ASSERT_EQ(link.sent().size(), 1u);
  EXPECT_EQ(link.sent()[0].destination, link::kBroadcastMac);
  EXPECT_EQ(link.sent()[0].payload[3], 4);
  EXPECT_EQ(router->stats().forwarded, 1u);
}

TEST_F(CbfRouterTest, UnknownSenderWaitsTheMaximumAndFarSendersTheMinimum) {
  receive(gbc_from(2, 1), mac(7));  // sender 7 never heard of
  rt.advance(99ms);
  EXPECT_TRUE(link.sent().empty());
  rt.advance(1ms);
  EXPECT_EQ(link.sent().size(), 1u);

  hear_shb_from(4, at(1500, 0));  // beyond the maximum communication range
  receive(gbc_from(2, 2), mac(4));
  rt.advance(1ms);
  EXPECT_EQ(link.sent().size(), 2u);
}

TEST_F(CbfRouterTest, HearingTheRebroadcastOfAnotherRouterCancelsOurs) {
  hear_shb_from(3, at(-100, 0));
  receive(gbc_from(2, 9), mac(3));
  rt.advance(30ms);
  receive(gbc_from(2, 9), mac(5));  // someone farther on was quicker
  rt.advance(200ms);
  EXPECT_TRUE(link.sent().empty());
  EXPECT_EQ(delivered.size(), 2u);  // delivered once
  EXPECT_EQ(drops.back().reason, DropReason::kContentionLost);
  EXPECT_EQ(router->stats().forwarded, 0u);
  // A later copy is a plain duplicate.
  receive(gbc_from(2, 9), mac(6));
  EXPECT_EQ(drops.back().reason, DropReason::kDuplicate);
}

TEST_F(RouterTest, GbcOutsideTheAreaGoesGreedilyToTheNeighbourNearestToIt) {
  start();
  set_position(at(0, 0));
  // Neighbours learnt from their SHBs: 4 at 200 m east (nearer to the area), 5 at 100 m west.
  PacketSpec n4;
  n4.source = remote_pv(4, at(200, 0), now_tst());
  receive(make_packet(n4), mac(4));
  PacketSpec n5;
  n5.source = remote_pv(5, at(-100, 0), now_tst());
  receive(make_packet(n5), mac(5));
  delivered.clear();

  PacketSpec s;
  s.type = PacketType::kGeoBroadcastEllipse;
  s.source = remote_pv(2, at(-300, 0), now_tst());
  s.area = {AreaShape::kEllipse,
            to_tenth_micro_degree(at(1000, 0).latitude_deg),
            to_tenth_micro_degree(at(1000, 0).longitude_deg),
            300,
            100,
            90};
  s.rhl = 5;
  s.mhl = 5;
  receive(make_packet(s), mac(5));
  EXPECT_TRUE(delivered.empty());
  ASSERT_EQ(link.sent().size(), 1u);
  EXPECT_EQ(link.sent()[0].destination, mac(4));
  EXPECT_EQ(link.sent()[0].payload[3], 4);
  EXPECT_EQ(drop_reasons(), std::vector{DropReason::kOutsideArea});
}

TEST_F(RouterTest, GbcAtALocalOptimumIsBroadcastAndFromInsideIsNotForwarded) {
  start();
  set_position(at(0, 0));
  PacketSpec s;
  s.type = PacketType::kGeoBroadcastCircle;
  s.source = remote_pv(2, at(-300, 0), now_tst());
  s.area = circle_at(at(1000, 0), 200);
  s.rhl = 5;
  s.mhl = 5;
  receive(make_packet(s), mac(2));
  // Annex E.2: no neighbour nearer to the area and no store-carry-forward: broadcast.
  EXPECT_EQ(drop_reasons(), std::vector{DropReason::kOutsideArea});
  ASSERT_EQ(link.sent().size(), 1u);
  EXPECT_EQ(link.sent()[0].destination, link::kBroadcastMac);
  EXPECT_EQ(link.sent()[0].payload[3], 4);
  link.sent().clear();
  drops.clear();

  // Station 6 sits inside the area and its broadcast reached us outside: let it be.
  PacketSpec n6;
  n6.source = remote_pv(6, at(900, 0), now_tst());
  receive(make_packet(n6), mac(6));
  PacketSpec n7;  // a neighbour nearer to the area, which greedy forwarding would pick
  n7.source = remote_pv(7, at(300, 0), now_tst());
  receive(make_packet(n7), mac(7));
  s.sn = 1;
  receive(make_packet(s), mac(6));
  EXPECT_EQ(drop_reasons(), std::vector{DropReason::kOutsideArea});
  EXPECT_TRUE(link.sent().empty());
}

TEST_F(RouterTest, GbcRequestFromOutsideTheAreaGoesGreedilyOrIsBroadcastAtALocalOptimum) {
  start();
  set_position(at(0, 0));
  auto scf = DataRequest::geo_broadcast(circle_at(at(0, 2000), 300));
  scf.traffic_class.store_carry_forward = true;  // would wait in a buffer we do not have
  EXPECT_EQ(router->request(scf, Bytes{1}), DataConfirm::kNoNeighbourTowardsArea);
  EXPECT_TRUE(link.sent().empty());
  const auto gbc = DataRequest::geo_broadcast(circle_at(at(0, 2000), 300));
  EXPECT_EQ(router->request(gbc, Bytes{1}), DataConfirm::kAccepted);
  ASSERT_EQ(link.sent().size(), 1u);
  EXPECT_EQ(link.sent()[0].destination, link::kBroadcastMac);
  link.sent().clear();
  PacketSpec n;
  n.source = remote_pv(9, at(0, 250), now_tst());
  receive(make_packet(n), mac(9));
  EXPECT_EQ(router->request(gbc, Bytes{1}), DataConfirm::kAccepted);
  ASSERT_EQ(link.sent().size(), 1u);
  EXPECT_EQ(link.sent()[0].destination, mac(9));
}

TEST_F(RouterTest, AFullLocationTableTurnsAwayNewSourcesButNotKnownOnes) {
  RouterConfig config;
  config.max_location_entries = 2;
  start(config);
  set_position(at(0, 0));
  for (std::uint8_t i = 2; i <= 4; ++i) {
    PacketSpec s;
    s.source = remote_pv(i, at(10.0 * i, 0), now_tst());
    receive(make_packet(s), mac(i));
  }
  EXPECT_EQ(delivered.size(), 2u);
  EXPECT_EQ(drop_reasons(), std::vector{DropReason::kLocationTableFull});
  rt.advance(10ms);
  set_position(at(0, 0));
  PacketSpec known;
  known.source = remote_pv(2, at(20, 0), now_tst());
  receive(make_packet(known), mac(2));
  EXPECT_EQ(delivered.size(), 3u);
  // Once the entries expire there is room again.
  rt.advance(21s);
  set_position(at(0, 0));
  PacketSpec late;
  late.source = remote_pv(4, at(40, 0), now_tst());
  receive(make_packet(late), mac(4));
  EXPECT_EQ(delivered.size(), 4u);
}

TEST_F(RouterTest, LocationTableEntriesExpireAfterTwentySeconds) {
  start();
  PacketSpec s;
  s.type = PacketType::kBeacon;
  s.source = remote_pv(2, at(50, 0), now_tst());
  receive(make_packet(s), mac(2));
  EXPECT_TRUE(delivered.empty());  // beacons update the table only
  const auto key = s.source.address.mid_key();
  ASSERT_NE(router->location_table().find(key, rt.steady_now()), nullptr);
  rt.advance(19'999ms);
  EXPECT_NE(router->location_table().find(key, rt.steady_now()), nullptr);
  rt.advance(1ms);
  EXPECT_EQ(router->location_table().find(key, rt.steady_now()), nullptr);
  // The next received packet purges it.
  PacketSpec other;
  other.source = remote_pv(3, at(10, 0), now_tst());
  receive(make_packet(other), mac(3));
  EXPECT_EQ(router->location_table().size(), 1u);
}

}  // namespace
}  // namespace tb::its::geonet
