#include "network-emulator/radio/medium.hpp"
#include "network-emulator/radio/tests/recording_sink.hpp"

#include <gtest/gtest.h>

namespace tb::emu::radio {
namespace {

using namespace std::chrono_literals;
using Kind = scenario::ChannelModel::Kind;

using testing::frame;
using testing::RecordingSink;

class MediumTest : public ::testing::Test {
 protected:
  void SetUp() override {
    positions.set(1, {{0, 0, 0}, 0});
    positions.set(2, {{200, 0, 0}, 0});
    positions.set(3, {{450, 0, 0}, 0});
  }
  std::unique_ptr<Channel> make(scenario::ChannelModel m) {
    auto ch = std::make_unique<Channel>(m, positions, 1);
    return ch;
  }
  clock::ManualRuntime rt;
  PositionTable positions;
  RecordingSink s1, s2, s3;
};

TEST_F(MediumTest, RangeModelReachesNeighboursOnlyAndNeverTheSender) {
  scenario::ChannelModel m;
  m.kind = Kind::kRange;
  m.range_m = 300;
  auto ch = make(m);
  Medium medium(rt, *ch);
  medium.attach(1, s1);
  medium.attach(2, s2);
  medium.attach(3, s3);
  medium.on_frame(1, frame(1));  // 2 at 200 m hears it, 3 at 450 m does not
  medium.on_frame(2, frame(2));  // both 1 and 3 (250 m) hear it
  EXPECT_TRUE(s1.frames.size() == 1 && s1.frames[0] == frame(2));
  ASSERT_EQ(s2.frames.size(), 1u);
  EXPECT_EQ(s2.frames[0], frame(1));
  ASSERT_EQ(s3.frames.size(), 1u);
  EXPECT_EQ(s3.frames[0], frame(2));
  EXPECT_EQ(medium.frames_in(), 2u);
  EXPECT_EQ(medium.deliveries(), 3u);
  EXPECT_EQ(ch->links().at({1, 3}).dropped[static_cast<int>(DropReason::kOutOfRange)], 1u);
}

TEST_F(MediumTest, DelayedFramesArriveAtTheirTimeAndInOrder) {
  scenario::ChannelModel m;
  m.delay_ms = 5;
  m.jitter_ms = 4;
  auto ch = make(m);
  Medium medium(rt, *ch);
  medium.attach(1, s1);
  medium.attach(2, s2);
  for (std::uint8_t i = 0; i < 50; ++i) {
    medium.on_frame(1, frame(i));
    rt.advance(100us);  // far less than the jitter: later frames could overtake without FIFO
  }
  EXPECT_TRUE(s2.frames.empty());  // 5 ms have not passed yet for any of them
  rt.advance(4ms);
  rt.advance(10ms);
  ASSERT_EQ(s2.frames.size(), 50u);
  for (std::uint8_t i = 0; i < 50; ++i)
    EXPECT_EQ(s2.frames[i].back(), i);
  EXPECT_EQ(medium.pending(), 0u);
  EXPECT_TRUE(s1.frames.empty());
}

TEST_F(MediumTest, FixedDelayIsExact) {
  scenario::ChannelModel m;
  m.delay_ms = 3;
  auto ch = make(m);
  Medium medium(rt, *ch);
  medium.attach(1, s1);
  medium.attach(2, s2);
  medium.on_frame(1, frame(7));
  rt.advance(2999us);
  EXPECT_TRUE(s2.frames.empty());
  rt.advance(1us);
  EXPECT_EQ(s2.frames.size(), 1u);
}

TEST_F(MediumTest, DetachedReceiverGetsNothingStillInFlight) {
  scenario::ChannelModel m;
  m.delay_ms = 1;
  auto ch = make(m);
  Medium medium(rt, *ch);
  medium.attach(1, s1);
  medium.attach(2, s2);
  medium.on_frame(1, frame(1));
  medium.detach(2);
  rt.advance(2ms);
  EXPECT_TRUE(s2.frames.empty());
}

TEST_F(MediumTest, DestroyingTheMediumCancelsItsTimers) {
  scenario::ChannelModel m;
  m.delay_ms = 1;
  auto ch = make(m);
  {
    Medium medium(rt, *ch);
    medium.attach(1, s1);
    medium.attach(2, s2);
    medium.on_frame(1, frame(1));
    EXPECT_EQ(rt.pending(), 1u);
  }
  EXPECT_EQ(rt.pending(), 0u);
  rt.advance(2ms);
  EXPECT_TRUE(s2.frames.empty());
}

}  // namespace
}  // namespace tb::emu::radio
