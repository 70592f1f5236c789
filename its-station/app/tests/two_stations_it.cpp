// Integration: two its-station processes in two network namespaces, joined by a veth pair
// named wlan0 on both ends (the radio stand-in), each with its own real gpsd fed NMEA over UDP
// by this test. Each must see the other in its LDM (--status-file) with the right position
// and speed. Needs root (namespaces); about 8 s.

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/can/netns.hpp"
#include "common/geodesy/local_frame.hpp"
#include "common/test_support/stale_netns.hpp"
#include "its-station/facilities/cam_rules.hpp"
#include "its-station/facilities/tests/nmea_feed.hpp"

extern char** environ;

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

int sh(const std::string& cmd) {
  return std::system((cmd + " >/dev/null 2>&1").c_str());
}

pid_t spawn(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const auto& a : args)
    argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = -1;
  if (posix_spawnp(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0)
    return -1;
  return pid;
}

/// Waits up to @p limit; kills the process if it is still running. Returns the exit status.
int wait_for(pid_t pid, std::chrono::milliseconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  int status = 0;
  while (std::chrono::steady_clock::now() < end) {
    if (waitpid(pid, &status, WNOHANG) == pid)
      return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    std::this_thread::sleep_for(50ms);
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return -1;
}

class TwoStationNamespaces : public ::testing::Test {
 protected:
  void SetUp() override {
    if (geteuid() != 0)
      GTEST_SKIP() << "needs root for network namespaces";
    const char* bin = std::getenv("TESTBED_BIN");
    station_bin = bin ? fs::path(bin) / "its-station" : fs::path("its-station");
    if (!fs::exists(station_bin))
      GTEST_SKIP() << station_bin << " not built";
    tb::test_support::remove_stale_netns({"facA", "facB"});
    const auto tag = std::to_string(getpid());
    ns_a = "facA" + tag;
    ns_b = "facB" + tag;
    dir = fs::temp_directory_path() / ("fac-two-stations-" + tag);
    fs::create_directories(dir);
    cleanup();
    const std::string va = "fva" + tag, vb = "fvb" + tag;
    ASSERT_EQ(sh("ip netns add " + ns_a), 0);
    ASSERT_EQ(sh("ip netns add " + ns_b), 0);
    ASSERT_EQ(sh(fmt::format("ip link add {} type veth peer name {}", va, vb)), 0);
    ASSERT_EQ(sh(fmt::format("ip link set {} netns {}", va, ns_a)), 0);
    ASSERT_EQ(sh(fmt::format("ip link set {} netns {}", vb, ns_b)), 0);
    for (const auto& [ns, v] : {std::pair{ns_a, va}, std::pair{ns_b, vb}}) {
      ASSERT_EQ(sh(fmt::format("ip netns exec {} ip link set {} name wlan0", ns, v)), 0);
      ASSERT_EQ(sh(fmt::format("ip netns exec {} ip link set wlan0 up", ns)), 0);
      ASSERT_EQ(sh(fmt::format("ip netns exec {} ip link set lo up", ns)), 0);
    }
  }
  void TearDown() override {
    cleanup();
    if (!dir.empty())
      fs::remove_all(dir);
  }
  void cleanup() {
    // Deleting a namespace kills nothing, but removes its veth end (and so the pair).
    if (!ns_a.empty())
      sh("ip netns del " + ns_a);
    if (!ns_b.empty())
      sh("ip netns del " + ns_b);
  }

  /// A UDP socket inside @p ns, for sending NMEA to that station's gpsd.
  int socket_in(const std::string& ns) {
    int fd = -1;
    auto ec = tb::can::run_in_netns(ns, [&] { fd = ::socket(AF_INET, SOCK_DGRAM, 0); });
    EXPECT_FALSE(ec) << ec.message();
    return fd;
  }

  pid_t start_station(const std::string& ns, std::uint32_t id) {
    return spawn({"ip", "netns", "exec", ns, station_bin.string(), "--station-id",
                  std::to_string(id), "--radio", "wlan0", "--can", "none", "--no-lcrw",
                  // A safety net only: the test stops the stations once they see each other.
                  "--duration", "60", "--status-file", (dir / (ns + ".json")).string(),
                  "--log-level", "warn"});
  }

  nlohmann::json status(const std::string& ns) {
    std::ifstream in(dir / (ns + ".json"));
    return nlohmann::json::parse(in, nullptr, false);
  }

  fs::path station_bin, dir;
  std::string ns_a, ns_b;
};

TEST_F(TwoStationNamespaces, EachSeesTheOtherInItsLdm) {
  const pid_t a = start_station(ns_a, 1001);
  const pid_t b = start_station(ns_b, 1002);
  ASSERT_GT(a, 0);
  ASSERT_GT(b, 0);
  const int fa = socket_in(ns_a), fb = socket_in(ns_b);
  ASSERT_GE(fa, 0);
  ASSERT_GE(fb, 0);
  sockaddr_in gpsd{};
  gpsd.sin_family = AF_INET;
  gpsd.sin_port = htons(10110);
  gpsd.sin_addr.s_addr = htonl(INADDR_LOOPBACK);

  // A drives east at 10 m/s; B drives west at 5 m/s 30 m further north.
  const tb::geodesy::LocalFrame frame({48.1, 11.5, 547.0});
  tb::geodesy::Geodetic last_a{}, last_b{};
  // Feed both gpsds at 10 Hz until each station has the other in its LDM, as its status file
  // says, after a few CAMs of its own (a deadline, not a fixed time: a loaded machine starts
  // gpsd and the stations later).
  auto sees_other = [&](const std::string& ns) {
    const auto st = status(ns);
    return st.is_object() && st.value("cams_sent", 0) > 3 && st.contains("neighbours") &&
           st["neighbours"].size() == 1;
  };
  const auto start = std::chrono::steady_clock::now();
  const auto deadline = start + 30s;
  for (int k = 0; std::chrono::steady_clock::now() < deadline; ++k) {
    if (k >= 20 && sees_other(ns_a) && sees_other(ns_b))
      break;
    const double t = k * 0.1;
    last_a = frame.to_geodetic({10.0 * t, 0.0, 0.0});
    last_b = frame.to_geodetic({200.0 - 5.0 * t, 30.0, 0.0});
    const auto now = std::chrono::system_clock::now();
    const auto ea = tb::its::facilities::testing::nmea_epoch(now, last_a.latitude_deg,
                                                             last_a.longitude_deg, 10.0, 90.0);
    const auto eb = tb::its::facilities::testing::nmea_epoch(now, last_b.latitude_deg,
                                                             last_b.longitude_deg, 5.0, 270.0);
    ::sendto(fa, ea.datagram.data(), ea.datagram.size(), 0,
             reinterpret_cast<const sockaddr*>(&gpsd), sizeof gpsd);
    ::sendto(fb, eb.datagram.data(), eb.datagram.size(), 0,
             reinterpret_cast<const sockaddr*>(&gpsd), sizeof gpsd);
    std::this_thread::sleep_until(start + (k + 1) * 100ms);
  }
  ::close(fa);
  ::close(fb);
  // SIGTERM: each writes its final status and exits 0.
  kill(a, SIGTERM);
  kill(b, SIGTERM);
  EXPECT_EQ(wait_for(a, 10s), 0);
  EXPECT_EQ(wait_for(b, 10s), 0);

  const auto sa = status(ns_a), sb = status(ns_b);
  ASSERT_FALSE(sa.is_discarded()) << "no status from A";
  ASSERT_FALSE(sb.is_discarded()) << "no status from B";
  EXPECT_GT(sa["cams_sent"].get<int>(), 3);
  EXPECT_GT(sb["cams_sent"].get<int>(), 3);
  ASSERT_EQ(sa["neighbours"].size(), 1u) << sa.dump();
  ASSERT_EQ(sb["neighbours"].size(), 1u) << sb.dump();
  const auto& b_seen_by_a = sa["neighbours"][0];
  const auto& a_seen_by_b = sb["neighbours"][0];
  EXPECT_EQ(b_seen_by_a["station_id"], 1002);
  EXPECT_EQ(a_seen_by_b["station_id"], 1001);
  EXPECT_NEAR(b_seen_by_a["speed_mps"].get<double>(), 5.0, 0.02);
  EXPECT_NEAR(a_seen_by_b["speed_mps"].get<double>(), 10.0, 0.02);
  EXPECT_NEAR(b_seen_by_a["heading_deg"].get<double>(), 270.0, 0.1);
  EXPECT_NEAR(a_seen_by_b["heading_deg"].get<double>(), 90.0, 0.1);
  // The newest CAM is at most one CAM interval old: within ~4 m (position trigger) of the last
  // fix fed (the stations stop right after the feed).
  const double da = tb::its::facilities::distance_m(a_seen_by_b["latitude_deg"].get<double>(),
                                                    a_seen_by_b["longitude_deg"].get<double>(),
                                                    last_a.latitude_deg, last_a.longitude_deg);
  const double db = tb::its::facilities::distance_m(b_seen_by_a["latitude_deg"].get<double>(),
                                                    b_seen_by_a["longitude_deg"].get<double>(),
                                                    last_b.latitude_deg, last_b.longitude_deg);
  EXPECT_LT(da, 5.0);
  EXPECT_LT(db, 5.0);
}

/// Runs an its-station command line; its exit status and what it printed (stdout and stderr).
std::pair<int, std::string> run_station(const std::string& command) {
  FILE* p = ::popen((command + " 2>&1").c_str(), "r");
  if (p == nullptr)
    return {-1, "popen failed"};
  std::string out;
  char buf[512];
  while (std::fgets(buf, sizeof buf, p) != nullptr)
    out += buf;
  return {::pclose(p), out};
}

// Bad values of the received-CAM mirror's interval stop the program before it opens anything,
// with a message that names the option and the value.
TEST(ItsStationOptions, MqttCamIntervalOutsideItsRangeIsRefusedByName) {
  const char* bin = std::getenv("TESTBED_BIN");
  const fs::path station = bin ? fs::path(bin) / "its-station" : fs::path("its-station");
  if (!fs::exists(station))
    GTEST_SKIP() << station << " not built";
  for (const std::string value : {"5", "60001", "fast"}) {
    const auto [status, out] = run_station(
        station.string() + " --station-id 1001 --radio none-such --mqtt-cam-interval-ms " + value);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) != 0) << value << ": " << out;
    EXPECT_NE(out.find("--mqtt-cam-interval-ms"), std::string::npos) << out;
    EXPECT_NE(out.find(value), std::string::npos) << out;
  }
}

// A bad --security-time-window stops the program before it opens anything, naming the option,
// the value and the part that is wrong.
TEST(ItsStationOptions, SecurityTimeWindowThatIsNotPsidEqualsMsIsRefusedByName) {
  const char* bin = std::getenv("TESTBED_BIN");
  const fs::path station = bin ? fs::path(bin) / "its-station" : fs::path("its-station");
  if (!fs::exists(station))
    GTEST_SKIP() << station << " not built";
  const std::pair<std::string, std::string> cases[] = {
      {"cam=2000", "PSID \"cam\""},
      {"37=600001", "PAST_MS \"600001\""},
      {"37=10000:soon", "FUTURE_MS \"soon\""},
      {"36", "no '='"},
  };
  for (const auto& [value, part] : cases) {
    const auto [status, out] =
        run_station(station.string() +
                    " --station-id 1001 --radio none-such --security-time-window 36=2000 "
                    "--security-time-window " +
                    value);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) != 0) << value << ": " << out;
    EXPECT_NE(out.find("--security-time-window"), std::string::npos) << out;
    EXPECT_NE(out.find("\"" + value + "\""), std::string::npos) << out;
    EXPECT_NE(out.find(part), std::string::npos) << out;
  }
}

}  // namespace
