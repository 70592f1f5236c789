#include "network-emulator/app/relay.hpp"

#include <gtest/gtest.h>

namespace tb::emu {
namespace {

using namespace std::chrono_literals;

class RecordingSink final : public DatagramSink {
 public:
  std::error_code send(std::span<const std::uint8_t> d) override {
    got.emplace_back(d.begin(), d.end());
    return next_error;
  }
  std::vector<std::vector<std::uint8_t>> got;
  std::error_code next_error;
};

TEST(RelayTest, TargetsAreHostAndPortWithRoomForTheSignalFeed) {
  const auto t = parse_relay_target("emulator-tb-node2:4700");
  ASSERT_TRUE(t);
  EXPECT_EQ(t->host, "emulator-tb-node2");
  EXPECT_EQ(t->port, 4700);
  EXPECT_TRUE(parse_relay_target("10.0.0.2:1"));
  for (const char* bad : {"emulator", ":4700", "h:", "h:0", "h:65535", "h:47x", "::1:4700"})
    EXPECT_FALSE(parse_relay_target(bad)) << bad;
}

TEST(RelayTest, StatesAndSignalsGoUnchangedToEveryResolvedTarget) {
  clock::ManualClock clock;
  Relay relay(clock, {*parse_relay_target("a:4700"), *parse_relay_target("b:4700")});
  RecordingSink a_states, a_signals, b_states, b_signals;
  const std::vector<std::uint8_t> state = {1, 2, 3, 4}, signal = {9, 8};
  relay.relay_states(state);  // nobody resolved yet
  EXPECT_EQ(relay.not_relayed(), 2u);
  relay.attach(0, a_states, a_signals);
  relay.relay_states(state);
  relay.attach(1, b_states, b_signals);
  relay.relay_states(state);
  relay.relay_signals(signal);
  EXPECT_EQ(a_states.got, (std::vector<std::vector<std::uint8_t>>{state, state}));
  EXPECT_EQ(b_states.got, (std::vector<std::vector<std::uint8_t>>{state}));
  EXPECT_EQ(a_signals.got, (std::vector<std::vector<std::uint8_t>>{signal}));
  EXPECT_EQ(b_signals.got, (std::vector<std::vector<std::uint8_t>>{signal}));
  EXPECT_EQ(relay.relayed(), 5u);
  EXPECT_EQ(relay.not_relayed(), 3u);
  relay.detach(0);
  relay.relay_states(state);
  EXPECT_EQ(a_states.got.size(), 2u);
  EXPECT_EQ(b_states.got.size(), 2u);
}

TEST(RelayTest, AnAbsentTargetIsSaidOncePausedAndSaidAgainWhenBack) {
  clock::ManualClock clock;
  Relay relay(clock, {*parse_relay_target("a:4700"), *parse_relay_target("b:4700")});
  RecordingSink a_states, a_signals, b_states, b_signals;
  relay.attach(0, a_states, a_signals);
  relay.attach(1, b_states, b_signals);
  std::vector<std::string> events;
  relay.set_events([&](const RelayTarget& t, bool up, const std::string& why) {
    events.push_back(t.text() + (up ? " up: " : " down: ") + why);
  });
  const std::vector<std::uint8_t> d = {1};
  a_states.next_error = std::make_error_code(std::errc::connection_refused);
  for (int i = 0; i < 10; ++i)
    relay.relay_states(d);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_NE(events[0].find("a:4700 down"), std::string::npos) << events[0];
  EXPECT_EQ(a_states.got.size(), 1u);   // paused after the first refusal
  EXPECT_EQ(b_states.got.size(), 10u);  // the other target is not held up
  a_states.next_error = {};
  clock.advance(1100ms);  // a probe per retry interval; back after two sends in a row
  relay.relay_states(d);
  relay.relay_states(d);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[1], "a:4700 up: takes datagrams again");
  EXPECT_EQ(a_states.got.size(), 3u);
}

}  // namespace
}  // namespace tb::emu
