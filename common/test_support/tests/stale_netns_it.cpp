// remove_stale_netns on real namespaces: one named as a dead process's is removed, one named as
// this (live) process's is kept, one of another scheme is kept.

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "common/test_support/stale_netns.hpp"

namespace tb::test_support {
namespace {

bool exists(const std::string& ns) {
  return std::filesystem::exists("/run/netns/" + ns);
}
int sh(const std::string& cmd) {
  return std::system((cmd + " >/dev/null 2>&1").c_str());
}

/// The pid of a child that has exited and been reaped: no process has it (until the kernel
/// hands it out again, which takes a wrap of pid_max).
pid_t dead_pid() {
  const pid_t child = ::fork();
  if (child == 0)
    ::_exit(0);
  ::waitpid(child, nullptr, 0);
  return child;
}

TEST(RemoveStaleNetns, RemovesADeadRunsNamespaceAndKeepsALiveOne) {
  if (::geteuid() != 0)
    GTEST_SKIP() << "needs root to create network namespaces";
  const pid_t dead = dead_pid();
  ASSERT_FALSE(process_alive(dead));
  const std::string stale = "tbsweep" + std::to_string(dead);
  const std::string live = "tbsweep" + std::to_string(::getpid());
  const std::string other = "tbsweepx" + std::to_string(dead);
  for (const auto& ns : {stale, live, other}) {
    sh("ip netns del " + ns);
    ASSERT_EQ(sh("ip netns add " + ns), 0) << ns;
  }

  const auto removed = remove_stale_netns({"tbsweep"});

  EXPECT_NE(std::find(removed.begin(), removed.end(), stale), removed.end());
  EXPECT_FALSE(exists(stale));
  EXPECT_TRUE(exists(live)) << "a live process's namespace was removed";
  EXPECT_TRUE(exists(other)) << "another scheme's namespace was removed";
  EXPECT_EQ(std::find(removed.begin(), removed.end(), live), removed.end());
  sh("ip netns del " + live);
  sh("ip netns del " + other);
}

}  // namespace
}  // namespace tb::test_support
