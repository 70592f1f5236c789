// Which names are stale: the pid after the prefix, and whether that process is alive (injected).

#include <sys/wait.h>
#include <unistd.h>

#include <set>

#include <gtest/gtest.h>

#include "common/test_support/stale_netns.hpp"

namespace tb::test_support {
namespace {

TEST(CreatorPid, IsTheDigitsRightAfterThePrefix) {
  EXPECT_EQ(creator_pid("gnA4242", "gnA"), 4242);
  EXPECT_EQ(creator_pid("tbfs4242-11", "tbfs"), 4242);
  EXPECT_EQ(creator_pid("tbrit4242a", "tbrit"), 4242);
  EXPECT_EQ(creator_pid("gnB4242", "gnA"), std::nullopt);
  EXPECT_EQ(creator_pid("gnA", "gnA"), std::nullopt);
  EXPECT_EQ(creator_pid("gnAx4242", "gnA"), std::nullopt);
  EXPECT_EQ(creator_pid("gnA-4242", "gnA"), std::nullopt);
  EXPECT_EQ(creator_pid("gnA0", "gnA"), std::nullopt);
  // Longer than any pid: not a name of ours.
  EXPECT_EQ(creator_pid("gnA99999999999999999999", "gnA"), std::nullopt);
  // Another scheme whose prefix extends ours by a letter is not ours.
  EXPECT_EQ(creator_pid("tbfba4242", "tbfb"), std::nullopt);
}

TEST(StaleNames, AreOursAndOfProcessesThatAreGone) {
  const std::set<pid_t> living{100, 200};
  const auto alive = [&](pid_t p) { return living.contains(p); };
  const std::vector<std::string> names{"gnA100",    "gnA101", "gnB101", "gnB200",
                                       "tbst-1001", "gnC101", "facA101"};
  const auto stale = stale_names(names, {"gnA", "gnB"}, alive);
  EXPECT_EQ(stale, (std::vector<StaleNetns>{{"gnA101", 101}, {"gnB101", 101}}));
  EXPECT_TRUE(stale_names(names, {}, alive).empty());
}

TEST(ProcessAlive, KnowsThisProcessAndAnExitedChild) {
  EXPECT_TRUE(process_alive(::getpid()));
  EXPECT_TRUE(process_alive(1));  // init: EPERM for a non-root caller still means alive
  const pid_t child = ::fork();
  if (child == 0)
    ::_exit(0);
  ASSERT_GT(child, 0);
  ::waitpid(child, nullptr, 0);
  EXPECT_FALSE(process_alive(child));
}

}  // namespace
}  // namespace tb::test_support
