#pragma once
// Helpers of the radio-medium integration tests and benchmarks that run the real program:
// named namespaces, the program as a child process, a station's wlan0 end. Runs as root.

#include <arpa/inet.h>
#include <fcntl.h>
#include <net/if.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "common/test_support/stale_netns.hpp"
#include "common/wire/pooled_delivery.hpp"
#include "network-emulator/radio/netns.hpp"
#include "network-emulator/radio/packet_socket.hpp"
#include "network-emulator/radio/veth_radios.hpp"

namespace tb::emu::radio {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

const std::string kTag = std::to_string(::getpid());
// Unique per test process (ctest may run them in parallel): "t" + the pid in base 36, within
// the 5 characters --prefix allows.
std::string pid_prefix() {
  std::string p = "t";
  unsigned v = static_cast<unsigned>(::getpid()) % (36u * 36u * 36u * 36u);
  for (int i = 0; i < 4; ++i, v /= 36)
    p += "0123456789abcdefghijklmnopqrstuvwxyz"[v % 36];
  return p;
}
const std::string kPrefix = pid_prefix();

// A named namespace made with `ip netns add` (the launcher's job in real runs), always removed.
class TestNetns {
 public:
  explicit TestNetns(std::string name) : name_(std::move(name)) {
    std::system(("ip netns del " + name_ + " 2>/dev/null").c_str());
    if (std::system(("ip netns add " + name_).c_str()) != 0)
      throw std::runtime_error("ip netns add " + name_ + " failed (needs root)");
  }
  ~TestNetns() { std::system(("ip netns del " + name_ + " 2>/dev/null").c_str()); }
  // A new namespace under the same name, as a station container gets when it restarts; the old
  // one dies with everything in it.
  void replace() {
    if (std::system(("ip netns del " + name_ + " && ip netns add " + name_).c_str()) != 0)
      throw std::runtime_error("cannot make " + name_ + " again");
  }
  const std::string& name() const { return name_; }
  bool has(const std::string& ifname) const {
    return in_netns(NetnsFd::open(name_), [&] { return if_nametoindex(ifname.c_str()) != 0; });
  }

 private:
  std::string name_;
};

// radio-medium as a child process; waits for its "ready" line, SIGTERMs it at the end.
class MediumProcess {
 public:
  /// @p netns: run inside that named namespace (a node of the federation tests).
  explicit MediumProcess(const std::vector<std::string>& args, const std::string& netns = {}) {
    const char* bin = std::getenv("TESTBED_BIN");
    if (!bin)
      throw std::runtime_error("TESTBED_BIN is not set (run through ctest)");
    int out[2];
    if (::pipe2(out, O_CLOEXEC) != 0)
      throw std::runtime_error("pipe");
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(out[1], STDOUT_FILENO);
      if (!netns.empty()) {
        const int fd = ::open(("/run/netns/" + netns).c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0 || ::setns(fd, CLONE_NEWNET) != 0)
          ::_exit(126);
      }
      std::vector<std::string> all{std::string(bin) + "/radio-medium"};
      all.insert(all.end(), args.begin(), args.end());
      std::vector<char*> argv;
      for (auto& a : all)
        argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    ::close(out[1]);
    stdout_ = out[0];
  }
  ~MediumProcess() {
    if (pid_ > 0)
      stop();
    if (stdout_ >= 0)
      ::close(stdout_);
  }
  // True once the program said it is ready; false if it exited or took longer than 10 s.
  bool wait_ready() {
    const auto deadline = Clock::now() + 10s;
    while (Clock::now() < deadline) {
      pollfd p{stdout_, POLLIN, 0};
      if (::poll(&p, 1, 100) > 0) {
        char buf[256];
        const ssize_t n = ::read(stdout_, buf, sizeof buf);
        if (n <= 0)
          return false;
        seen_.append(buf, static_cast<std::size_t>(n));
        if (seen_.find("radio-medium: ready") != std::string::npos)
          return true;
      }
    }
    return false;
  }
  /// Everything the program wrote to stdout so far (its log, too: spdlog writes there).
  const std::string& output() {
    char buf[4096];
    for (pollfd p{stdout_, POLLIN, 0}; ::poll(&p, 1, 0) > 0;) {
      const ssize_t n = ::read(stdout_, buf, sizeof buf);
      if (n <= 0)
        break;
      seen_.append(buf, static_cast<std::size_t>(n));
    }
    return seen_;
  }
  void signal(int sig) { ::kill(pid_, sig); }
  bool running() const { return pid_ > 0; }
  // SIGTERM (or @p sig) and the exit status; SIGKILL after 10 s.
  int stop(int sig = SIGTERM) {
    ::kill(pid_, sig);
    int status = 0;
    const auto deadline = Clock::now() + 10s;
    while (::waitpid(pid_, &status, WNOHANG) == 0) {
      if (Clock::now() > deadline) {
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, &status, 0);
        break;
      }
      std::this_thread::sleep_for(5ms);
    }
    pid_ = -1;
    return status;
  }

 private:
  pid_t pid_ = -1;
  int stdout_ = -1;
  std::string seen_;
};

// A broadcast GeoNetworking-typed frame from station @p id's MAC carrying its id and @p seq
// (bytes 14–21, host order): what the test stations send and recognise.
inline std::vector<std::uint8_t> test_frame(StationId id, std::uint32_t seq) {
  std::vector<std::uint8_t> f(100, 0);
  std::fill_n(f.begin(), 6, 0xff);
  const MacAddress src = station_mac(id);
  std::copy(src.begin(), src.end(), f.begin() + 6);
  f[12] = 0x89;
  f[13] = 0x47;
  std::memcpy(&f[14], &id, 4);
  std::memcpy(&f[18], &seq, 4);
  return f;
}

// A station's end: AF_PACKET on wlan0 inside its namespace.
class Station {
 public:
  Station(StationId id, const std::string& netns) : id_(id) {
    socket_ = in_netns(NetnsFd::open(netns), [] {
      return std::make_unique<PacketSocket>(kStationIfname, kEthertypeGeoNetworking, 16 << 20);
    });
  }
  void send(std::uint32_t seq) {
    ASSERT_TRUE(socket_->send(test_frame(id_, seq)))
        << "send on station " << id_ << ": " << std::strerror(errno);
  }
  // Reads every frame waiting, or waits up to @p wait for the first.
  void poll_frames(std::chrono::milliseconds wait = 0ms) {
    std::array<std::uint8_t, 2048> buf{};
    pollfd p{socket_->fd(), POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(wait.count())) <= 0)
      return;
    for (;;) {
      const long n = socket_->receive(buf);
      if (n <= 0)
        return;
      if (n < 22)
        continue;
      StationId from;
      std::uint32_t seq;
      std::memcpy(&from, &buf[14], 4);
      std::memcpy(&seq, &buf[18], 4);
      auto& r = from_[from];
      if (seq != r.next)
        ++r.out_of_order;
      r.next = seq + 1;
      ++r.count;
    }
  }
  std::uint64_t count_from(StationId id) const {
    auto it = from_.find(id);
    return it == from_.end() ? 0 : it->second.count;
  }
  std::uint64_t out_of_order_from(StationId id) const {
    auto it = from_.find(id);
    return it == from_.end() ? 0 : it->second.out_of_order;
  }
  StationId id() const { return id_; }

 private:
  struct FromStats {
    std::uint64_t count = 0;
    std::uint32_t next = 0;
    std::uint64_t out_of_order = 0;
  };
  StationId id_;
  std::unique_ptr<PacketSocket> socket_;
  std::map<StationId, FromStats> from_;
};

// A station-host's end, standing in for station-host: AF_PACKET on its wlan0 for every
// ethertype; sends with any pooled station's MAC, sorts out plain and pooled deliveries.
class RawHost {
 public:
  explicit RawHost(const std::string& netns) {
    socket_ = in_netns(NetnsFd::open(netns), [] {
      return std::make_unique<PacketSocket>(kStationIfname, kEthertypeAll, 16 << 20);
    });
  }
  void send_as(StationId id, std::uint32_t seq) {
    ASSERT_TRUE(socket_->send(test_frame(id, seq)))
        << "send as " << id << ": " << std::strerror(errno);
  }
  struct Got {
    bool pooled = false;            ///< a TBPD frame (else a plain GN frame)
    std::vector<StationId> listed;  ///< TBPD: the receivers it names
    MacAddress outer_src{};         ///< the outer frame's source MAC
    StationId from = 0;             ///< the test payload's sender
    std::uint32_t seq = 0;
  };
  // Every GN or TBPD frame waiting, or the first within @p wait; malformed TBPD fails the test.
  void poll(std::chrono::milliseconds wait = 0ms) {
    std::array<std::uint8_t, 16384> buf{};
    pollfd p{socket_->fd(), POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(wait.count())) <= 0)
      return;
    for (;;) {
      const long n = socket_->receive(buf);
      if (n <= 0)
        return;
      const std::span<const std::uint8_t> frame(buf.data(), static_cast<std::size_t>(n));
      if (frame.size() < 14)
        continue;
      const unsigned type = unsigned{frame[12]} << 8 | frame[13];
      Got g;
      std::copy_n(frame.begin() + 6, 6, g.outer_src.begin());
      std::span<const std::uint8_t> inner = frame;
      if (type == wire::kEthertypePooledDelivery) {
        const auto d = wire::parse_pooled_delivery_frame(frame);
        ASSERT_TRUE(d) << "malformed TBPD: " << wire::to_string(d.error());
        g.pooled = true;
        g.listed = d->receivers();
        inner = d->inner_frame;
      } else if (type != kEthertypeGeoNetworking) {
        continue;  // a namespace's own IPv6 chatter, forwarded by the bridge
      }
      if (inner.size() < 22)
        continue;
      std::memcpy(&g.from, &inner[14], 4);
      std::memcpy(&g.seq, &inner[18], 4);
      got.push_back(std::move(g));
    }
  }
  std::vector<Got> got;

 private:
  std::unique_ptr<PacketSocket> socket_;
};

// Sends @p n frames from @p tx, never more than a window ahead of the slowest receiver that
// should hear it: a test of the medium's losslessness, not of socket buffer sizes.
[[maybe_unused]] void send_paced(Station& tx, std::uint32_t n, std::vector<Station*> all,
                                 const std::vector<Station*>& expected_rx) {
  constexpr std::uint64_t kWindow = 128;
  std::map<Station*, std::uint64_t> base;
  for (Station* s : expected_rx)
    base[s] = s->count_from(tx.id());
  const auto deadline = Clock::now() + 60s;
  for (std::uint32_t seq = 0; seq < n; ++seq) {
    for (;;) {
      std::uint64_t slowest = seq;
      for (Station* s : expected_rx)
        slowest = std::min(slowest, s->count_from(tx.id()) - base[s]);
      if (seq - slowest < kWindow)
        break;
      for (Station* s : all)
        s->poll_frames(1ms);
      ASSERT_LT(Clock::now(), deadline) << "stalled at frame " << seq;
    }
    tx.send(seq);
  }
  // Everything due has arrived, and a little longer for frames that must not.
  const auto until = Clock::now() + 5s;
  for (;;) {
    bool all_in = true;
    for (Station* s : expected_rx)
      all_in &= s->count_from(tx.id()) - base[s] >= n;
    if (all_in || Clock::now() > until)
      break;
    for (Station* s : all)
      s->poll_frames(1ms);
  }
  for (int i = 0; i < 20; ++i)
    for (Station* s : all)
      s->poll_frames(5ms);
}

[[maybe_unused]] unsigned short free_udp_port() {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  ::close(fd);
  return ntohs(a.sin_port);
}

}  // namespace
}  // namespace tb::emu::radio
