#include "sim-client/v2x/warning_sound.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <vector>

namespace tb::client::v2x {
namespace {

constexpr int kRate = 48000;

// Zero crossings from negative to positive in [from, to): the tone's frequency times the time.
int rising(const std::vector<std::int16_t>& s, std::size_t from, std::size_t to) {
  int n = 0;
  for (std::size_t i = from + 1; i < to; ++i)
    n += s[i - 1] < 0 && s[i] >= 0;
  return n;
}

int peak(const std::vector<std::int16_t>& s, std::size_t from, std::size_t to) {
  int p = 0;
  for (std::size_t i = from; i < to; ++i)
    p = std::max(p, std::abs(static_cast<int>(s[i])));
  return p;
}

TEST(WarningTone, SilentWhileOff) {
  WarningTone t(kRate);
  std::vector<std::int16_t> s(4800, 123);
  t.fill(s);
  EXPECT_EQ(peak(s, 0, s.size()), 0);
}

TEST(WarningTone, WarningBeeps1kHz150msOn150msOff) {
  WarningTone t(kRate);
  t.set(Alarm::kWarning);
  std::vector<std::int16_t> s(kRate);  // one second
  t.fill(s);
  // First beep: 0..150 ms, 1 kHz: ~150 rising crossings; then silence to 300 ms.
  EXPECT_NEAR(rising(s, 0, 7200), 150, 2);
  EXPECT_GT(peak(s, 480, 6720), 8000);
  EXPECT_EQ(peak(s, 7300, 14300), 0);
  EXPECT_GT(peak(s, 14400 + 480, 14400 + 6720), 8000);  // the second beep
}

TEST(WarningTone, CriticalIsFasterAndHigher) {
  WarningTone t(kRate);
  t.set(Alarm::kCritical);
  std::vector<std::int16_t> s(kRate);
  t.fill(s);
  EXPECT_NEAR(rising(s, 0, 3840), 120, 2);  // 80 ms at 1.5 kHz
  EXPECT_EQ(peak(s, 3900, 6700), 0);        // 60 ms gap
  EXPECT_GT(peak(s, 6720 + 480, 6720 + 3360), 8000);
}

TEST(WarningTone, RedLightIsADoubleBeepOfItsOwn) {
  WarningTone t(kRate);
  t.set(Alarm::kRedLight);
  std::vector<std::int16_t> s(kRate);
  t.fill(s);
  // 1.25 kHz: 90 ms beep (~112 rising crossings), 60 ms gap, 90 ms beep, silence to 600 ms.
  EXPECT_NEAR(rising(s, 0, 4320), 112, 2);
  EXPECT_GT(peak(s, 480, 3840), 8000);
  EXPECT_EQ(peak(s, 4400, 7150), 0);
  EXPECT_GT(peak(s, 7200 + 480, 7200 + 3840), 8000);
  EXPECT_NEAR(rising(s, 7200, 11520), 112, 2);
  EXPECT_EQ(peak(s, 11600, 28750), 0);
  EXPECT_GT(peak(s, 28800 + 480, 28800 + 3840), 8000);  // the next pair, 600 ms on
}

TEST(WarningTone, StartsWithABeepEachTimeItIsSwitchedOn) {
  WarningTone t(kRate);
  t.set(Alarm::kWarning);
  std::vector<std::int16_t> s(9000);
  t.fill(s);  // into the first gap
  t.set(Alarm::kOff);
  t.fill(s);
  t.set(Alarm::kWarning);
  t.fill(s);
  EXPECT_GT(peak(s, 480, 6720), 8000);
  // Going from warning to critical keeps the pattern's clock: no click, no restart.
  t.set(Alarm::kCritical);
  EXPECT_EQ(t.alarm(), Alarm::kCritical);
}

}  // namespace
}  // namespace tb::client::v2x
