#include <gtest/gtest.h>

#include <array>

#include "common/util/bytes.hpp"
#include "common/util/expected.hpp"

namespace tb {
namespace {

TEST(ByteReader, ReadsBothByteOrders) {
  const std::array<std::uint8_t, 6> b{0x12, 0x34, 0x56, 0x78, 0x9a, 0xbc};
  ByteReader r(b);
  EXPECT_EQ(r.be<std::uint16_t>(), 0x1234);
  EXPECT_EQ(r.le<std::uint32_t>(), 0xbc9a7856u);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.remaining(), 0u);
}

TEST(ByteReader, ReadingPastTheEndFailsAndYieldsZero) {
  const std::array<std::uint8_t, 3> b{1, 2, 3};
  ByteReader r(b);
  EXPECT_EQ(r.be<std::uint16_t>(), 0x0102);
  EXPECT_EQ(r.be<std::uint16_t>(), 0);
  EXPECT_FALSE(r.ok());
  std::array<std::uint8_t, 1> one{};
  EXPECT_FALSE(r.read(one));
}

TEST(ByteWriter, OverflowFailsWithoutWriting) {
  std::array<std::uint8_t, 3> out{};
  ByteWriter w(out);
  w.be<std::uint16_t>(0xabcd);
  w.be<std::uint16_t>(0x1111);
  EXPECT_FALSE(w.ok());
  EXPECT_EQ(out[0], 0xab);
  EXPECT_EQ(out[1], 0xcd);
  EXPECT_EQ(out[2], 0x00);
}

TEST(Expected, HoldsValueOrError) {
  Expected<int, std::string> good = 5;
  Expected<int, std::string> bad = Unexpected{std::string("nope")};
  ASSERT_TRUE(good);
  EXPECT_EQ(*good, 5);
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error(), "nope");
}

}  // namespace
}  // namespace tb
