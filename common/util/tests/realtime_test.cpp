#include "common/util/realtime.hpp"

#include <gtest/gtest.h>
#include <sched.h>

#include <thread>

namespace {

TEST(Realtime, APriorityOutsideTheKernelsRangeIsRefusedNamingIt) {
  for (int bad : {0, -1, 100}) {
    const auto r = tb::run_at_realtime_priority(bad);
    ASSERT_FALSE(r.has_value());
    EXPECT_NE(r.error().find("priority " + std::to_string(bad) + " is not in 1..99"),
              std::string::npos)
        << r.error();
  }
  EXPECT_EQ(tb::current_scheduling().policy, "SCHED_OTHER");
}

// On its own thread, so that the test runner's thread keeps its normal priority.
TEST(Realtime, TheThreadRunsSchedFifoAtThePriorityOrTheRefusalSaysWhatIsMissing) {
  std::string outcome;
  tb::SchedulingReport after;
  std::thread t([&] {
    const auto r = tb::run_at_realtime_priority(7);
    if (!r) {
      outcome = r.error();
      return;
    }
    after = tb::current_scheduling();
  });
  t.join();
  if (!outcome.empty()) {
    // Without CAP_SYS_NICE or a real-time budget (a container): the refusal names both.
    EXPECT_NE(outcome.find("SCHED_FIFO at priority 7"), std::string::npos) << outcome;
    if (outcome.find("Operation not permitted") != std::string::npos) {
      EXPECT_NE(outcome.find("CAP_SYS_NICE"), std::string::npos) << outcome;
    }
    GTEST_SKIP() << "not permitted here: " << outcome;
  }
  EXPECT_EQ(after.policy, "SCHED_FIFO");
  EXPECT_EQ(after.priority, 7);
  // Only that thread changed.
  EXPECT_EQ(tb::current_scheduling().policy, "SCHED_OTHER");
}

}  // namespace
