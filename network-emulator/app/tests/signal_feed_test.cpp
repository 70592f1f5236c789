// SignalFeed (issue 34): signal-state datagrams from the sim-clients in, each RSU's junction's
// groups out, with copies from several clients dropped. Injected datagrams, capture sinks.

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "network-emulator/app/signal_feed.hpp"

namespace tb::emu {
namespace {

namespace sim = wire::sim;
using P = sim::MovementPhaseState;

class CaptureSink final : public DatagramSink {
 public:
  std::error_code send(std::span<const std::uint8_t> d) override {
    if (fail)
      return std::make_error_code(std::errc::connection_refused);
    sent.emplace_back(d.begin(), d.end());
    return {};
  }
  std::vector<std::vector<std::uint8_t>> sent;
  bool fail = false;
};

constexpr std::int64_t kT = 1'795'000'000'000;

/// The server's message: junctions 7 (groups 1, 2), 100 (1 to 4) and 300 (1), ascending.
sim::SignalStates world(std::int64_t t) {
  sim::SignalStates s{t, {}};
  s.groups.push_back({7, 1, P::kProtectedMovementAllowed, t + 1000, t + 1000});
  s.groups.push_back({7, 2, P::kStopAndRemain, t + 9000, t + 9000});
  for (std::uint8_t g = 1; g <= 4; ++g)
    s.groups.push_back(
        {100, g, g % 2 ? P::kProtectedClearance : P::kStopAndRemain, t + 2000 * g, t + 2500 * g});
  s.groups.push_back({300, 1, P::kStopAndRemain, 0, 0});
  return s;
}

sim::SignalStates decoded(const std::vector<std::uint8_t>& d) {
  const auto s = wire::decode_signal_feed(d);
  EXPECT_TRUE(s.has_value()) << wire::to_string(s.error());
  return s ? *s : sim::SignalStates{};
}

class SignalFeedTest : public ::testing::Test {
 protected:
  SignalFeed make() {
    return SignalFeed({{5001, 100, &rsu100}, {5002, 7, &rsu7}, {5003, 555, &rsu555}}, tracer);
  }
  CaptureSink rsu100, rsu7, rsu555;
  trace::Tracer tracer;
};

TEST_F(SignalFeedTest, EachRsuGetsOnlyItsJunctionsGroupsAtOnce) {
  SignalFeed feed = make();
  ASSERT_TRUE(feed.handle_datagram(sim::encode(world(kT))));
  ASSERT_EQ(rsu100.sent.size(), 1u);
  ASSERT_EQ(rsu7.sent.size(), 1u);
  const sim::SignalStates a = decoded(rsu100.sent[0]);
  EXPECT_EQ(a.world_time_ms, kT);
  ASSERT_EQ(a.groups.size(), 4u);
  const auto all = world(kT);
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_EQ(a.groups[i], all.groups[2 + i]);  // unchanged, in the server's order
  const sim::SignalStates b = decoded(rsu7.sent[0]);
  ASSERT_EQ(b.groups.size(), 2u);
  EXPECT_EQ(b.groups[0].intersection_id, 7);
  EXPECT_EQ(b.groups[1].signal_group, 2);
  // Junction 555 is not in the message: its RSU gets nothing rather than an empty list.
  EXPECT_TRUE(rsu555.sent.empty());
  EXPECT_EQ(feed.counters().no_groups, 1u);
  EXPECT_EQ(feed.counters().sent, 2u);
}

TEST_F(SignalFeedTest, CopiesFromOtherClientsAndOvertakenMessagesAreDropped) {
  SignalFeed feed = make();
  EXPECT_TRUE(feed.handle_datagram(sim::encode(world(kT))));
  // A second client forwards the same message: one copy reaches the RSU.
  EXPECT_FALSE(feed.handle_datagram(sim::encode(world(kT))));
  // A slow client's older message after a newer one: dropped, the RSU keeps the newer.
  EXPECT_TRUE(feed.handle_datagram(sim::encode(world(kT + 1000))));
  EXPECT_FALSE(feed.handle_datagram(sim::encode(world(kT + 900))));
  EXPECT_TRUE(feed.handle_datagram(sim::encode(world(kT + 1010))));
  ASSERT_EQ(rsu100.sent.size(), 3u);
  EXPECT_EQ(decoded(rsu100.sent[2]).world_time_ms, kT + 1010);
  EXPECT_EQ(feed.counters().datagrams, 5u);
  EXPECT_EQ(feed.counters().duplicates, 2u);
  EXPECT_EQ(feed.counters().taken, 3u);
}

TEST_F(SignalFeedTest, AWorldThatStartsAgainIsTaken) {
  SignalFeed feed = make();
  EXPECT_TRUE(feed.handle_datagram(sim::encode(world(kT + 60'000))));
  // sim-server restarted with the same pinned start time: a minute back is a new world.
  EXPECT_TRUE(feed.handle_datagram(sim::encode(world(kT))));
  EXPECT_EQ(rsu100.sent.size(), 2u);
}

TEST_F(SignalFeedTest, MalformedDatagramsAreCountedByKindAndNeverPassedOn) {
  SignalFeed feed = make();
  const std::uint8_t junk[] = {'S', 'P', 7};
  EXPECT_FALSE(feed.handle_datagram(junk));
  auto cut = sim::encode(world(kT));
  cut.pop_back();
  EXPECT_FALSE(feed.handle_datagram(cut));
  auto padded = sim::encode(world(kT));
  padded.push_back(0);
  EXPECT_FALSE(feed.handle_datagram(padded));
  EXPECT_FALSE(feed.handle_datagram(sim::encode(sim::Closing{})));
  EXPECT_FALSE(feed.handle_datagram({}));
  const auto& c = feed.counters();
  EXPECT_EQ(c.malformed, 5u);
  EXPECT_EQ(c.malformed_by_error[static_cast<std::size_t>(wire::SignalFeedError::kTruncated)], 3u);
  EXPECT_EQ(c.malformed_by_error[static_cast<std::size_t>(wire::SignalFeedError::kTrailingBytes)],
            1u);
  EXPECT_EQ(c.malformed_by_error[static_cast<std::size_t>(wire::SignalFeedError::kNotSignalStates)],
            1u);
  EXPECT_TRUE(rsu100.sent.empty());
  // A malformed datagram does not move the de-duplication on: the next good one is taken.
  EXPECT_TRUE(feed.handle_datagram(sim::encode(world(kT))));
}

TEST_F(SignalFeedTest, ASinkThatFailsIsCountedAndTheOthersStillGetTheirs) {
  SignalFeed feed = make();
  rsu100.fail = true;
  EXPECT_TRUE(feed.handle_datagram(sim::encode(world(kT))));
  EXPECT_EQ(feed.counters().failed, 1u);
  EXPECT_EQ(rsu7.sent.size(), 1u);
}

TEST_F(SignalFeedTest, SendsAreTraced) {
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("signal_feed_trace_" + std::to_string(::getpid()) + ".jsonl");
  std::filesystem::remove(file);
  {
    trace::Tracer on(file.string(), "network-emulator");
    CaptureSink sink;
    SignalFeed feed({{5001, 100, &sink}}, on);
    feed.handle_datagram(sim::encode(world(kT)));
  }
  std::ifstream in(file);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::filesystem::remove(file);
  EXPECT_NE(text.find("\"ev\":\"emu.signals\""), std::string::npos) << text;
  EXPECT_NE(text.find("\"world_ms\":" + std::to_string(kT)), std::string::npos) << text;
  EXPECT_NE(text.find("\"station\":5001"), std::string::npos) << text;
}

}  // namespace
}  // namespace tb::emu
