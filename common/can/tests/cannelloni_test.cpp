#include <gtest/gtest.h>

#include "common/can/cannelloni.hpp"

namespace tb::can {
namespace {

TEST(Cannelloni, EncodesTheWireFormatByteForByte) {
  const std::uint8_t a[] = {0xDE, 0xAD};
  CanFrame ext = make_frame(0x12345, {}, true);
  ext.len = 0;
  CanFrame rtr;
  rtr.can_id = 0x7FF | kRtrFlag;
  rtr.len = 4;  // a remote frame asks for 4 bytes but carries none
  const CanFrame frames[] = {make_frame(0x123, a), ext, rtr};
  const auto bytes = encode_cannelloni(7, frames);
  const std::vector<std::uint8_t> expected{
      0x02, 0x00, 0x07, 0x00, 0x03,              // version 2, DATA, seq 7, 3 frames
      0x00, 0x00, 0x01, 0x23, 0x02, 0xDE, 0xAD,  // 0x123, len 2
      0x80, 0x01, 0x23, 0x45, 0x00,              // EFF | 0x12345, len 0
      0x40, 0x00, 0x07, 0xFF, 0x04};             // RTR | 0x7FF, len 4, no data
  EXPECT_EQ(bytes, expected);
  EXPECT_EQ(cannelloni_size(frames), expected.size());

  auto p = decode_cannelloni(bytes);
  ASSERT_TRUE(p.has_value()) << to_string(p.error());
  EXPECT_EQ(p->sequence, 7);
  ASSERT_EQ(p->frames.size(), 3u);
  EXPECT_EQ(p->frames[0], frames[0]);
  EXPECT_EQ(p->frames[1].id(), 0x12345u);
  EXPECT_TRUE(p->frames[1].extended());
  EXPECT_TRUE(p->frames[2].remote());
  EXPECT_EQ(p->frames[2].len, 4);
}

TEST(Cannelloni, CarriesCanFdFramesWithFlags) {
  CanFrame fd;
  fd.can_id = 0x42;
  fd.fd = true;
  fd.fd_flags = 0x01;  // BRS
  fd.len = 12;
  for (int i = 0; i < 12; ++i)
    fd.data[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(i);
  const auto bytes = encode_cannelloni(0, std::span(&fd, 1));
  ASSERT_EQ(bytes.size(), 5u + 4 + 1 + 1 + 12);
  EXPECT_EQ(bytes[9], 0x80 | 12);
  EXPECT_EQ(bytes[10], 0x01);
  auto p = decode_cannelloni(bytes);
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->frames[0], fd);
}

TEST(Cannelloni, RejectsMalformedPackets) {
  using V = std::vector<std::uint8_t>;
  auto err = [](const V& v) {
    auto p = decode_cannelloni(v);
    EXPECT_FALSE(p.has_value());
    return p ? CannelloniError{} : p.error();
  };
  EXPECT_EQ(err(V{0x02, 0x00, 0x01}), CannelloniError::kTruncatedHeader);
  EXPECT_EQ(err(V{0x01, 0x00, 0x01, 0x00, 0x00}), CannelloniError::kUnsupportedVersion);
  EXPECT_EQ(err(V{0x02, 0x01, 0x01, 0x00, 0x00}), CannelloniError::kNotData);
  EXPECT_EQ(err(V{0x02, 0x00, 0x01, 0x00, 0x01, 0x00, 0x00, 0x01, 0x23, 0x08, 0x01}),
            CannelloniError::kTruncatedFrame);
  EXPECT_EQ(err(V{0x02, 0x00, 0x01, 0xFF, 0xFF, 0x00, 0x00, 0x01, 0x23, 0x00}),
            CannelloniError::kTruncatedFrame);
  EXPECT_EQ(
      err(V{0x02, 0x00, 0x01, 0x00, 0x01, 0x00, 0x00, 0x01, 0x23, 0x09, 1, 2, 3, 4, 5, 6, 7, 8, 9}),
      CannelloniError::kBadLength);
  EXPECT_EQ(err(V{0x02, 0x00, 0x01, 0x00, 0x00, 0x99}), CannelloniError::kTrailingBytes);
  for (auto e : {CannelloniError::kTruncatedHeader, CannelloniError::kTrailingBytes})
    EXPECT_FALSE(to_string(e).empty());
}

TEST(Cannelloni, EveryTruncationIsAnErrorNotACrash) {
  const std::uint8_t a[] = {1, 2, 3, 4, 5, 6, 7, 8};
  const CanFrame frames[] = {make_frame(1, a), make_frame(2, a)};
  const auto bytes = encode_cannelloni(1, frames);
  for (std::size_t n = 0; n < bytes.size(); ++n)
    EXPECT_FALSE(decode_cannelloni(std::span(bytes).first(n)).has_value()) << n;
  EXPECT_TRUE(decode_cannelloni(bytes).has_value());
}

TEST(Cannelloni, EncodeRefusesTooSmallBuffer) {
  const std::uint8_t a[] = {1, 2};
  const CanFrame f = make_frame(1, a);
  std::array<std::uint8_t, 8> out{};
  EXPECT_EQ(encode_cannelloni(0, std::span(&f, 1), out), 0u);
}

}  // namespace
}  // namespace tb::can
