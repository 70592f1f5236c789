#include "network-emulator/radio/federation_datagram.hpp"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace tb::emu::radio {
namespace {

const std::vector<std::uint8_t> kFrame = {0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 2,    0,
                                          0,    0,    3,    0xe9, 0x89, 0x47, 0x11, 0x22};

TEST(FederationDatagramTest, AFrameRoundTrips) {
  std::vector<std::uint8_t> out;
  const std::array<double, 3> pos = {-12.5, 300.25, 1.5};
  ASSERT_TRUE(
      encode_federated_frame("tb-node1", 1001, &pos, 1'700'000'000'123'456'789, kFrame, out));
  EXPECT_EQ(out.size(), kFederationHeadSize + 8 + kFederationFrameFieldsSize + kFrame.size());
  const auto d = decode_federation_datagram(out);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->kind, FederationKind::kFrame);
  EXPECT_EQ(d->node, "tb-node1");
  EXPECT_EQ(d->sender, 1001u);
  EXPECT_TRUE(d->has_position);
  EXPECT_EQ(d->position, pos);
  EXPECT_EQ(d->tx_unix_ns, 1'700'000'000'123'456'789);
  EXPECT_EQ(std::vector<std::uint8_t>(d->frame.begin(), d->frame.end()), kFrame);

  ASSERT_TRUE(encode_federated_frame("n", 7, nullptr, 5, {}, out));
  const auto e = decode_federation_datagram(out);
  ASSERT_TRUE(e);
  EXPECT_FALSE(e->has_position);
  EXPECT_TRUE(e->frame.empty());
}

TEST(FederationDatagramTest, AHeartbeatRoundTrips) {
  std::vector<std::uint8_t> out;
  ASSERT_TRUE(encode_federation_heartbeat("tb-node2", -1, out));
  const auto d = decode_federation_datagram(out);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->kind, FederationKind::kHeartbeat);
  EXPECT_EQ(d->node, "tb-node2");
  EXPECT_EQ(d->tx_unix_ns, -1);
}

TEST(FederationDatagramTest, EncoderRefusesWhatItCannotCarry) {
  std::vector<std::uint8_t> out;
  EXPECT_FALSE(encode_federated_frame("", 1, nullptr, 0, kFrame, out));
  EXPECT_FALSE(encode_federated_frame(std::string(65, 'n'), 1, nullptr, 0, kFrame, out));
  const std::vector<std::uint8_t> big(kMaxFederatedFrame + 1);
  EXPECT_FALSE(encode_federated_frame("n", 1, nullptr, 0, big, out));
  EXPECT_TRUE(out.empty());
}

TEST(FederationDatagramTest, EveryCutOfAValidDatagramIsRefused) {
  std::vector<std::uint8_t> full;
  const std::array<double, 3> pos = {1, 2, 3};
  ASSERT_TRUE(encode_federated_frame("node", 9, &pos, 1, kFrame, full));
  for (std::size_t n = 0; n < full.size(); ++n) {
    // A copy of exactly n bytes, so that a sanitizer sees any read past its end.
    const std::vector<std::uint8_t> cut(full.begin(), full.begin() + static_cast<long>(n));
    EXPECT_FALSE(decode_federation_datagram(cut)) << n << " bytes";
  }
  auto longer = full;
  longer.push_back(0);
  EXPECT_EQ(decode_federation_datagram(longer).error(), FederationError::kBadFrameLength);
}

TEST(FederationDatagramTest, MalformedFieldsAreRefusedWithTheirReason) {
  std::vector<std::uint8_t> good;
  const std::array<double, 3> pos = {1, 2, 3};
  ASSERT_TRUE(encode_federated_frame("node", 9, &pos, 1, kFrame, good));
  auto with = [&](std::size_t at, std::uint8_t v) {
    auto b = good;
    b.at(at) = v;
    return decode_federation_datagram(b);
  };
  EXPECT_EQ(with(0, 'X').error(), FederationError::kBadMagic);
  EXPECT_EQ(with(4, 2).error(), FederationError::kUnsupportedVersion);
  EXPECT_EQ(with(5, 3).error(), FederationError::kUnknownKind);
  EXPECT_EQ(with(6, 0).error(), FederationError::kBadNodeName);
  EXPECT_EQ(with(6, 65).error(), FederationError::kBadNodeName);
  EXPECT_EQ(with(6, 200).error(), FederationError::kBadNodeName);
  // Frame length (u16 at 6 after the sender) one too many.
  const std::size_t fields = kFederationHeadSize + 4;  // after the name "node"
  EXPECT_EQ(with(fields + 7, static_cast<std::uint8_t>(kFrame.size() + 1)).error(),
            FederationError::kBadFrameLength);
  // x = NaN.
  auto nan = good;
  const auto bits = std::bit_cast<std::uint64_t>(std::numeric_limits<double>::quiet_NaN());
  for (int i = 0; i < 8; ++i)
    nan[fields + 16 + static_cast<std::size_t>(i)] =
        static_cast<std::uint8_t>(bits >> (56 - 8 * i));
  EXPECT_EQ(decode_federation_datagram(nan).error(), FederationError::kBadPosition);
  std::vector<std::uint8_t> hb;
  ASSERT_TRUE(encode_federation_heartbeat("node", 1, hb));
  hb.push_back(0);
  EXPECT_EQ(decode_federation_datagram(hb).error(), FederationError::kTrailingBytes);
}

}  // namespace
}  // namespace tb::emu::radio
