#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "common/wire/pooled_delivery.hpp"

namespace tb::wire {
namespace {

// A GN-over-Ethernet frame as a station sends it: broadcast, source 02:00:00:00:0b:c4 (station
// 3012), ethertype 0x8947, a few payload bytes.
std::vector<std::uint8_t> inner() {
  return {0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x02, 0x00, 0x00, 0x00, 0x0b,
          0xc4, 0x89, 0x47, 0x11, 0x00, 0x1a, 0x01, 0x20, 0x50, 0x02, 0x80};
}

TEST(PooledDelivery, FrameLayoutIsTheContracts) {
  const std::vector<std::uint32_t> ids{3004, 0xA1B2C3D4};
  const auto in = inner();
  const auto f = build_pooled_delivery_frame(ids, in);
  ASSERT_EQ(f.size(), 14u + 8 + 8 + in.size());
  EXPECT_EQ(f.size(), pooled_delivery_frame_size(2, in.size()));
  const std::vector<std::uint8_t> head(f.begin(), f.begin() + 30);
  const std::vector<std::uint8_t> want{0xff, 0xff, 0xff, 0xff, 0xff, 0xff,  // broadcast
                                       0x02, 0x00, 0x00, 0x00, 0x0b, 0xc4,  // the original source
                                       0x88, 0xb5,                          // local experimental 1
                                       'T',  'B',  'P',  'D',  1,    0,
                                       0x00, 0x02,              // magic, version, reserved, count
                                       0x00, 0x00, 0x0b, 0xbc,  // 3004
                                       0xa1, 0xb2, 0xc3, 0xd4};
  EXPECT_EQ(head, want);
  EXPECT_EQ(std::vector<std::uint8_t>(f.begin() + 30, f.end()), in);
}

TEST(PooledDelivery, RoundTrips) {
  const std::vector<std::uint32_t> ids{7, 3004, 0xFFFFFFFF, 0};
  const auto in = inner();
  const auto f = build_pooled_delivery_frame(ids, in);
  const auto d = parse_pooled_delivery_frame(f);
  ASSERT_TRUE(d) << to_string(d.error());
  EXPECT_EQ(d->receivers(), ids);
  ASSERT_EQ(d->receiver_count(), 4u);
  EXPECT_EQ(d->receiver(1), 3004u);
  EXPECT_EQ(std::vector<std::uint8_t>(d->inner_frame.begin(), d->inner_frame.end()), in);
  const std::vector<std::uint8_t> src(d->source_mac().begin(), d->source_mac().end());
  EXPECT_EQ(src, (std::vector<std::uint8_t>{0x02, 0x00, 0x00, 0x00, 0x0b, 0xc4}));
}

TEST(PooledDelivery, RoundTripsTheLargestCount) {
  std::vector<std::uint32_t> ids(kMaxPooledReceivers);
  for (std::size_t i = 0; i < ids.size(); ++i)
    ids[i] = static_cast<std::uint32_t>(i * 7919);
  const auto in = inner();
  const auto f = build_pooled_delivery_frame(ids, in);
  const auto d = parse_pooled_delivery_frame(f);
  ASSERT_TRUE(d) << to_string(d.error());
  EXPECT_EQ(d->receivers(), ids);
}

TEST(PooledDelivery, BuilderRefusesWhatItCannotWrite) {
  const auto in = inner();
  std::vector<std::uint8_t> out(4096);
  const std::vector<std::uint32_t> one{1};
  EXPECT_EQ(build_pooled_delivery({}, in, out), 0u);  // nobody receives: no frame
  std::vector<std::uint32_t> too_many(kMaxPooledReceivers + 1, 1);
  std::vector<std::uint8_t> big(pooled_delivery_frame_size(too_many.size(), in.size()));
  EXPECT_EQ(build_pooled_delivery_frame(too_many, in, big), 0u);
  EXPECT_EQ(build_pooled_delivery(one, std::span(in).first(13), out), 0u);
  // exactly large enough, and one byte short
  std::vector<std::uint8_t> exact(pooled_delivery_size(1, in.size()));
  EXPECT_EQ(build_pooled_delivery(one, in, exact), exact.size());
  EXPECT_EQ(build_pooled_delivery(one, in, std::span(exact).first(exact.size() - 1)), 0u);
  std::vector<std::uint8_t> exact_frame(pooled_delivery_frame_size(1, in.size()));
  EXPECT_EQ(build_pooled_delivery_frame(one, in, exact_frame), exact_frame.size());
  EXPECT_EQ(build_pooled_delivery_frame(one, in, std::span(exact_frame).first(13)), 0u);
  EXPECT_EQ(build_pooled_delivery_frame(one, in, std::span(exact_frame).first(40)), 0u);
}

TEST(PooledDelivery, ReceiversPerFrameFitTheMtu) {
  EXPECT_EQ(pooled_receivers_per_frame(1500, 400), (1500u - 8 - 400) / 4);
  EXPECT_EQ(pooled_delivery_size(pooled_receivers_per_frame(1500, 400), 400) <= 1500, true);
  EXPECT_EQ(pooled_receivers_per_frame(411, 400), 0u);
  EXPECT_EQ(pooled_receivers_per_frame(412, 400), 1u);
  EXPECT_EQ(pooled_receivers_per_frame(1u << 20, 14), kMaxPooledReceivers);
}

Expected<PooledDelivery, PooledDeliveryError> parse(const std::vector<std::uint8_t>& payload) {
  return parse_pooled_delivery(payload);
}

std::vector<std::uint8_t> good_payload() {
  const std::vector<std::uint32_t> ids{11, 12};
  const auto in = inner();
  std::vector<std::uint8_t> p(pooled_delivery_size(ids.size(), in.size()));
  EXPECT_EQ(build_pooled_delivery(ids, in, p), p.size());
  return p;
}

TEST(PooledDelivery, RefusesEveryTruncation) {
  const auto p = good_payload();
  ASSERT_TRUE(parse(p));
  for (std::size_t n = 0; n < p.size(); ++n) {
    const auto d = parse_pooled_delivery(std::span(p).first(n));
    if (n < kPooledDeliveryHeadSize + 8 + kEthernetHeaderSize) {
      ASSERT_FALSE(d) << n;
      const auto want = n < kPooledDeliveryHeadSize ? PooledDeliveryError::kTooShort
                        : n < kPooledDeliveryHeadSize + 8
                            ? PooledDeliveryError::kTruncatedReceivers
                            : PooledDeliveryError::kInnerFrameTooShort;
      EXPECT_EQ(d.error(), want) << n;
    } else {
      // a shorter GN payload is still a frame: the parser does not judge the inner frame's body
      ASSERT_TRUE(d) << n;
      EXPECT_EQ(d->inner_frame.size(), n - kPooledDeliveryHeadSize - 8);
    }
  }
}

TEST(PooledDelivery, RefusesBadMagicVersionAndCount) {
  for (std::size_t i = 0; i < 4; ++i) {
    auto p = good_payload();
    p[i] ^= 0x20;
    const auto d = parse(p);
    ASSERT_FALSE(d);
    EXPECT_EQ(d.error(), PooledDeliveryError::kBadMagic);
  }
  for (std::uint8_t v : {0, 2, 255}) {
    auto p = good_payload();
    p[4] = v;
    const auto d = parse(p);
    ASSERT_FALSE(d);
    EXPECT_EQ(d.error(), PooledDeliveryError::kUnsupportedVersion);
  }
  auto zero = good_payload();
  zero[6] = zero[7] = 0;
  ASSERT_FALSE(parse(zero));
  EXPECT_EQ(parse(zero).error(), PooledDeliveryError::kNoReceivers);
  // A count larger than the bytes (the high byte matters: 0x0102 ids).
  auto big = good_payload();
  big[6] = 1;
  ASSERT_FALSE(parse(big));
  EXPECT_EQ(parse(big).error(), PooledDeliveryError::kTruncatedReceivers);
  // A count that leaves the inner frame without its header: 5 ids eat 12 of its 22 bytes.
  auto eats = good_payload();
  eats[7] = 5;
  ASSERT_FALSE(parse(eats));
  EXPECT_EQ(parse(eats).error(), PooledDeliveryError::kInnerFrameTooShort);
}

TEST(PooledDelivery, IgnoresTheReservedByte) {
  auto p = good_payload();
  p[5] = 0x5a;
  const auto d = parse(p);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->receivers(), (std::vector<std::uint32_t>{11, 12}));
}

TEST(PooledDelivery, OuterFrameNeedsItsEthertype) {
  const std::vector<std::uint32_t> ids{1};
  auto f = build_pooled_delivery_frame(ids, inner());
  ASSERT_TRUE(parse_pooled_delivery_frame(f));
  for (std::size_t n : {0, 1, 13}) {
    const auto d = parse_pooled_delivery_frame(std::span(f).first(n));
    ASSERT_FALSE(d);
    EXPECT_EQ(d.error(), PooledDeliveryError::kNotPooledDelivery);
  }
  const auto head_only = parse_pooled_delivery_frame(std::span(f).first(14));
  ASSERT_FALSE(head_only);
  EXPECT_EQ(head_only.error(), PooledDeliveryError::kTooShort);
  f[12] = 0x89;
  f[13] = 0x47;  // a plain GN frame is not a pooled delivery
  ASSERT_FALSE(parse_pooled_delivery_frame(f));
  EXPECT_EQ(parse_pooled_delivery_frame(f).error(), PooledDeliveryError::kNotPooledDelivery);
}

TEST(PooledDelivery, EveryErrorHasAName) {
  for (std::size_t i = 0; i < kPooledDeliveryErrorCount; ++i)
    EXPECT_NE(to_string(static_cast<PooledDeliveryError>(i)), "unknown TBPD error") << i;
}

}  // namespace
}  // namespace tb::wire
