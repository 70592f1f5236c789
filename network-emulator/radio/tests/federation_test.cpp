#include "network-emulator/radio/federation.hpp"

#include <cmath>
#include <map>

#include <gtest/gtest.h>

#include "common/clock/runtime.hpp"
#include "network-emulator/radio/tests/recording_sink.hpp"

namespace tb::emu::radio {
namespace {

using namespace std::chrono_literals;
using Kind = scenario::ChannelModel::Kind;

struct RecordingTransport : FederationTransport {
  void send(std::size_t peer, std::span<const std::uint8_t> d) override {
    sent.emplace_back(peer, std::vector<std::uint8_t>(d.begin(), d.end()));
  }
  std::vector<std::pair<std::size_t, std::vector<std::uint8_t>>> sent;
};

using testing::frame;
using testing::RecordingSink;

// Node a (this one): 1 and 2; b: 11 and pooled 12; c: 21, 22.
Placement three_nodes() {
  return parse_placement(R"({"nodes": [
    {"name": "a", "medium": "ma:4730", "stations": [1, 2]},
    {"name": "b", "medium": "mb:4730", "stations": [11], "pooled": [12], "station_hosts": 1},
    {"name": "c", "medium": "mc:4730", "stations": [21, 22]}]})",
                         "test");
}

scenario::ChannelModel range_model(double r = 300) {
  scenario::ChannelModel m;
  m.kind = Kind::kRange;
  m.range_m = r;
  return m;
}

class FederationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    place(1, {0, 0, 0});
    place(2, {1000, 0, 0});
    place(11, {200, 0, 0});
    place(12, {5000, 5000, 0});
    place(21, {0, 400, 0});
    place(22, {1000, 250, 0});
  }
  void place(StationId id, std::array<double, 3> p) {
    positions.set(id, {p, 0});
    where[id] = p;
  }
  // The truth from geometry: the peers with a station within the range of @p from.
  std::vector<std::size_t> peers_in_range(const Federation& f, StationId from, double range) {
    std::vector<std::size_t> out;
    for (std::size_t k = 0; k < f.peers().size(); ++k) {
      bool any = false;
      for (const auto* list : {&f.peers()[k].stations, &f.peers()[k].pooled})
        for (const StationId s : *list) {
          const auto& a = where.at(from);
          const auto& b = where.at(s);
          any |= std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]) <= range;
        }
      if (any)
        out.push_back(k);
    }
    return out;
  }
  std::unique_ptr<Channel> channel(const scenario::ChannelModel& m, std::uint64_t seed = 1) {
    auto ch = std::make_unique<Channel>(m, positions, seed);
    if (ch->max_range_m())
      positions.index_cells(*ch->max_range_m());
    return ch;
  }
  std::vector<std::uint8_t> datagram_from(std::string_view node, StationId sender,
                                          std::span<const std::uint8_t> f, std::int64_t tx = 7) {
    std::vector<std::uint8_t> out;
    EXPECT_TRUE(encode_federated_frame(node, sender, nullptr, tx, f, out));
    return out;
  }

  clock::ManualRuntime rt;
  PositionTable positions;
  std::map<StationId, std::array<double, 3>> where;
  RecordingTransport transport;
};

TEST_F(FederationTest, PeersAreChosenByTheChannelsRange) {
  auto ch = channel(range_model());
  Medium medium(rt, *ch);
  MediumRemoteSink sink(medium);
  Federation f(three_nodes(), "a", *ch, positions, rt, transport, sink);
  ASSERT_EQ(f.peers().size(), 2u);
  EXPECT_EQ(f.peers()[0].name, "b");
  std::vector<std::size_t> got;
  for (const StationId from : {1u, 2u}) {
    f.peers_for(from, got);
    EXPECT_EQ(got, peers_in_range(f, from, 300)) << "from " << from;
  }
  f.peers_for(1, got);
  EXPECT_EQ(got, (std::vector<std::size_t>{0}));  // 11 at 200 m; c's nearest 400 m
  f.peers_for(2, got);
  EXPECT_EQ(got, (std::vector<std::size_t>{1}));  // 22 at 250 m
  // 21 drives to 290 m of station 1: c hears 1 from now on.
  place(21, {0, 290, 0});
  f.peers_for(1, got);
  EXPECT_EQ(got, peers_in_range(f, 1, 300));
  EXPECT_EQ(got, (std::vector<std::size_t>{0, 1}));
  // Moving 11 away leaves b out.
  place(11, {-400, 0, 0});
  f.peers_for(1, got);
  EXPECT_EQ(got, (std::vector<std::size_t>{1}));
}

TEST_F(FederationTest, IdealChannelAndUnplacedStationsReachEveryPeerThatMayHear) {
  scenario::ChannelModel ideal;
  auto ch = channel(ideal);
  Medium medium(rt, *ch);
  MediumRemoteSink sink(medium);
  Federation f(three_nodes(), "a", *ch, positions, rt, transport, sink);
  std::vector<std::size_t> got;
  f.peers_for(1, got);
  EXPECT_EQ(got, (std::vector<std::size_t>{0, 1}));

  // Range model, but a peer station without a position: its node cannot be ruled out.
  PositionTable partial(300);
  partial.set(1, {{0, 0, 0}, 0});
  partial.set(11, {{5000, 0, 0}, 0});
  partial.set(12, {{5000, 0, 0}, 0});
  partial.set(21, {{0, 5000, 0}, 0});  // 22 unknown
  Channel rc(range_model(), partial, 1);
  Federation g(three_nodes(), "a", rc, partial, rt, transport, sink);
  g.peers_for(1, got);
  EXPECT_EQ(got, (std::vector<std::size_t>{1}));
  // A sender without a position goes to everyone.
  g.peers_for(2, got);
  EXPECT_EQ(got, (std::vector<std::size_t>{0, 1}));
}

TEST_F(FederationTest, ALocalFrameGoesAsOneDatagramPerChosenPeer) {
  auto ch = channel(range_model());
  Medium medium(rt, *ch);
  MediumRemoteSink sink(medium);
  Federation f(three_nodes(), "a", *ch, positions, rt, transport, sink);
  const auto fr = frame(5);
  f.on_local_frame(1, fr, 1'700'000'000'000'000'042);
  ASSERT_EQ(transport.sent.size(), 1u);
  EXPECT_EQ(transport.sent[0].first, 0u);  // b
  const auto d = decode_federation_datagram(transport.sent[0].second);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->node, "a");
  EXPECT_EQ(d->sender, 1u);
  EXPECT_EQ(d->tx_unix_ns, 1'700'000'000'000'000'042);
  EXPECT_TRUE(d->has_position);
  EXPECT_EQ(d->position, where[1]);
  EXPECT_EQ(std::vector<std::uint8_t>(d->frame.begin(), d->frame.end()), fr);
  EXPECT_EQ(f.peers_skipped(), 1u);
  // Unknown time: now, from the injected clock.
  f.on_local_frame(2, fr, 0);
  ASSERT_EQ(transport.sent.size(), 2u);
  EXPECT_EQ(transport.sent[1].first, 1u);
  EXPECT_EQ(decode_federation_datagram(transport.sent[1].second)->tx_unix_ns,
            clock::to_unix_ns(rt.wall_now()));
}

TEST_F(FederationTest, ARemoteFrameGetsTheChannelPerLocalReceiver) {
  auto ch = channel(range_model());
  Medium medium(rt, *ch);
  RecordingSink s1, s2;
  medium.attach(1, s1);
  medium.attach(2, s2);
  int observed = 0;
  medium.set_frame_observer([&](StationId, auto, std::int64_t) { ++observed; });
  MediumRemoteSink sink(medium);
  Federation f(three_nodes(), "a", *ch, positions, rt, transport, sink);
  std::vector<std::int64_t> hops;
  f.set_hop_observer([&](const FederationDatagram& d, std::int64_t rx, std::int64_t) {
    EXPECT_EQ(d.sender, 11u);
    hops.push_back(rx - d.tx_unix_ns);
  });
  rt.advance(1ms);
  const std::int64_t tx = clock::to_unix_ns(rt.wall_now()) - 300'000;
  f.on_datagram(datagram_from("b", 11, frame(9), tx), 0);
  // 1 is 200 m from 11 and hears it; 2 is 800 m away and does not.
  ASSERT_EQ(s1.frames.size(), 1u);
  EXPECT_EQ(s1.frames[0], frame(9));
  EXPECT_TRUE(s2.frames.empty());
  EXPECT_EQ(ch->links().at({11, 1}).delivered, 1u);
  EXPECT_EQ(medium.culled(), 1u);  // 2, beyond the range
  EXPECT_EQ(hops, (std::vector<std::int64_t>{300'000}));
  EXPECT_EQ(observed, 0);  // neither traced as medium.rx nor federated again
  EXPECT_TRUE(transport.sent.empty());
  EXPECT_EQ(f.frames_in(), 1u);
}

// A frame from a remote station is decided exactly as the same frame from the same station
// would be were it local: same seed, same outcome per receiver.
TEST_F(FederationTest, SameSeedSameOutcomeAsALocalSender) {
  auto m = range_model(2000);
  m.packet_error_rate = 0.3;
  auto run = [&](bool remote) {
    PositionTable table(2000);
    for (const auto& [id, p] : where)
      table.set(id, {p, 0});
    Channel ch(m, table, 42);
    Medium medium(rt, ch);
    RecordingSink s1, s2, s11;
    medium.attach(1, s1);
    medium.attach(2, s2);
    if (!remote)
      medium.attach(11, s11);
    MediumRemoteSink sink(medium);
    RecordingTransport t;
    Federation f(three_nodes(), "a", ch, table, rt, t, sink);
    for (int i = 0; i < 500; ++i) {
      const auto fr = frame(static_cast<std::uint8_t>(i));
      if (remote)
        f.on_datagram(datagram_from("b", 11, fr), 1);
      else
        medium.on_frame(11, fr);
    }
    return std::make_pair(s1.frames, s2.frames);
  };
  const auto local = run(false);
  const auto remote = run(true);
  EXPECT_EQ(remote, local);
  // And the loss is the model's: 30 % within 5 σ on each link.
  for (const auto* got : {&remote.first, &remote.second}) {
    const double sigma = std::sqrt(500 * 0.3 * 0.7);
    EXPECT_NEAR(static_cast<double>(got->size()), 350.0, 5 * sigma);
  }
}

TEST_F(FederationTest, BadAndForeignDatagramsAreRefusedWithoutDelivery) {
  auto ch = channel(range_model());
  Medium medium(rt, *ch);
  RecordingSink s1;
  medium.attach(1, s1);
  MediumRemoteSink sink(medium);
  Federation f(three_nodes(), "a", *ch, positions, rt, transport, sink);
  std::vector<std::string> why;
  f.set_reject_observer([&](std::string_view w) { why.emplace_back(w); });
  const auto good = datagram_from("b", 11, frame(1));
  for (std::size_t n = 0; n < good.size(); ++n)
    f.on_datagram(std::vector<std::uint8_t>(good.begin(), good.begin() + static_cast<long>(n)), 1);
  f.on_datagram(datagram_from("b", 21, frame(1)), 1);   // 21 is c's
  f.on_datagram(datagram_from("b", 1, frame(1)), 1);    // 1 is ours
  f.on_datagram(datagram_from("zz", 11, frame(1)), 1);  // no such node
  f.on_datagram(datagram_from("a", 11, frame(1)), 1);   // ourselves
  EXPECT_TRUE(s1.frames.empty());
  EXPECT_EQ(f.rejected(), good.size() + 4);
  EXPECT_EQ(f.frames_in(), 0u);
  EXPECT_NE(why.at(good.size()).find("station 21"), std::string::npos) << why.at(good.size());
  EXPECT_NE(why.at(good.size() + 2).find("\"zz\""), std::string::npos);
  f.on_datagram(good, 1);
  EXPECT_EQ(s1.frames.size(), 1u);
}

TEST_F(FederationTest, SilentOrUnreachablePeersAreReportedOnceAndAgainWhenBack) {
  auto ch = channel(range_model());
  Medium medium(rt, *ch);
  MediumRemoteSink sink(medium);
  Federation f(three_nodes(), "a", *ch, positions, rt, transport, sink);
  std::vector<PeerEvent> events;
  f.set_peer_events([&](const PeerEvent& e) { events.push_back(e); });
  std::vector<std::uint8_t> hb_b, hb_c;
  ASSERT_TRUE(encode_federation_heartbeat("b", 0, hb_b));
  ASSERT_TRUE(encode_federation_heartbeat("c", 0, hb_c));

  f.on_datagram(hb_b, 0);  // b answers from the start, c never
  ASSERT_EQ(events.size(), 1u);
  EXPECT_TRUE(events[0].up);
  EXPECT_EQ(events[0].node, "b");
  for (int i = 0; i < 12; ++i) {  // 6 s of ticks; b keeps sending
    rt.advance(Federation::kHeartbeatInterval);
    f.tick();
    f.on_datagram(hb_b, 0);
  }
  // Heartbeats go to every peer, down or not.
  EXPECT_EQ(transport.sent.size(), 24u);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[1].node, "c");
  EXPECT_FALSE(events[1].up);
  EXPECT_NE(events[1].why.find("nothing heard for 3.0 s"), std::string::npos) << events[1].why;
  EXPECT_TRUE(f.peer_up(0));
  EXPECT_FALSE(f.peer_up(1));

  // b's socket says it is gone: reported at once, with the socket's reason, and only once.
  f.on_send_error(0, "connection refused (ICMP port unreachable from 10.0.0.2:4730)");
  f.on_send_error(0, "connection refused (ICMP port unreachable from 10.0.0.2:4730)");
  for (int i = 0; i < 10; ++i) {
    rt.advance(Federation::kHeartbeatInterval);
    f.tick();
  }
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[2].node, "b");
  EXPECT_FALSE(events[2].up);
  EXPECT_NE(events[2].why.find("connection refused"), std::string::npos);

  // Both come back.
  f.on_datagram(hb_c, 0);
  f.on_datagram(hb_b, 0);
  ASSERT_EQ(events.size(), 5u);
  EXPECT_TRUE(events[3].up && events[3].node == "c" && events[3].why == "heard from again");
  EXPECT_TRUE(events[4].up && events[4].node == "b");
  f.tick();
  EXPECT_EQ(events.size(), 5u);
}

TEST_F(FederationTest, ANodeNotInThePlacementIsRefused) {
  auto ch = channel(range_model());
  Medium medium(rt, *ch);
  MediumRemoteSink sink(medium);
  EXPECT_THROW(Federation(three_nodes(), "d", *ch, positions, rt, transport, sink), PlacementError);
}

}  // namespace
}  // namespace tb::emu::radio
