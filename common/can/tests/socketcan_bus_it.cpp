// SocketCanBus on a real vcan interface: delivery at arrival, and on demand (the descriptor out
// of every epoll set, frames waiting in the socket until poll() or the backstop, none lost).
// This machine's kernel has no CAN: every test skips here and runs in the VM stage
// (tests/vm/guest/test.sh, check can.socketcan_bus_it).
//
// Each test makes its own anonymous network namespace (unshare on the test's thread) with a
// vcan0 in it: nothing is named, so nothing is left behind when a run is killed.

#include <sched.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <boost/asio/io_context.hpp>

#include "common/can/dbc.hpp"
#include "common/can/socketcan_bus.hpp"
#include "common/test_support/epoll_watch.hpp"

namespace tb::can {
namespace {

std::int64_t now_unix_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

using test_support::epoll_watched_descriptors;

/// A sender and a receiver on vcan0 of a namespace of their own. CAN_RAW loops a frame sent on
/// vcan back to every other socket on the interface, so the receiver sees what the sender sends.
///
/// The loop-back is not done when send() returns: vcan hands the frame to the kernel's backlog,
/// which a loaded machine works off later, in ksoftirqd. A test that needs frames queued at the
/// receiver before it reads waits for them at a probe socket. The probe is bound before the
/// receiver, and af_can hands each frame to the sockets bound later first (its receiver lists
/// add at the head), so once the probe holds a frame the receiver holds it too.
class VcanPair : public ::testing::Test {
 protected:
  void SetUp() override {
    if (::geteuid() != 0)
      GTEST_SKIP() << "needs root (a network namespace, a vcan interface)";
    if (!socketcan_available())
      GTEST_SKIP() << "this kernel has no SocketCAN (runs in the VM stage, tests/vm)";
    std::string failure;
    // setns/unshare change only the calling thread: a short-lived thread makes the namespace and
    // opens both sockets in it; the sockets keep the namespace (and vcan0) alive.
    std::thread([&] {
      if (::unshare(CLONE_NEWNET) != 0) {
        failure = std::string("unshare(CLONE_NEWNET): ") + std::strerror(errno);
        return;
      }
      // std::system forks from this thread, so ip runs in the new namespace.
      if (std::system("ip link add vcan0 type vcan && ip link set vcan0 up") != 0) {
        failure = "ip link add vcan0 type vcan failed (modprobe vcan?)";
        return;
      }
      auto p = SocketCanBus::open(io, "vcan0");
      auto t = SocketCanBus::open(io, "vcan0");
      auto r = SocketCanBus::open(io, "vcan0");
      if (!p || !t || !r) {
        failure = "SocketCanBus::open: " + (!p ? p.error() : !t ? t.error() : r.error()).message();
        return;
      }
      probe = std::move(*p);
      tx = std::move(*t);
      rx = std::move(*r);
    }).join();
    ASSERT_TRUE(failure.empty()) << failure;
    probe->start_receive([this](const CanFrame&, std::int64_t) { ++probed_; });
  }

  /// Runs the io_context until the probe has seen @p n frames since the test began: then the
  /// receiver's socket holds them too (see the class comment).
  void wait_until_looped_back(std::size_t n) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (probed_ < n && std::chrono::steady_clock::now() < deadline)
      io.run_for(std::chrono::milliseconds(1));
    ASSERT_EQ(probed_, n) << "frames looped back by vcan0 within 5 s";
  }

  /// @p n frames of vehicle.dbc's VehicleSpeed, AliveCounter 0, 1, ... (mod 16) and the frame's
  /// index in the speed signal, so that order and gaps can be read back from the frames alone.
  std::vector<CanFrame> counted_frames(int n, int first = 0) {
    std::vector<CanFrame> frames;
    for (int i = first; i < first + n; ++i) {
      CanFrame f;
      f.can_id = speed_->id;
      f.len = static_cast<std::uint8_t>(speed_->dlc);
      counter_->encode(i % 16, f.payload());
      index_->encode(i, f.payload());
      frames.push_back(f);
    }
    return frames;
  }
  int counter_of(const CanFrame& f) const {
    return static_cast<int>(counter_->decode(f.payload()));
  }

  /// Sends @p frames, a frame at a time (each a separate skb, as a real feeder's).
  void send(const std::vector<CanFrame>& frames) {
    for (const CanFrame& f : frames)
      ASSERT_FALSE(tx->send(std::span<const CanFrame>(&f, 1)));
  }

  boost::asio::io_context io;
  std::unique_ptr<SocketCanBus> probe, tx, rx;
  std::size_t probed_ = 0;
  Database dbc = *Database::load(TESTBED_VEHICLE_DBC);
  const Message* speed_ = dbc.find_message("VehicleSpeed");
  const Signal* counter_ = speed_->find_signal("AliveCounter");
  const Signal* index_ = speed_->find_signal("VehicleSpeed");  // 16 bits: the frame's index
};

TEST_F(VcanPair, DeliversAtArrivalWithTheKernelsReceiveTime) {
  std::vector<CanFrame> got;
  std::vector<std::int64_t> stamps;
  rx->start_receive([&](const CanFrame& f, std::int64_t ts) {
    got.push_back(f);
    stamps.push_back(ts);
  });
  const auto frames = counted_frames(5);
  const std::int64_t before = now_unix_ns();
  send(frames);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (got.size() < frames.size() && std::chrono::steady_clock::now() < deadline)
    io.run_for(std::chrono::milliseconds(5));
  const std::int64_t after = now_unix_ns();
  EXPECT_EQ(got, frames);
  for (const std::int64_t ts : stamps) {
    EXPECT_GE(ts, before);
    EXPECT_LE(ts, after);
  }
}

TEST_F(VcanPair, OnDemandLeavesTheEpollSetSoThatFramesWakeNobody) {
  const std::size_t watched = epoll_watched_descriptors();
  ASSERT_GE(watched, 1u);
  std::vector<CanFrame> got;
  rx->start_on_demand([&](const CanFrame& f, std::int64_t) { got.push_back(f); },
                      std::chrono::hours{1});
  EXPECT_EQ(epoll_watched_descriptors(), watched - 1);
  const auto frames = counted_frames(3);
  send(frames);
  wait_until_looped_back(3);
  io.run_for(std::chrono::milliseconds(100));
  EXPECT_TRUE(got.empty()) << "no read before poll()";
  EXPECT_EQ(rx->poll(), 3u);
  EXPECT_EQ(got, frames);
  // The sender still sends through its own descriptor, and the released one reads on.
  send(counted_frames(2, 3));
  wait_until_looped_back(5);
  EXPECT_EQ(rx->poll(), 2u);
}

TEST_F(VcanPair, OnePollReadsMoreFramesThanOneBatchInOrder) {
  std::vector<CanFrame> got;
  rx->start_on_demand([&](const CanFrame& f, std::int64_t) { got.push_back(f); },
                      std::chrono::hours{1});
  const auto frames = counted_frames(3 * static_cast<int>(SocketCanBus::kReadBatch) + 5);
  send(frames);
  wait_until_looped_back(frames.size());
  EXPECT_EQ(rx->poll(), frames.size());
  EXPECT_EQ(got, frames);
  // Four system calls for 53 frames: three full batches and a short one that ends the read.
  EXPECT_EQ(rx->stats().reads, 4u);
  EXPECT_EQ(rx->poll(), 0u);
}

TEST_F(VcanPair, TheBackstopReadsWhenNobodyPolls) {
  std::vector<CanFrame> got;
  rx->start_on_demand([&](const CanFrame& f, std::int64_t) { got.push_back(f); },
                      std::chrono::milliseconds{20});
  const auto frames = counted_frames(3);
  send(frames);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (got.size() < frames.size() && std::chrono::steady_clock::now() < deadline)
    io.run_for(std::chrono::milliseconds(5));
  EXPECT_EQ(got, frames);
}

TEST_F(VcanPair, AliveCountersSeeNoGapAcrossPollsAndTheBackstop) {
  // A stream at the vehicle's pace read now by poll(), now by the backstop: every frame
  // arrives once, in order, its AliveCounter one more (mod 16) than the one before.
  std::vector<CanFrame> got;
  rx->start_on_demand([&](const CanFrame& f, std::int64_t) { got.push_back(f); },
                      std::chrono::milliseconds{15});
  constexpr int kFrames = 400;
  for (int i = 0; i < kFrames; i += 8) {
    send(counted_frames(8, i));
    io.run_for(std::chrono::milliseconds(2));  // the backstop fires now and then
    if ((i / 8) % 3 == 0)
      rx->poll();
  }
  // The last frames may still be on their way through the kernel's backlog (softirq).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  rx->poll();
  while (got.size() < kFrames && std::chrono::steady_clock::now() < deadline) {
    io.run_for(std::chrono::milliseconds(1));
    rx->poll();
  }
  ASSERT_EQ(got.size(), static_cast<std::size_t>(kFrames));
  for (std::size_t i = 1; i < got.size(); ++i)
    ASSERT_EQ(counter_of(got[i]), (counter_of(got[i - 1]) + 1) % 16) << "gap before frame " << i;
  EXPECT_EQ(got, counted_frames(kFrames));
  EXPECT_EQ(rx->dropped_by_kernel(), 0u);
  EXPECT_EQ(rx->stats().unexpected_size, 0u);
}

}  // namespace
}  // namespace tb::can
