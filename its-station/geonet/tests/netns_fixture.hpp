#pragma once
// Two network namespaces joined by a veth pair whose ends are both named wlan0, as the radio
// stand-in gives each station. Names carry the test process's pid, so parallel tests do not
// collide; TearDown deletes the namespaces (and with them the veth pair) even after a failure,
// and SetUp first removes those of runs killed before their TearDown.

#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <string>

#include <boost/asio/io_context.hpp>

#include "common/test_support/stale_netns.hpp"
#include "its-station/link/packet_socket_link.hpp"

namespace tb::its::testing {

using namespace std::chrono_literals;

int run(const std::string& cmd) {
  return std::system((cmd + " >/dev/null 2>&1").c_str());
}

class Netns {
 public:
  explicit Netns(std::string name) : name_(std::move(name)) {}
  const std::string& name() const { return name_; }
  /// Runs @p fn with this thread in the namespace.
  void enter(const std::function<void()>& fn) const {
    const int self = ::open("/proc/self/ns/net", O_RDONLY | O_CLOEXEC);
    const int target = ::open(("/run/netns/" + name_).c_str(), O_RDONLY | O_CLOEXEC);
    ASSERT_GE(self, 0);
    ASSERT_GE(target, 0) << "no namespace " << name_;
    ASSERT_EQ(::setns(target, CLONE_NEWNET), 0) << std::strerror(errno);
    fn();
    EXPECT_EQ(::setns(self, CLONE_NEWNET), 0);
    ::close(target);
    ::close(self);
  }

 private:
  std::string name_;
};

class VethPair : public ::testing::Test {
 public:
  void SetUp() override {
    if (::geteuid() != 0)
      GTEST_SKIP() << "needs root to create network namespaces";
    test_support::remove_stale_netns({"gnA", "gnB"});
    const std::string id = std::to_string(::getpid());
    a_ = std::make_unique<Netns>("gnA" + id);
    b_ = std::make_unique<Netns>("gnB" + id);
    cleanup();
    ASSERT_EQ(run("ip netns add " + a_->name()), 0);
    ASSERT_EQ(run("ip netns add " + b_->name()), 0);
    ASSERT_EQ(run("ip link add gna" + id + " type veth peer name gnb" + id), 0);
    ASSERT_EQ(run("ip link set gna" + id + " netns " + a_->name()), 0);
    ASSERT_EQ(run("ip link set gnb" + id + " netns " + b_->name()), 0);
    ASSERT_EQ(run("ip -n " + a_->name() + " link set gna" + id + " name wlan0 up"), 0);
    ASSERT_EQ(run("ip -n " + b_->name() + " link set gnb" + id + " name wlan0 up"), 0);
  }
  void TearDown() override { cleanup(); }
  void cleanup() {
    // Deleting a namespace destroys the veth end inside it, and with it the pair.
    if (a_)
      run("ip netns del " + a_->name());
    if (b_)
      run("ip netns del " + b_->name());
  }
  std::unique_ptr<link::PacketSocketLink> open_in(const Netns& ns) {
    std::unique_ptr<link::PacketSocketLink> out;
    ns.enter([&] {
      auto l = link::PacketSocketLink::open(io, "wlan0");
      ASSERT_TRUE(l) << l.error().message();
      out = std::move(*l);
    });
    return out;
  }
  /// Runs the io_context until @p done or 5 s pass.
  bool run_until(const std::function<bool()>& done) {
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (!done() && std::chrono::steady_clock::now() < deadline)
      io.run_for(5ms);
    return done();
  }

  std::unique_ptr<Netns> a_, b_;
  boost::asio::io_context io;
};

}  // namespace tb::its::testing
