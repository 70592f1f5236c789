#include <gtest/gtest.h>

#include "its-station/geonet/timestamp.hpp"

namespace tb::its::geonet {
namespace {

clock::WallTime unix_s(std::int64_t s) {
  return clock::WallTime{std::chrono::seconds{s}};
}

TEST(Timestamp, CountsMillisecondsFromTheItsEpoch) {
  EXPECT_EQ(to_timestamp(unix_s(kItsEpochUnixSeconds)), 0u);
  EXPECT_EQ(to_timestamp(unix_s(kItsEpochUnixSeconds) + std::chrono::milliseconds{1234}), 1234u);
}

TEST(Timestamp, AddsTheLeapSecondsInsertedSince2004) {
  EXPECT_EQ(leap_seconds_since_its_epoch(unix_s(1'136'073'599)), 0);  // 2005-12-31 23:59:59
  EXPECT_EQ(leap_seconds_since_its_epoch(unix_s(1'136'073'600)), 1);  // 2006-01-01
  EXPECT_EQ(leap_seconds_since_its_epoch(unix_s(1'483'228'799)), 4);
  EXPECT_EQ(leap_seconds_since_its_epoch(unix_s(1'483'228'800)), 5);  // 2017-01-01
  // 2017-01-01 00:00:00 UTC: 410 313 600 s after the epoch plus 5 leap seconds, in ms, mod 2^32:
  // 410 313 605 000 mod 4 294 967 296 = 2 291 711 880.
  EXPECT_EQ(to_timestamp(unix_s(1'483'228'800)), 2'291'711'880u);
  // 2023-11-14 22:13:20 UTC (Unix 1.7e9): 627 084 805 000 mod 2^32 = 19 579 784.
  EXPECT_EQ(to_timestamp(unix_s(1'700'000'000)), 19'579'784u);
}

TEST(Timestamp, NewerAndDifferenceHonourTheWrap) {
  EXPECT_TRUE(is_newer(10, 5));
  EXPECT_FALSE(is_newer(5, 10));
  EXPECT_FALSE(is_newer(7, 7));
  EXPECT_TRUE(is_newer(3, 0xffff'fff0u));  // wrapped: 3 is 19 ms after 2^32 − 16
  EXPECT_FALSE(is_newer(0xffff'fff0u, 3));
  EXPECT_EQ(timestamp_difference(3, 0xffff'fff0u), 19);
  EXPECT_EQ(timestamp_difference(0xffff'fff0u, 3), -19);
}

}  // namespace
}  // namespace tb::its::geonet
