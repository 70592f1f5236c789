// CAN over UDP between real sockets: on loopback, and to a reader in another network
// namespace over a veth pair (the stand-in path between emulator and station).

#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <boost/asio/io_context.hpp>

#include "common/can/netns.hpp"
#include "common/can/udp_can_bus.hpp"
#include "common/test_support/epoll_watch.hpp"
#include "common/test_support/stale_netns.hpp"

namespace tb::can {
namespace {

using udp = boost::asio::ip::udp;

std::vector<CanFrame> sample_frames(int n) {
  std::vector<CanFrame> frames;
  for (int i = 0; i < n; ++i) {
    const std::uint8_t data[] = {static_cast<std::uint8_t>(i), 0xAB, 0xCD};
    frames.push_back(make_frame(0x100 + static_cast<std::uint32_t>(i), data));
  }
  return frames;
}

/// Runs @p io until @p done or 5 s pass.
template <typename Pred>
void run_until(boost::asio::io_context& io, Pred done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!done() && std::chrono::steady_clock::now() < deadline) {
    io.restart();
    io.run_for(std::chrono::milliseconds(20));
  }
}

TEST(UdpCanBus, DeliversFramesOnLoopbackAndSplitsLargeBatches) {
  boost::asio::io_context io;
  auto rx = UdpCanBus::bind(io, {boost::asio::ip::make_address("127.0.0.1"), 0});
  std::vector<CanFrame> got;
  rx->start_receive([&](const CanFrame& f, std::int64_t ts) {
    EXPECT_GT(ts, 0);
    got.push_back(f);
  });
  auto tx = UdpCanBus::connect(io, rx->local_endpoint());
  // 200 frames of 8 + 3 bytes do not fit in one 1400-byte datagram.
  const auto frames = sample_frames(200);
  ASSERT_FALSE(tx->send(frames));
  run_until(io, [&] { return got.size() >= frames.size(); });
  ASSERT_EQ(got.size(), frames.size());
  EXPECT_EQ(got, frames);
  EXPECT_GE(rx->stats().packets, 2u);
  EXPECT_EQ(rx->stats().sequence_gaps, 0u);
}

TEST(UdpCanBus, OnDemandHoldsFramesUntilPolledOrTheBackstop) {
  boost::asio::io_context io;
  auto rx = UdpCanBus::bind(io, {boost::asio::ip::make_address("127.0.0.1"), 0});
  std::vector<CanFrame> got;
  rx->start_on_demand([&](const CanFrame& f, std::int64_t) { got.push_back(f); },
                      std::chrono::hours{1});
  auto tx = UdpCanBus::connect(io, rx->local_endpoint());
  const auto frames = sample_frames(200);  // two datagrams
  ASSERT_FALSE(tx->send(frames));
  io.run_for(std::chrono::milliseconds(100));
  EXPECT_TRUE(got.empty()) << "no read before poll()";
  EXPECT_EQ(rx->poll(), rx->stats().packets);
  EXPECT_GE(rx->stats().packets, 2u);
  EXPECT_EQ(got, frames);
  EXPECT_EQ(rx->poll(), 0u);

  // Nobody polls: the backstop reads.
  auto rx2 = UdpCanBus::bind(io, {boost::asio::ip::make_address("127.0.0.1"), 0});
  std::vector<CanFrame> got2;
  rx2->start_on_demand([&](const CanFrame& f, std::int64_t) { got2.push_back(f); },
                       std::chrono::milliseconds{20});
  auto tx2 = UdpCanBus::connect(io, rx2->local_endpoint());
  ASSERT_FALSE(tx2->send(sample_frames(3)));
  run_until(io, [&] { return got2.size() >= 3; });
  EXPECT_EQ(got2, sample_frames(3));
}

TEST(UdpCanBus, OnePollReadsMoreDatagramsThanOneBatchInOrder) {
  // poll() reads in batches (recvmmsg): a queue longer than a batch is read to its end, in
  // order; a datagram longer than a batch slot is counted as malformed, not decoded cut.
  boost::asio::io_context io;
  auto rx = UdpCanBus::bind(io, {boost::asio::ip::make_address("127.0.0.1"), 0});
  std::vector<CanFrame> got;
  rx->start_on_demand([&](const CanFrame& f, std::int64_t) { got.push_back(f); },
                      std::chrono::hours{1});
  auto tx = UdpCanBus::connect(io, rx->local_endpoint());
  udp::socket raw(io, udp::v4());
  const auto frames = sample_frames(40);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    ASSERT_FALSE(tx->send(std::span<const CanFrame>(&frames[i], 1)));
    if (i == 20) {
      const std::vector<std::uint8_t> huge(5000, 0x02);
      raw.send_to(boost::asio::buffer(huge), rx->local_endpoint());
    }
  }
  EXPECT_EQ(rx->poll(), 40u);
  EXPECT_EQ(got, frames);
  EXPECT_EQ(rx->stats().packets, 40u);
  EXPECT_EQ(rx->stats().sequence_gaps, 0u);
  EXPECT_EQ(rx->stats().malformed, 1u);
  EXPECT_EQ(rx->poll(), 0u);
}

using test_support::epoll_watched_descriptors;

TEST(UdpCanBus, OnDemandLeavesTheEpollSetSoThatDatagramsWakeNobody) {
  // Registered with the io_context's epoll, every datagram would wake the thread that runs it
  // although nobody waits on the socket (issue 33).
  boost::asio::io_context io;
  auto rx = UdpCanBus::bind(io, {boost::asio::ip::make_address("127.0.0.1"), 0});
  const std::size_t watched = epoll_watched_descriptors();
  ASSERT_GE(watched, 1u);
  std::vector<CanFrame> got;
  rx->start_on_demand([&](const CanFrame& f, std::int64_t) { got.push_back(f); },
                      std::chrono::hours{1});
  EXPECT_EQ(epoll_watched_descriptors(), watched - 1);
  auto tx = UdpCanBus::connect(io, rx->local_endpoint());
  ASSERT_FALSE(tx->send(sample_frames(3)));
  EXPECT_EQ(rx->poll(), 1u);
  EXPECT_EQ(got, sample_frames(3));
}

TEST(UdpCanBus, CountsMalformedPacketsAndKeepsReceiving) {
  boost::asio::io_context io;
  auto rx = UdpCanBus::bind(io, {boost::asio::ip::make_address("127.0.0.1"), 0});
  int frames = 0;
  rx->start_receive([&](const CanFrame&, std::int64_t) { ++frames; });
  udp::socket raw(io, udp::v4());
  const std::uint8_t junk[] = {0x09, 0x00, 0x00, 0x00, 0x00};
  raw.send_to(boost::asio::buffer(junk), rx->local_endpoint());
  auto tx = UdpCanBus::connect(io, rx->local_endpoint());
  ASSERT_FALSE(tx->send(sample_frames(1)));
  run_until(io, [&] { return frames == 1 && rx->stats().malformed == 1; });
  EXPECT_EQ(frames, 1);
  EXPECT_EQ(rx->stats().malformed, 1u);
  ASSERT_TRUE(rx->stats().last_error.has_value());
  EXPECT_EQ(*rx->stats().last_error, CannelloniError::kUnsupportedVersion);
}

TEST(UdpCanBus, ReportsAnAbsentReceiverAsConnectionRefused) {
  boost::asio::io_context io;
  udp::endpoint closed;
  {
    udp::socket probe(io, udp::endpoint(boost::asio::ip::make_address("127.0.0.1"), 0));
    closed = probe.local_endpoint();
  }  // closed again: nobody listens there now
  auto tx = UdpCanBus::connect(io, closed);
  std::error_code ec;
  for (int i = 0; i < 3 && !ec; ++i)
    ec = tx->send(sample_frames(1));
  EXPECT_EQ(ec, std::errc::connection_refused) << ec.message();
}

/// A network namespace with a veth pair to the host, removed again in the destructor (and by
/// the next run when this one is killed first: the name carries the whole pid for that).
class VethNamespace {
 public:
  VethNamespace() {
    test_support::remove_stale_netns({"emucan"});
    const int id = static_cast<int>(::getpid());
    ns_ = fmt::format("emucan{}", id);
    host_if_ = fmt::format("emuc{}a", id);
    const std::string ns_if = fmt::format("emuc{}b", id);
    const int subnet = id % 250;
    host_addr_ = fmt::format("10.213.{}.1", subnet);
    ns_addr_ = fmt::format("10.213.{}.2", subnet);
    cleanup();
    ok_ = sh("ip netns add " + ns_) &&
          sh(fmt::format("ip link add {} type veth peer name {}", host_if_, ns_if)) &&
          sh(fmt::format("ip link set {} netns {}", ns_if, ns_)) &&
          sh(fmt::format("ip addr add {}/24 dev {}", host_addr_, host_if_)) &&
          sh(fmt::format("ip link set {} up", host_if_)) &&
          sh(fmt::format("ip -n {} addr add {}/24 dev {}", ns_, ns_addr_, ns_if)) &&
          sh(fmt::format("ip -n {} link set {} up", ns_, ns_if)) &&
          sh(fmt::format("ip -n {} link set lo up", ns_));
  }
  ~VethNamespace() { cleanup(); }
  bool ok() const { return ok_; }
  const std::string& name() const { return ns_; }
  const std::string& ns_addr() const { return ns_addr_; }

 private:
  static bool sh(const std::string& cmd) {
    return std::system((cmd + " 2>/dev/null").c_str()) == 0;
  }
  void cleanup() {
    sh("ip link del " + host_if_);
    sh("ip netns del " + ns_);
  }
  std::string ns_, host_if_, host_addr_, ns_addr_;
  bool ok_ = false;
};

TEST(UdpCanBus, ReachesAReaderInAnotherNetworkNamespace) {
  if (::geteuid() != 0)
    GTEST_SKIP() << "needs root to create a network namespace";
  VethNamespace ns;
  ASSERT_TRUE(ns.ok()) << "could not set up namespace " << ns.name();

  boost::asio::io_context io;
  std::unique_ptr<UdpCanBus> rx;
  // The reader's socket lives in the station's namespace, bound to its veth address.
  const std::error_code ec = run_in_netns(ns.name(), [&] {
    rx = UdpCanBus::bind(io, {boost::asio::ip::make_address(ns.ns_addr()), kCannelloniDefaultPort});
  });
  ASSERT_FALSE(ec) << ec.message();
  std::vector<CanFrame> got;
  rx->start_receive([&](const CanFrame& f, std::int64_t) { got.push_back(f); });

  auto tx =
      UdpCanBus::connect(io, {boost::asio::ip::make_address(ns.ns_addr()), kCannelloniDefaultPort});
  const auto frames = sample_frames(5);
  run_until(io, [&] {
    if (got.empty())
      (void)tx->send(frames);  // the veth may need a moment (ARP) before the first datagram
    return !got.empty();
  });
  ASSERT_GE(got.size(), frames.size());
  EXPECT_EQ(std::vector<CanFrame>(got.begin(), got.begin() + 5), frames);
}

TEST(Netns, ReportsAMissingNamespace) {
  bool ran = false;
  const std::error_code ec = run_in_netns("emucan-does-not-exist", [&] { ran = true; });
  EXPECT_EQ(ec, std::errc::no_such_file_or_directory);
  EXPECT_FALSE(ran);
}

}  // namespace
}  // namespace tb::can
