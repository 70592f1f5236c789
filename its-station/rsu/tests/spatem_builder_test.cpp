// SPATEMs from signal states: times as TimeMarks of the UTC instants given, graded by turning
// them back into instants; the hour boundary; the special values.

#include "its-station/rsu/spatem_builder.hpp"

#include <gtest/gtest.h>

#include <cstdint>

namespace tb::its::rsu {
namespace {

namespace msg = messages;
using wire::sim::MovementPhaseState;

// 2026-11-27 11:40:12.345 UTC.
constexpr std::int64_t kNow = 1'795'779'612'345;

wire::sim::SignalStates states(std::int64_t now, MovementPhaseState s1, std::int64_t end1,
                               MovementPhaseState s2, std::int64_t end2) {
  wire::sim::SignalStates st;
  st.world_time_ms = now;
  st.groups.push_back({100, 1, s1, end1, end1});
  st.groups.push_back({100, 2, s2, end2, end2});
  st.groups.push_back({200, 1, MovementPhaseState::kDark, 0, 0});  // another junction's
  return st;
}

TEST(SpatemBuilder, StatesAndTimesOfOneIntersection) {
  SpatemBuilder b(100);
  const auto bytes = b.build(states(kNow, MovementPhaseState::kStopAndRemain, kNow + 7'250,
                                    MovementPhaseState::kProtectedMovementAllowed, kNow + 2'000),
                             kNow);
  ASSERT_TRUE(bytes.has_value());
  const auto spatem = msg::decode_spatem(*bytes);
  ASSERT_TRUE(spatem.has_value());
  EXPECT_EQ(spatem->header.messageID, msg::kMessageIdSpatem);
  ASSERT_EQ(spatem->spat.intersections.size(), 1u);
  const msg::IntersectionState& is = spatem->spat.intersections[0];
  EXPECT_EQ(is.id.id, 100);
  EXPECT_TRUE(is.status & msg::intersection_status::kFixedTimeOperation);
  // moy + timeStamp: 2026-11-27 is day 330 of the year (0-based), 11:40 → minute 475'900.
  ASSERT_TRUE(is.moy.has_value());
  EXPECT_EQ(*is.moy, 330u * 1440u + 11u * 60u + 40u);
  EXPECT_EQ(is.timeStamp, 12'345);
  ASSERT_EQ(is.states.size(), 2u);  // junction 200's group is not ours
  EXPECT_EQ(is.states[0].signalGroup, 1);
  EXPECT_EQ(is.states[0].state_time_speed[0].eventState, msg::MovementPhaseState::stop_And_Remain);
  EXPECT_EQ(is.states[1].state_time_speed[0].eventState,
            msg::MovementPhaseState::protected_Movement_Allowed);
  // Back to instants, as a receiver does: within the TimeMark's 100 ms of what was fed.
  const auto& t1 = *is.states[0].state_time_speed[0].timing;
  const std::int64_t end1 = msg::utc_ms_from_time_mark(t1.minEndTime, kNow);
  EXPECT_LE(kNow + 7'250 - end1, 100);
  EXPECT_GE(kNow + 7'250 - end1, 0);
  ASSERT_TRUE(t1.likelyTime.has_value());
  EXPECT_LE(kNow + 7'250 - msg::utc_ms_from_time_mark(*t1.likelyTime, kNow), 100);
  const auto& t2 = *is.states[1].state_time_speed[0].timing;
  EXPECT_LE(std::llabs(kNow + 2'000 - msg::utc_ms_from_time_mark(t2.minEndTime, kNow)), 100);
}

TEST(SpatemBuilder, EndPastTheHourWrapsIntoTheNextHour) {
  // 11:59:58.000; red ends at 12:00:03.500 (next hour), green at 11:59:59.900.
  const std::int64_t now = kNow - (kNow % 3'600'000) + 3'598'000;
  SpatemBuilder b(100);
  const auto bytes = b.build(states(now, MovementPhaseState::kStopAndRemain, now + 5'500,
                                    MovementPhaseState::kProtectedClearance, now + 1'900),
                             now);
  ASSERT_TRUE(bytes.has_value());
  const auto& is = b.last().spat.intersections[0];
  EXPECT_EQ(is.states[0].state_time_speed[0].timing->minEndTime, 35);  // 3.5 s into the hour
  EXPECT_EQ(is.states[1].state_time_speed[0].timing->minEndTime, 35'999);
  EXPECT_EQ(msg::utc_ms_from_time_mark(35, now), now + 5'500);
  EXPECT_EQ(*is.timeStamp, 58'000);
}

TEST(SpatemBuilder, SpecialValues) {
  const std::int64_t now = kNow;
  // No change planned (0) is unknown; an end an hour or more ahead is 36000.
  EXPECT_EQ(time_mark(0, now), msg::kTimeMarkUnknown);
  EXPECT_EQ(time_mark(now + 3'600'000, now), 36'000);
  EXPECT_EQ(time_mark(now + 3'599'900, now), msg::time_mark_from_utc_ms(now + 3'599'900));
  SpatemBuilder b(100);
  wire::sim::SignalStates st = states(now, MovementPhaseState::kDark, 0,
                                      MovementPhaseState::kStopAndRemain, now + 4'000'000);
  st.groups[0].likely_change_ms = 0;
  ASSERT_TRUE(b.build(st, now).has_value());
  const auto& is = b.last().spat.intersections[0];
  EXPECT_EQ(is.states[0].state_time_speed[0].timing->minEndTime, msg::kTimeMarkUnknown);
  EXPECT_FALSE(is.states[0].state_time_speed[0].timing->likelyTime.has_value());
  EXPECT_EQ(is.states[1].state_time_speed[0].timing->minEndTime, 36'000);
  // No group of ours: nothing to send.
  EXPECT_FALSE(SpatemBuilder(300).build(st, now).has_value());
}

TEST(SpatemBuilder, RevisionCountsStateChanges) {
  SpatemBuilder b(100);
  const auto red = states(kNow, MovementPhaseState::kStopAndRemain, kNow + 5'000,
                          MovementPhaseState::kProtectedMovementAllowed, kNow + 3'000);
  ASSERT_TRUE(b.build(red, kNow).has_value());
  const msg::MsgCount r0 = b.last().spat.intersections[0].revision;
  ASSERT_TRUE(b.build(red, kNow + 100).has_value());  // times move, states stay
  EXPECT_EQ(b.last().spat.intersections[0].revision, r0);
  auto amber = red;
  amber.groups[1].state = MovementPhaseState::kProtectedClearance;
  EXPECT_FALSE(same_states(red, amber));
  EXPECT_TRUE(same_states(red, red));
  ASSERT_TRUE(b.build(amber, kNow + 200).has_value());
  EXPECT_EQ(b.last().spat.intersections[0].revision, (r0 + 1) % 128);
}

}  // namespace
}  // namespace tb::its::rsu
