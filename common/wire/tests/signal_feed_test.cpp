// The signal feed's datagrams (issue 34): one SignalStates frame each, nothing more or less.

#include <gtest/gtest.h>

#include "common/wire/signal_feed.hpp"

namespace tb::wire {
namespace {

using P = sim::MovementPhaseState;

sim::SignalStates sample() {
  const std::int64_t t = 1'795'000'000'000;
  return {t,
          {{100, 1, P::kProtectedMovementAllowed, t + 900, t + 900},
           {100, 2, P::kStopAndRemain, t + 5000, t + 6000}}};
}

TEST(SignalFeed, ADatagramIsExactlyOneSimProtocolFrame) {
  const auto bytes = encode_signal_feed(sample());
  ASSERT_TRUE(bytes.has_value());
  // The sim protocol's own encoding, header "SP", version 7, type 0x86: the same bytes.
  EXPECT_EQ(*bytes, sim::encode(sample()));
  EXPECT_EQ((*bytes)[0], 'S');
  EXPECT_EQ((*bytes)[1], 'P');
  EXPECT_EQ((*bytes)[2], 7);
  EXPECT_EQ((*bytes)[3], 0x86);
  // 8 header + 8 world time + 2 count + 2 × 20.
  EXPECT_EQ(bytes->size(), 8u + 10u + 2u * 20u);
  const auto back = decode_signal_feed(*bytes);
  ASSERT_TRUE(back.has_value()) << to_string(back.error());
  EXPECT_EQ(*back, sample());
}

TEST(SignalFeed, AnEmptyListIsAValidMessage) {
  const sim::SignalStates none{42, {}};
  const auto back = decode_signal_feed(*encode_signal_feed(none));
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(*back, none);
}

TEST(SignalFeed, CutOrPaddedDatagramsAreRefused) {
  auto bytes = *encode_signal_feed(sample());
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    const auto r = decode_signal_feed(std::span<const std::uint8_t>(bytes.data(), n));
    ASSERT_FALSE(r.has_value()) << n;
    EXPECT_EQ(r.error(), SignalFeedError::kTruncated) << n;
  }
  bytes.push_back(0);
  EXPECT_EQ(decode_signal_feed(bytes).error(), SignalFeedError::kTrailingBytes);
  // Two frames in one datagram are refused too: one frame per datagram.
  auto two = *encode_signal_feed(sample());
  const auto second = two;
  two.insert(two.end(), second.begin(), second.end());
  EXPECT_EQ(decode_signal_feed(two).error(), SignalFeedError::kTrailingBytes);
}

TEST(SignalFeed, OtherFramesAndGarbageAreRefused) {
  // Another server frame, valid in the protocol but not in the feed.
  const auto closing = sim::encode(sim::Closing{});
  EXPECT_EQ(decode_signal_feed(closing).error(), SignalFeedError::kNotSignalStates);
  // A client message type.
  const auto hello = sim::encode(sim::Hello{"x"});
  EXPECT_EQ(decode_signal_feed(hello).error(), SignalFeedError::kNotSignalStates);
  auto bytes = *encode_signal_feed(sample());
  bytes[0] = 'X';
  EXPECT_EQ(decode_signal_feed(bytes).error(), SignalFeedError::kBadFrame);
  bytes = *encode_signal_feed(sample());
  bytes[2] = 6;  // an older protocol version
  EXPECT_EQ(decode_signal_feed(bytes).error(), SignalFeedError::kBadFrame);
  // Groups out of order (the decoder's rule), and a reserved SignalGroupID.
  auto swapped = sample();
  std::swap(swapped.groups[0], swapped.groups[1]);
  EXPECT_EQ(decode_signal_feed(sim::encode(swapped)).error(), SignalFeedError::kBadFrame);
  auto reserved = sample();
  reserved.groups[1].signal_group = 255;
  EXPECT_EQ(decode_signal_feed(sim::encode(reserved)).error(), SignalFeedError::kBadFrame);
}

TEST(SignalFeed, StatesBeyondADatagramAreNotEncoded) {
  sim::SignalStates many{1, {}};
  // An 18-byte head and 3274 groups of 20 bytes fit 65507 bytes; 3275 do not.
  for (int i = 0; i < 3275; ++i)
    many.groups.push_back({static_cast<std::uint16_t>(i / 254),
                           static_cast<std::uint8_t>(1 + i % 254), P::kStopAndRemain, 0, 0});
  EXPECT_EQ(encode_signal_feed(many).error(), SignalFeedError::kTooLarge);
  many.groups.pop_back();
  EXPECT_TRUE(encode_signal_feed(many).has_value());
}

}  // namespace
}  // namespace tb::wire
