#include <gtest/gtest.h>

#include "network-emulator/app/peer_health.hpp"

namespace tb::emu {
namespace {

using namespace std::chrono_literals;
using Change = PeerHealth::Change;

TEST(PeerHealth, PausesOnRefusalProbesOncePerIntervalAndResumesAfterTwoGoodSends) {
  clock::ManualClock clock;
  PeerHealth h(clock, 1s);
  ASSERT_TRUE(h.should_send());
  EXPECT_EQ(h.record({}), Change::kNone);
  ASSERT_TRUE(h.should_send());
  EXPECT_EQ(h.record(std::make_error_code(std::errc::connection_refused)), Change::kPaused);
  EXPECT_TRUE(h.paused());
  EXPECT_FALSE(h.should_send());
  clock.advance(999ms);
  EXPECT_FALSE(h.should_send());
  EXPECT_EQ(h.skipped(), 2u);
  clock.advance(1ms);
  ASSERT_TRUE(h.should_send());  // the probe
  EXPECT_EQ(h.record({}), Change::kNone);
  ASSERT_TRUE(h.should_send());
  // The probe drew an ICMP answer: still gone, paused again without a second log line.
  EXPECT_EQ(h.record(std::make_error_code(std::errc::connection_refused)), Change::kNone);
  EXPECT_FALSE(h.should_send());
  clock.advance(1s);
  ASSERT_TRUE(h.should_send());
  EXPECT_EQ(h.record({}), Change::kNone);
  ASSERT_TRUE(h.should_send());
  EXPECT_EQ(h.record({}), Change::kResumed);
  EXPECT_FALSE(h.paused());
  EXPECT_EQ(h.last_error(), std::errc::connection_refused);
}

TEST(PeerHealth, AFullSocketBufferPausesNothing) {
  clock::ManualClock clock;
  PeerHealth h(clock);
  EXPECT_EQ(h.record(std::make_error_code(std::errc::operation_would_block)), Change::kNone);
  EXPECT_EQ(h.record(std::make_error_code(std::errc::no_buffer_space)), Change::kNone);
  EXPECT_FALSE(h.paused());
  EXPECT_EQ(h.record(std::make_error_code(std::errc::host_unreachable)), Change::kPaused);
}

}  // namespace
}  // namespace tb::emu
