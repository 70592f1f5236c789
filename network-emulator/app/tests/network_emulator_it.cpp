// The network-emulator program end to end: vehicle states over UDP in, NMEA and cannelloni
// datagrams out to sockets this test owns; a station with no receiver; a bad scenario.

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "common/can/cannelloni.hpp"
#include "common/can/socketcan_bus.hpp"
#include "common/wire/vehicle_state.hpp"
#include "network-emulator/app/tests/test_scenario.hpp"

extern char** environ;

namespace tb::emu {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

struct Socket {
  int fd = -1;
  int port = 0;
  Socket() {
    fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t len = sizeof a;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    port = ntohs(a.sin_port);
    timeval tv{0, 20'000};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  }
  ~Socket() { ::close(fd); }
  std::optional<std::string> receive() {
    char buf[4096];
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0)
      return std::nullopt;
    return std::string(buf, static_cast<std::size_t>(n));
  }
  void send_to(int to_port, const void* data, std::size_t n) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(static_cast<std::uint16_t>(to_port));
    ::sendto(fd, data, n, 0, reinterpret_cast<sockaddr*>(&a), sizeof a);
  }
};

int free_port() {
  Socket s;
  return s.port;
}

class Program {
 public:
  Program(const std::vector<std::string>& args, const fs::path& log) {
    const char* bin = std::getenv("TESTBED_BIN");
    const std::string exe = std::string(bin ? bin : "build/bin") + "/network-emulator";
    std::vector<std::string> a{exe};
    a.insert(a.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& s : a)
      argv.push_back(s.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    if (::posix_spawn(&pid_, exe.c_str(), &fa, nullptr, argv.data(), environ) != 0)
      pid_ = -1;
    posix_spawn_file_actions_destroy(&fa);
  }
  ~Program() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  bool started() const { return pid_ > 0; }
  /// Waits up to 10 s for the exit code; -1 if it did not end.
  int wait_exit(bool terminate) {
    // Never kill(-1, ...): that would signal every process we may signal.
    if (pid_ <= 0)
      return -1;
    if (terminate)
      ::kill(pid_, SIGTERM);
    for (int i = 0; i < 1000; ++i) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(10ms);
    }
    return -1;
  }

 private:
  pid_t pid_ = -1;
};

/// Polls @p done until it holds or @p timeout has passed; whether it held. A loaded two-core
/// machine may be slow, so the tests wait on the condition, never a fixed time.
template <typename Pred>
bool wait_until(Pred done, std::chrono::milliseconds timeout = 10s) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline)
      return false;
    std::this_thread::sleep_for(5ms);
  }
  return true;
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class NetworkEmulatorIt : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("emu_it_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    std::ofstream(dir_ / "scenario.json") << testing::kTwoStations;
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

wire::VehicleState vehicle(std::uint32_t station, std::int64_t ms) {
  wire::VehicleState s;
  s.station_id = station;
  s.tick = static_cast<std::uint64_t>(ms / 10);
  s.sim_time_ns = ms * 1'000'000;
  s.position = {10.0 + 0.1 * static_cast<double>(ms) / 10.0, -1.75, 0.0};
  s.velocity = {10.0f, 0.0f, 0.0f};
  s.speed = 10.0f;
  return s;
}

/// A batch datagram of the stations' states at @p ms.
std::vector<std::uint8_t> batch(std::initializer_list<std::uint32_t> stations, std::int64_t ms) {
  std::vector<wire::VehicleState> states;
  for (const auto id : stations)
    states.push_back(vehicle(id, ms));
  return wire::encode_batch(states);
}

TEST_F(NetworkEmulatorIt, FeedsStationsAndSurvivesOneWithoutReceiver) {
  Socket gnss_a, can_a, can_b, sender, radio;
  const int gnss_b_port = free_port();  // nobody listens: station 1002's gpsd is "gone"
  const int listen_port = free_port();
  std::ofstream(dir_ / "stations.json")
      << "{\"stations\": [{\"station_id\": 1001, \"gnss_port\": " << gnss_a.port
      << ", \"can_port\": " << can_a.port
      << "}, {\"station_id\": 1002, \"gnss_port\": " << gnss_b_port
      << ", \"can_port\": " << can_b.port << "}]}";
  const fs::path log = dir_ / "emu.log";
  Program emu({"--scenario", (dir_ / "scenario.json").string(), "--stations",
               (dir_ / "stations.json").string(), "--listen",
               "127.0.0.1:" + std::to_string(listen_port), "--can", "udp", "--status-interval",
               "0.2", "--forward", "127.0.0.1:" + std::to_string(radio.port)},
              log);
  ASSERT_TRUE(emu.started());

  // Until the program listens, states are lost; send the first one until NMEA comes back.
  std::optional<std::string> first;
  for (int i = 0; i < 250 && !first; ++i) {
    const auto s = batch({1001}, 0);
    sender.send_to(listen_port, s.data(), s.size());
    first = gnss_a.receive();
  }
  ASSERT_TRUE(first.has_value()) << read_file(log);
  EXPECT_EQ(first->substr(0, 17), "$GPRMC,120000.000");

  const std::uint8_t junk[] = {0xDE, 0xAD};
  sender.send_to(listen_port, junk, sizeof junk);
  const auto unknown = batch({999}, 0);
  sender.send_to(listen_port, unknown.data(), unknown.size());
  // The old format, one state per datagram (version 1), is refused by its version.
  const auto old = wire::encode(vehicle(1001, 5));
  sender.send_to(listen_port, old.data(), old.size());

  std::vector<std::string> nmea;
  std::map<std::uint32_t, int> frames_a, frames_b;
  std::size_t forwarded = 0, forwarded_bad = 0;
  std::vector<wire::VehicleState> states;
  auto drain = [&] {
    while (auto d = radio.receive()) {
      if (const auto n = wire::decode_batch(
              {reinterpret_cast<const std::uint8_t*>(d->data()), d->size()}, states))
        forwarded += *n;
      else
        ++forwarded_bad;
    }
    while (auto d = gnss_a.receive())
      nmea.push_back(*d);
    for (auto* sock : {&can_a, &can_b})
      while (auto d = sock->receive()) {
        const auto p = tb::can::decode_cannelloni(
            {reinterpret_cast<const std::uint8_t*>(d->data()), d->size()});
        ASSERT_TRUE(p.has_value());
        for (const auto& f : p->frames)
          ++(sock == &can_a ? frames_a : frames_b)[f.id()];
      }
  };
  for (std::int64_t ms = 10; ms < 1500; ms += 10) {
    const auto s = batch({1001, 1002}, ms);  // one tick's states in one datagram
    sender.send_to(listen_port, s.data(), s.size());
    if (ms % 100 == 0) {
      // Pace the sender by the emulator: wait for this 100 ms epoch's NMEA sentence.
      const auto epochs = static_cast<std::size_t>(ms / 100);
      ASSERT_TRUE(wait_until([&] {
        drain();
        return nmea.size() >= epochs;
      })) << "epoch "
          << epochs << " never came; " << read_file(log);
    }
  }
  // Everything sent must come out; wait for it (a deadline, not a fixed time).
  const bool all = wait_until([&] {
    drain();
    return nmea.size() >= 14 && frames_a[256] >= 150 && frames_a[512] >= 15 &&
           frames_b[256] >= 149 && forwarded >= 2u * 149 + 1;
  });
  EXPECT_TRUE(all) << read_file(log);

  // Station 1001: an epoch per 100 ms of sim time (0 was read above), all its CAN messages.
  EXPECT_EQ(nmea.size(), 14u);
  EXPECT_EQ(frames_a[256], 150);  // 0 ms (the first state) to 1490 ms
  EXPECT_EQ(frames_a[512], 15);
  // Station 1002's gpsd is gone, but its CAN reader is there and got everything.
  EXPECT_EQ(frames_b[256], 149);
  // --forward passed on the valid states (also station 999's), not the junk.
  EXPECT_GE(forwarded, 2u * 149 + 1);
  EXPECT_EQ(forwarded_bad, 0u);

  EXPECT_EQ(emu.wait_exit(true), 0) << read_file(log);
  const std::string text = read_file(log);
  EXPECT_NE(text.find("CAN transport: CAN frames over UDP in cannelloni's format (--can udp)"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("station 1002: GNSS receiver at 127.0.0.1 is gone"), std::string::npos)
      << text;
  EXPECT_NE(text.find("dropping malformed vehicle-state datagrams"), std::string::npos) << text;
  EXPECT_NE(text.find("dropping states of station 999"), std::string::npos) << text;
  EXPECT_NE(text.find("malformed 2, unknown station 1"), std::string::npos) << text;
  EXPECT_NE(text.find("version 1 (a single-state datagram of the old format"), std::string::npos)
      << text;
}

// Issue 35: --relay HOST:PORT passes every state datagram on unchanged to HOST:PORT and every
// signal-feed datagram to HOST:PORT+1; HOST is a name, resolved by the program.
TEST_F(NetworkEmulatorIt, RelayPassesStatesAndSignalsOnUnchanged) {
  // Two consecutive ports for the relay target: states at P, signals at P+1.
  std::unique_ptr<Socket> states, signals;
  for (int i = 0; i < 50 && !signals; ++i) {
    states = std::make_unique<Socket>();
    auto next = std::make_unique<Socket>();
    ::close(next->fd);
    next->fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(static_cast<std::uint16_t>(states->port + 1));
    if (::bind(next->fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) {
      timeval tv{0, 20'000};
      ::setsockopt(next->fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
      next->port = states->port + 1;
      signals = std::move(next);
    }
  }
  ASSERT_TRUE(signals) << "no two consecutive free ports";
  Socket sender;
  const int listen_port = free_port(), signals_port = free_port();
  const fs::path log = dir_ / "relay.log";
  Program emu({"--scenario", (dir_ / "scenario.json").string(), "--listen",
               "127.0.0.1:" + std::to_string(listen_port), "--signals-listen",
               "127.0.0.1:" + std::to_string(signals_port), "--can", "udp", "--relay",
               "localhost:" + std::to_string(states->port)},
              log);
  ASSERT_TRUE(emu.started());
  // Until the program listens and has resolved the name, datagrams are lost: resend.
  const auto s = batch({1001, 1002}, 0);
  std::optional<std::string> got;
  for (int i = 0; i < 250 && !got; ++i) {
    sender.send_to(listen_port, s.data(), s.size());
    got = states->receive();
  }
  ASSERT_TRUE(got) << read_file(log);
  EXPECT_EQ(*got, std::string(s.begin(), s.end()));
  // Unchanged, whatever this node makes of it: a datagram it refuses goes on too.
  const std::uint8_t junk[] = {0xDE, 0xAD, 0xBE, 0xEF};
  sender.send_to(listen_port, junk, sizeof junk);
  std::optional<std::string> j;
  ASSERT_TRUE(wait_until([&] { return (j = states->receive()).has_value(); })) << read_file(log);
  EXPECT_EQ(*j, std::string(std::begin(junk), std::end(junk)));
  const std::uint8_t feed[] = {'T', 'B', 'S', 'F', 1, 2, 3};
  sender.send_to(signals_port, feed, sizeof feed);
  std::optional<std::string> f;
  ASSERT_TRUE(wait_until([&] { return (f = signals->receive()).has_value(); })) << read_file(log);
  EXPECT_EQ(*f, std::string(std::begin(feed), std::end(feed)));
  EXPECT_EQ(emu.wait_exit(true), 0) << read_file(log);
  EXPECT_NE(read_file(log).find("relay localhost:" + std::to_string(states->port) +
                                ": vehicle states to 127.0.0.1"),
            std::string::npos)
      << read_file(log);
}

TEST_F(NetworkEmulatorIt, ARelayThatIsNotHostAndPortIsRefused) {
  const fs::path log = dir_ / "bad-relay.log";
  Program emu({"--scenario", (dir_ / "scenario.json").string(), "--listen", "127.0.0.1:0",
               "--relay", "emulator-tb-node2:65535"},
              log);
  EXPECT_EQ(emu.wait_exit(false), 1);
  EXPECT_NE(read_file(log).find("--relay emulator-tb-node2:65535"), std::string::npos)
      << read_file(log);
}

TEST_F(NetworkEmulatorIt, BadScenarioExitsWithTwoAndNamesTheField) {
  std::ofstream(dir_ / "bad.json") << R"({"name": "x", "map": {"type": "moon"},
    "origin": {"lat": 48, "lon": 11}, "vehicles": []})";
  const fs::path log = dir_ / "bad.log";
  Program emu({"--scenario", (dir_ / "bad.json").string()}, log);
  ASSERT_TRUE(emu.started());
  EXPECT_EQ(emu.wait_exit(false), 2);
  const std::string text = read_file(log);
  EXPECT_NE(text.find("bad.json"), std::string::npos) << text;
  EXPECT_NE(text.find("/map/type"), std::string::npos) << text;
}

TEST_F(NetworkEmulatorIt, BadStationsFileExitsWithTwo) {
  std::ofstream(dir_ / "stations.json") << R"({"stations": [{"station_id": 5}]})";
  const fs::path log = dir_ / "st.log";
  Program emu({"--scenario", (dir_ / "scenario.json").string(), "--stations",
               (dir_ / "stations.json").string()},
              log);
  EXPECT_EQ(emu.wait_exit(false), 2);
  EXPECT_NE(read_file(log).find("station 5 is not in scenario"), std::string::npos);
}

TEST_F(NetworkEmulatorIt, CanTransportIsDetectedAndSaidOnce) {
  if (tb::can::socketcan_available())
    GTEST_SKIP() << "this kernel has SocketCAN; the stand-in path is not chosen here";
  const fs::path log = dir_ / "auto.log";
  {
    Program emu({"--scenario", (dir_ / "scenario.json").string(), "--listen", "127.0.0.1:0"}, log);
    // Up (its last start-up line), so that SIGTERM is the stop it handles.
    EXPECT_TRUE(wait_until([&] {
      return read_file(log).find("; listening on ") != std::string::npos;
    })) << read_file(log);
    EXPECT_EQ(emu.wait_exit(true), 0);
  }
  const std::string text = read_file(log);
  EXPECT_NE(text.find("CAN transport: CAN frames over UDP in cannelloni's format (this kernel "
                      "has no SocketCAN)"),
            std::string::npos)
      << text;
  // Asking for SocketCAN where there is none is an error, not a silent stand-in.
  Program vcan(
      {"--scenario", (dir_ / "scenario.json").string(), "--listen", "127.0.0.1:0", "--can", "vcan"},
      dir_ / "vcan.log");
  EXPECT_EQ(vcan.wait_exit(false), 1);
  EXPECT_NE(read_file(dir_ / "vcan.log").find("--can vcan: this kernel has no SocketCAN"),
            std::string::npos);
}

}  // namespace
}  // namespace tb::emu
