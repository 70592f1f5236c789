// The medium with range culling and station-hosts' ports (issue 33), on an injected clock and
// injected positions.

#include <gtest/gtest.h>

#include <vector>

#include <nlohmann/json.hpp>

#include "network-emulator/radio/medium.hpp"
#include "network-emulator/radio/sender_attribution.hpp"
#include "network-emulator/radio/tests/recording_sink.hpp"

namespace tb::emu::radio {
namespace {

using namespace std::chrono_literals;
using Kind = scenario::ChannelModel::Kind;

struct RecordingHost : PooledSink {
  struct Delivery {
    std::vector<StationId> to;
    std::vector<std::uint8_t> frame;
  };
  void transmit(std::span<const StationId> receivers,
                std::span<const std::uint8_t> frame) override {
    got.push_back({{receivers.begin(), receivers.end()}, {frame.begin(), frame.end()}});
  }
  std::vector<Delivery> got;
};

using testing::frame;
using testing::RecordingSink;

scenario::ChannelModel range(double m) {
  scenario::ChannelModel c;
  c.kind = Kind::kRange;
  c.range_m = m;
  return c;
}

std::uint64_t dropped(const Channel& ch, StationId a, StationId b, DropReason r) {
  return ch.links().at({a, b}).dropped[static_cast<std::size_t>(r)];
}

TEST(RangeCulling, OffersOnlyStationsWithinRange) {
  clock::ManualRuntime rt;
  PositionTable pos(300);
  pos.set(1, {{0, 0, 0}, 0});
  pos.set(2, {{299.9, 0, 0}, 0});  // just inside
  pos.set(3, {{300.1, 0, 0}, 0});  // just outside
  pos.set(4, {{0, 300, 0}, 0});    // exactly at the range: hears
  Channel ch(range(300), pos, 1);
  Medium m(rt, ch);
  RecordingSink s1, s2, s3, s4;
  m.attach(1, s1);
  m.attach(2, s2);
  m.attach(3, s3);
  m.attach(4, s4);
  m.on_frame(1, frame(1));
  EXPECT_EQ(s2.frames.size(), 1u);
  EXPECT_EQ(s4.frames.size(), 1u);
  EXPECT_TRUE(s3.frames.empty());
  EXPECT_FALSE(ch.links().contains({1, 3}));  // not offered: no link, not a drop
  EXPECT_EQ(m.culled(), 1u);
  EXPECT_EQ(ch.culled(), 1u);
  const LinkStats t = ch.totals();
  EXPECT_EQ(t.sent, 2u);
  EXPECT_EQ(t.sent, t.delivered + t.dropped_total());
  EXPECT_EQ(ch.stats_json()["culled"], 1u);
}

TEST(RangeCulling, FollowsStationsThatMoveBetweenCells) {
  clock::ManualRuntime rt;
  PositionTable pos(100);
  pos.set(1, {{0, 0, 0}, 0});
  pos.set(2, {{50, 0, 0}, 0});
  Channel ch(range(100), pos, 1);
  Medium m(rt, ch);
  RecordingSink s1, s2;
  m.attach(1, s1);
  m.attach(2, s2);
  m.on_frame(1, frame(1));
  wire::VehicleState st;
  st.station_id = 2;
  st.sim_time_ns = 1;
  st.position = {450, 0, 0};  // four cells on: out of range
  pos.update(st);
  m.on_frame(1, frame(2));
  st.sim_time_ns = 2;
  st.position = {-99, 5, 0};  // back, in the cell on the other side
  pos.update(st);
  m.on_frame(1, frame(3));
  ASSERT_EQ(s2.frames.size(), 2u);
  EXPECT_EQ(s2.frames[0].back(), 1);
  EXPECT_EQ(s2.frames[1].back(), 3);
  EXPECT_EQ(ch.links().at({1, 2}).sent, 2u);
  EXPECT_EQ(m.culled(), 1u);
}

TEST(RangeCulling, StationsWithoutAPositionAreStillOffered) {
  clock::ManualRuntime rt;
  PositionTable pos(100);
  pos.set(1, {{0, 0, 0}, 0});
  Channel ch(range(100), pos, 1);
  Medium m(rt, ch);
  RecordingSink s1, s2;
  m.attach(1, s1);
  m.attach(2, s2);  // no position yet
  m.on_frame(1, frame(1));
  EXPECT_EQ(dropped(ch, 1, 2, DropReason::kUnknownPosition), 1u);
  pos.set(2, {{5000, 0, 0}, 0});
  m.on_frame(1, frame(2));  // now placed, far away: culled
  EXPECT_EQ(ch.links().at({1, 2}).sent, 1u);
  EXPECT_EQ(m.culled(), 1u);
  m.on_frame(2, frame(3));  // nor does station 1 hear it
  EXPECT_TRUE(s1.frames.empty());
}

TEST(RangeCulling, TheSameSeedGivesTheSameDeliveriesWithAndWithout) {
  // Links beyond the range draw no random numbers, so culling them leaves the packet errors
  // of the others where they were.
  auto run = [](bool culling) {
    clock::ManualRuntime rt;
    PositionTable pos(250);
    auto c = range(250);
    c.packet_error_rate = 0.3;
    Channel ch(c, pos, 42);
    Medium m(rt, ch);
    m.set_culling(culling);
    std::vector<RecordingSink> sinks(40);
    for (StationId id = 0; id < 40; ++id) {
      pos.set(id, {{id * 37.0, (id % 5) * 90.0, 0}, 0});
      m.attach(id, sinks[id]);
    }
    for (int f = 0; f < 30; ++f)
      m.on_frame(static_cast<StationId>(f % 40), frame(static_cast<std::uint8_t>(f)));
    std::vector<std::size_t> got;
    for (const auto& s : sinks)
      got.push_back(s.frames.size());
    return std::make_pair(got, m.culled());
  };
  const auto [with, culled] = run(true);
  const auto [without, none] = run(false);
  EXPECT_EQ(with, without);
  EXPECT_GT(culled, 0u);
  EXPECT_EQ(none, 0u);
}

TEST(RangeCulling, IdealChannelCullsNothing) {
  clock::ManualRuntime rt;
  PositionTable pos(100);
  pos.set(1, {{0, 0, 0}, 0});
  pos.set(2, {{1e6, 0, 0}, 0});
  Channel ch(scenario::ChannelModel{}, pos, 1);
  Medium m(rt, ch);
  RecordingSink s1, s2;
  m.attach(1, s1);
  m.attach(2, s2);
  m.on_frame(1, frame(1));
  EXPECT_EQ(s2.frames.size(), 1u);
  EXPECT_EQ(m.culled(), 0u);
}

class PooledMedium : public ::testing::Test {
 protected:
  void SetUp() override {
    pos.set(1, {{0, 0, 0}, 0});     // full
    pos.set(11, {{10, 0, 0}, 0});   // host A
    pos.set(12, {{20, 0, 0}, 0});   // host A
    pos.set(13, {{900, 0, 0}, 0});  // host A, out of range of everyone but 21
    pos.set(21, {{850, 0, 0}, 0});  // host B
  }
  void attach(Medium& m) {
    m.attach(1, full);
    m.attach_pooled(11, a);
    m.attach_pooled(12, a);
    m.attach_pooled(13, a);
    m.attach_pooled(21, b);
  }
  clock::ManualRuntime rt;
  PositionTable pos{300};
  RecordingSink full;
  RecordingHost a, b;
};

TEST_F(PooledMedium, OneFramePerHostListingItsReceiversInRange) {
  Channel ch(range(300), pos, 1);
  Medium m(rt, ch);
  attach(m);
  m.on_frame(1, frame(1));
  ASSERT_EQ(a.got.size(), 1u);
  EXPECT_EQ(a.got[0].to, (std::vector<StationId>{11, 12}));
  EXPECT_EQ(a.got[0].frame, frame(1));
  EXPECT_TRUE(b.got.empty());
  EXPECT_EQ(m.deliveries(), 2u);
  EXPECT_EQ(m.pooled_transmits(), 1u);
}

TEST_F(PooledMedium, AHostsOwnStationsHearEachOtherThroughTheMedium) {
  Channel ch(range(300), pos, 1);
  Medium m(rt, ch);
  attach(m);
  m.on_frame(11, frame(2));  // to the full station and to 12, on the sender's own host
  ASSERT_EQ(a.got.size(), 1u);
  EXPECT_EQ(a.got[0].to, std::vector<StationId>{12});
  EXPECT_EQ(full.frames.size(), 1u);
  m.on_frame(13, frame(3));  // only 21, on the other host
  ASSERT_EQ(b.got.size(), 1u);
  EXPECT_EQ(b.got[0].to, std::vector<StationId>{21});
  EXPECT_EQ(a.got.size(), 1u);
  EXPECT_EQ(ch.links().at({11, 12}).delivered, 1u);  // links per station id, pooled or not
  EXPECT_EQ(ch.links().at({13, 21}).delivered, 1u);
}

TEST_F(PooledMedium, DelayedDeliveriesDueTogetherShareAFrame) {
  auto c = range(300);
  c.delay_ms = 2;
  Channel ch(c, pos, 1);
  Medium m(rt, ch);
  attach(m);
  m.on_frame(1, frame(4));
  EXPECT_TRUE(a.got.empty());
  EXPECT_EQ(rt.pending(), 1u);  // one timer for host A's two receivers
  rt.advance(2ms);
  ASSERT_EQ(a.got.size(), 1u);
  EXPECT_EQ(a.got[0].to, (std::vector<StationId>{11, 12}));
  EXPECT_EQ(full.frames.size(), 0u);  // the sender does not hear itself
  m.on_frame(12, frame(5));
  EXPECT_EQ(rt.pending(), 2u);  // the full station's and host A's (for 11)
  rt.advance(2ms);
  ASSERT_EQ(a.got.size(), 2u);
  EXPECT_EQ(a.got[1].to, std::vector<StationId>{11});
  EXPECT_EQ(full.frames.size(), 1u);
}

TEST_F(PooledMedium, JitterGivesEachReceiverItsOwnDueTime) {
  auto c = range(300);
  c.delay_ms = 1;
  c.jitter_ms = 3;
  Channel ch(c, pos, 1);
  Medium m(rt, ch);
  attach(m);
  m.on_frame(1, frame(5));
  rt.advance(5ms);
  ASSERT_EQ(a.got.size(), 2u);  // two due times: two frames of one receiver each
  EXPECT_EQ(a.got[0].to.size() + a.got[1].to.size(), 2u);
}

TEST_F(PooledMedium, StationsDetachedInFlightAreLeftOut) {
  auto c = range(300);
  c.delay_ms = 1;
  Channel ch(c, pos, 1);
  Medium m(rt, ch);
  attach(m);
  m.on_frame(1, frame(6));
  m.detach(11);
  rt.advance(1ms);
  ASSERT_EQ(a.got.size(), 1u);
  EXPECT_EQ(a.got[0].to, std::vector<StationId>{12});
  m.on_frame(21, frame(7));
  m.detach(13);
  rt.advance(1ms);
  EXPECT_EQ(a.got.size(), 1u);  // nobody left for that frame: no frame at all
}

std::vector<std::uint8_t> from_mac(StationId id) {
  return {0xff,
          0xff,
          0xff,
          0xff,
          0xff,
          0xff,
          0x02,
          0x00,
          static_cast<std::uint8_t>(id >> 24),
          static_cast<std::uint8_t>(id >> 16),
          static_cast<std::uint8_t>(id >> 8),
          static_cast<std::uint8_t>(id),
          0x89,
          0x47};
}

TEST(SenderAttribution, BySourceMacElseByPort) {
  SenderAttribution at;
  at.add_station_port(5, 1001);
  at.add_pooled(9, 3004);
  at.add_pooled(9, 3007);
  EXPECT_EQ(at.sender(9, from_mac(3004)), 3004u);
  EXPECT_EQ(at.sender(9, from_mac(3007)), 3007u);
  EXPECT_EQ(at.sender(5, from_mac(1001)), 1001u);
  // A full station's port with a MAC that names no station (a test's raw socket): the port's.
  EXPECT_EQ(at.sender(5, from_mac(42)), 1001u);
  auto odd = from_mac(1001);
  odd[6] = 0x06;
  EXPECT_EQ(at.sender(5, odd), 1001u);
  // A host's port with an unknown sender: dropped and counted.
  EXPECT_FALSE(at.sender(9, from_mac(42)));
  EXPECT_FALSE(at.sender(9, odd));
  EXPECT_FALSE(at.sender(9, std::vector<std::uint8_t>{1, 2, 3}));  // too short for a MAC
  EXPECT_EQ(at.unknown_sender(), 3u);
  // Not a port at all: ignored, not counted.
  EXPECT_FALSE(at.sender(77, from_mac(3004)));
  EXPECT_EQ(at.unknown_sender(), 3u);
  EXPECT_EQ(at.host_port_of(3004), 9);
  EXPECT_EQ(at.host_port_of(1001), 0);
}

TEST(SenderAttribution, ForgetsRemovedStations) {
  SenderAttribution at;
  at.add_station_port(5, 1001);
  at.add_pooled(9, 3004);
  at.remove_station(3004);
  EXPECT_FALSE(at.is_port(9));  // its last station gone
  EXPECT_FALSE(at.sender(9, from_mac(3004)));
  EXPECT_EQ(at.unknown_sender(), 0u);
  at.remove_station(1001);
  EXPECT_FALSE(at.is_port(5));
}

}  // namespace
}  // namespace tb::emu::radio
