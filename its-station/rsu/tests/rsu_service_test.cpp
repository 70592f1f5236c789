// The RSU's send schedule driven by a manual clock and injected feed datagrams: MAPEM at 1 Hz,
// SPATEM at 10 Hz and at once on a change, none on a stale feed, malformed datagrams counted.

#include "its-station/rsu/rsu_service.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <vector>

#include "common/geodesy/local_frame.hpp"
#include "common/map/opendrive/reader.hpp"
#include "its-station/messages/mapem.hpp"
#include "its-station/messages/spatem.hpp"

namespace tb::its::rsu {
namespace {

using namespace std::chrono_literals;
namespace sim = wire::sim;
namespace msg = messages;

struct Sent {
  clock::SteadyTime at;
  std::uint16_t port;
  std::vector<std::uint8_t> bytes;
};

class RecordingSender final : public facilities::MessageSender {
 public:
  explicit RecordingSender(clock::Runtime& rt) : rt_(rt) {}
  facilities::SendResult send_single_hop(std::uint16_t port,
                                         std::span<const std::uint8_t> payload) override {
    if (refuse)
      return facilities::SendResult::kNoPosition;
    sent.push_back({rt_.steady_now(), port, {payload.begin(), payload.end()}});
    return facilities::SendResult::kSent;
  }
  facilities::SendResult send_geobroadcast(std::uint16_t, const facilities::GeoArea&,
                                           std::span<const std::uint8_t>, std::uint32_t,
                                           std::uint8_t) override {
    ADD_FAILURE() << "the RSU's messages are single-hop";
    return facilities::SendResult::kLinkError;
  }
  std::vector<Sent> of(std::uint16_t port) const {
    std::vector<Sent> out;
    for (const Sent& s : sent)
      if (s.port == port)
        out.push_back(s);
    return out;
  }
  std::vector<Sent> sent;
  bool refuse = false;

 private:
  clock::Runtime& rt_;
};

// A small MAPEM of the shipped four-way junction (intersection 100).
IntersectionMap four_way_map() {
  const char* root = std::getenv("TESTBED_ROOT");
  static const map::odr::RoadNetwork net = map::odr::load_opendrive(
      std::string(root != nullptr ? root : ".") + "/scenarios/maps/four_way_junction.xodr");
  static const map::odr::SignalLayout layout(net);
  static const geodesy::LocalFrame frame({48.0, 11.0, 500.0});
  return MapemBuilder(net, layout, frame).build("100");
}

std::int64_t wall_ms(const clock::Runtime& rt) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(rt.wall_now().time_since_epoch())
      .count();
}

sim::SignalStates feed(const clock::Runtime& rt, sim::MovementPhaseState g1,
                       std::int64_t end_in_ms) {
  sim::SignalStates s;
  s.world_time_ms = wall_ms(rt);
  const std::int64_t end = s.world_time_ms + end_in_ms;
  s.groups = {{100, 1, g1, end, end},
              {100, 2, sim::MovementPhaseState::kStopAndRemain, end + 3000, end + 3000},
              {101, 1, sim::MovementPhaseState::kDark, 0, 0}};
  return s;
}

msg::MovementPhaseState state_of(const Sent& s, int group) {
  const auto spatem = msg::decode_spatem(s.bytes);
  EXPECT_TRUE(spatem.has_value());
  for (const msg::MovementState& m : spatem->spat.intersections[0].states)
    if (m.signalGroup == group)
      return m.state_time_speed[0].eventState;
  ADD_FAILURE() << "no group " << group;
  return msg::MovementPhaseState::unavailable;
}

TEST(RsuService, MapemEverySecondSpatemEveryTenthWhileTheFeedIsFresh) {
  clock::ManualRuntime rt;
  RecordingSender sender(rt);
  RsuService rsu(rt, sender, four_way_map());
  const clock::SteadyTime t0 = rt.steady_now();
  rsu.start();
  // The feed repeats its states every 500 ms, as sim-server's once-a-second repeat does more
  // slowly.
  for (int i = 0; i < 20; ++i) {
    rsu.on_datagram(sim::encode(
        feed(rt, sim::MovementPhaseState::kProtectedMovementAllowed, 60'000 - i * 500)));
    rt.advance(500ms);
  }
  const auto mapems = sender.of(kBtpPortMapem);
  ASSERT_EQ(mapems.size(), 11u);  // t = 0, 1, ..., 10 s
  for (std::size_t i = 0; i < mapems.size(); ++i) {
    EXPECT_EQ(mapems[i].at - t0, std::chrono::seconds(i));
    EXPECT_EQ(mapems[i].bytes, rsu.map().encoded);
  }
  const auto back = msg::decode_mapem(mapems[0].bytes);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ((*back->map.intersections)[0].id.id, 100);

  const auto spatems = sender.of(kBtpPortSpatem);
  // The first at once on the first feed (t 0, a change from nothing), then every 100 ms.
  ASSERT_EQ(spatems.size(), 101u);
  for (std::size_t i = 0; i < spatems.size(); ++i)
    EXPECT_EQ(spatems[i].at - t0, std::chrono::milliseconds(100 * i)) << i;
  EXPECT_EQ(state_of(spatems[50], 1), msg::MovementPhaseState::protected_Movement_Allowed);
  EXPECT_EQ(rsu.counters().spatem_on_change, 1u);
  EXPECT_EQ(rsu.counters().feed_datagrams, 20u);
  EXPECT_EQ(rsu.counters().feed_malformed, 0u);
}

TEST(RsuService, StateChangeGoesOutAtOnce) {
  clock::ManualRuntime rt;
  RecordingSender sender(rt);
  RsuService rsu(rt, sender, four_way_map());
  rsu.start();
  rsu.on_signal_states(feed(rt, sim::MovementPhaseState::kProtectedMovementAllowed, 1234));
  rt.advance(1234ms);
  const std::size_t before = sender.of(kBtpPortSpatem).size();
  const clock::SteadyTime change_at = rt.steady_now();
  rsu.on_signal_states(feed(rt, sim::MovementPhaseState::kProtectedClearance, 3000));
  auto spatems = sender.of(kBtpPortSpatem);
  ASSERT_EQ(spatems.size(), before + 1);  // without the clock moving
  EXPECT_EQ(spatems.back().at, change_at);
  EXPECT_EQ(state_of(spatems.back(), 1), msg::MovementPhaseState::protected_clearance);
  // Its minEndTime is the fed end, within the TimeMark's 100 ms.
  const auto spatem = msg::decode_spatem(spatems.back().bytes);
  const std::int64_t end = wall_ms(rt) + 3000;
  const std::int64_t got = msg::utc_ms_from_time_mark(
      spatem->spat.intersections[0].states[0].state_time_speed[0].timing->minEndTime, wall_ms(rt));
  EXPECT_LE(end - got, 100);
  EXPECT_GE(end - got, 0);
  EXPECT_EQ(rsu.counters().spatem_on_change, 2u);
  // The same states again: no extra SPATEM; the periodic one follows 100 ms after the change.
  rsu.on_signal_states(feed(rt, sim::MovementPhaseState::kProtectedClearance, 3000));
  EXPECT_EQ(sender.of(kBtpPortSpatem).size(), before + 1);
  rt.advance(99ms);
  EXPECT_EQ(sender.of(kBtpPortSpatem).size(), before + 1);
  rt.advance(1ms);
  EXPECT_EQ(sender.of(kBtpPortSpatem).size(), before + 2);
  // Another junction's groups changing is not our change.
  auto other = feed(rt, sim::MovementPhaseState::kProtectedClearance, 3000);
  other.groups[2].state = sim::MovementPhaseState::kStopAndRemain;
  rsu.on_signal_states(other);
  EXPECT_EQ(sender.of(kBtpPortSpatem).size(), before + 2);
}

TEST(RsuService, NoSpatemOnAStaleFeedUntilItResumes) {
  clock::ManualRuntime rt;
  RecordingSender sender(rt);
  RsuService rsu(rt, sender, four_way_map());
  const clock::SteadyTime t0 = rt.steady_now();
  rsu.start();
  rsu.on_signal_states(feed(rt, sim::MovementPhaseState::kStopAndRemain, 30'000));
  rt.advance(5s);
  const auto spatems = sender.of(kBtpPortSpatem);
  // At 0 (the feed), then every 100 ms up to and including 2 s: the feed is stale after that.
  ASSERT_FALSE(spatems.empty());
  EXPECT_EQ(spatems.back().at - t0, 2s);
  EXPECT_EQ(spatems.size(), 21u);
  EXPECT_EQ(rsu.counters().spatem_stale, 30u);  // 2.1 .. 5.0 s
  EXPECT_EQ(rsu.last_feed_age_ms(), 5000);
  EXPECT_EQ(sender.of(kBtpPortMapem).size(), 6u);  // MAPEM does not depend on the feed
  rsu.on_signal_states(feed(rt, sim::MovementPhaseState::kStopAndRemain, 25'000));
  rt.advance(100ms);
  EXPECT_EQ(sender.of(kBtpPortSpatem).size(), 22u);
  EXPECT_EQ(rsu.last_feed_age_ms(), 100);
}

TEST(RsuService, MalformedAndForeignDatagramsAreCountedNeverSent) {
  clock::ManualRuntime rt;
  RecordingSender sender(rt);
  RsuService rsu(rt, sender, four_way_map());
  rsu.start();
  const std::vector<std::uint8_t> good =
      sim::encode(feed(rt, sim::MovementPhaseState::kStopAndRemain, 5000));
  std::vector<std::uint8_t> garbage{1, 2, 3, 4, 5, 6, 7, 8, 9};
  std::vector<std::uint8_t> truncated(good.begin(), good.end() - 3);
  std::vector<std::uint8_t> two = good;
  two.insert(two.end(), good.begin(), good.end());
  const std::vector<std::uint8_t> closing = sim::encode(sim::Closing{});
  std::vector<std::uint8_t> bad_version = good;
  bad_version[2] = 6;
  for (const auto& d : {garbage, truncated, two, closing, bad_version, std::vector<std::uint8_t>{}})
    rsu.on_datagram(d);
  EXPECT_EQ(rsu.counters().feed_datagrams, 6u);
  EXPECT_EQ(rsu.counters().feed_malformed, 6u);
  EXPECT_TRUE(sender.of(kBtpPortSpatem).empty());
  EXPECT_FALSE(rsu.last_feed_age_ms().has_value());
  sim::SignalStates foreign;
  foreign.groups = {{7, 1, sim::MovementPhaseState::kStopAndRemain, 0, 0}};
  rsu.on_datagram(sim::encode(foreign));
  EXPECT_EQ(rsu.counters().feed_foreign, 1u);
  EXPECT_TRUE(sender.of(kBtpPortSpatem).empty());
  rsu.on_datagram(good);
  EXPECT_EQ(sender.of(kBtpPortSpatem).size(), 1u);
  EXPECT_EQ(rsu.counters().feed_malformed, 6u);
}

TEST(RsuService, SendRefusalsAreCounted) {
  clock::ManualRuntime rt;
  RecordingSender sender(rt);
  sender.refuse = true;  // no position yet
  RsuService rsu(rt, sender, four_way_map());
  rsu.start();
  rsu.on_signal_states(feed(rt, sim::MovementPhaseState::kStopAndRemain, 5000));
  rt.advance(1s);
  EXPECT_EQ(rsu.counters().mapem_sent, 0u);
  EXPECT_EQ(rsu.counters().spatem_sent, 0u);
  EXPECT_EQ(rsu.counters().send_errors, 2u + 11u);  // MAPEM at 0 and 1 s, SPATEM 0..1 s
  sender.refuse = false;
  rt.advance(100ms);
  EXPECT_EQ(rsu.counters().spatem_sent, 1u);
}

}  // namespace
}  // namespace tb::its::rsu
