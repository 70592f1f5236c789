// Integration: one station-host with 20 pooled stations and one full its-station, in two
// network namespaces, the full station's gpsd fed NMEA and the host fed vehicle states by this
// test. Two media: a veth pair named wlan0 on both ends (as the kernel bridge forwards: every
// frame to the other end, never back; the host loops its own stations' frames back), and
// radio-medium with --pooled and a range channel (the program forwards: pooled deliveries,
// TBPD, to the host, its own stations' frames included). CAMs must go both ways, the host's
// stations must hear each other, and every pooled station must send with its own MAC and
// station id (checked in a capture of the air). Unsigned and signed. Needs root; ~10 s each.

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/can/netns.hpp"
#include "common/geodesy/local_frame.hpp"
#include "common/test_support/stale_netns.hpp"
#include "common/wire/vehicle_state.hpp"
#include "its-station/facilities/tests/nmea_feed.hpp"

extern char** environ;

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

constexpr std::uint32_t kFull = 1001;
constexpr std::uint32_t kFirstPooled = 3001;
constexpr int kPooled = 20;
constexpr double kOriginLat = 41.105, kOriginLon = 29.023, kOriginAlt = 60.0;

int sh(const std::string& cmd) {
  return std::system((cmd + " >/dev/null 2>&1").c_str());
}

std::string output_of(const std::string& cmd) {
  std::string out;
  FILE* p = ::popen(cmd.c_str(), "r");
  if (p == nullptr)
    return out;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0)
    out.append(buf, n);
  ::pclose(p);
  return out;
}

pid_t spawn(const std::vector<std::string>& args, const fs::path& log = {}) {
  std::vector<char*> argv;
  for (const auto& a : args)
    argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  if (!log.empty()) {
    posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
  }
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  return rc == 0 ? pid : -1;
}

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

std::string mac_of(std::uint32_t id) {
  return fmt::format("02:00:{:02x}:{:02x}:{:02x}:{:02x}", id >> 24 & 0xff, id >> 16 & 0xff,
                     id >> 8 & 0xff, id & 0xff);
}

struct Case {
  bool signed_mode = false;
  bool radio_medium = false;  ///< else a plain veth pair
};

/// radio-medium in this process's namespace; says "radio-medium: ready" on stdout.
class Medium {
 public:
  Medium(const std::vector<std::string>& args, const fs::path& log)
      : pid_(spawn(args, log)), log_(log) {}
  ~Medium() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      wait_for(pid_, 10s);
    }
  }
  bool wait_ready() const {
    for (int i = 0; i < 100; ++i) {
      if (output_of("cat " + log_.string()).find("radio-medium: ready") != std::string::npos)
        return true;
      std::this_thread::sleep_for(100ms);
    }
    return false;
  }

 private:
  pid_t pid_ = -1;
  fs::path log_;
};

class StationHostIt : public ::testing::TestWithParam<Case> {
 protected:
  void SetUp() override {
    if (geteuid() != 0)
      GTEST_SKIP() << "needs root for network namespaces";
    const char* bin = std::getenv("TESTBED_BIN");
    const fs::path b = bin ? fs::path(bin) : fs::path(".");
    host_bin = b / "station-host";
    station_bin = b / "its-station";
    pki_bin = b / "its-pki";
    medium_bin = b / "radio-medium";
    for (const auto& p : {host_bin, station_bin, pki_bin, medium_bin})
      if (!fs::exists(p))
        GTEST_SKIP() << p << " not built";
    if (sh("command -v tshark") != 0)
      GTEST_SKIP() << "tshark not installed";
    tb::test_support::remove_stale_netns({"shF", "shH"});
    const auto tag = std::to_string(getpid());
    ns_full = "shF" + tag;
    ns_host = "shH" + tag;
    dir = fs::temp_directory_path() / ("station-host-it-" + tag);
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string va = "shva" + tag, vb = "shvb" + tag;
    ASSERT_EQ(sh("ip netns add " + ns_full), 0);
    ASSERT_EQ(sh("ip netns add " + ns_host), 0);
    for (const auto& ns : {ns_full, ns_host})
      ASSERT_EQ(sh(fmt::format("ip netns exec {} ip link set lo up", ns)), 0);
    if (GetParam().radio_medium)
      return;  // radio-medium makes the pairs and names the ends
    ASSERT_EQ(sh(fmt::format("ip link add {} type veth peer name {}", va, vb)), 0);
    ASSERT_EQ(sh(fmt::format("ip link set {} netns {}", va, ns_full)), 0);
    ASSERT_EQ(sh(fmt::format("ip link set {} netns {}", vb, ns_host)), 0);
    for (const auto& [ns, v] : {std::pair{ns_full, va}, std::pair{ns_host, vb}}) {
      ASSERT_EQ(sh(fmt::format("ip netns exec {} ip link set {} name wlan0", ns, v)), 0);
      ASSERT_EQ(sh(fmt::format("ip netns exec {} ip link set wlan0 up", ns)), 0);
    }
    // The full station sends with 02:00 + its id, as radio-medium gives every station.
    ASSERT_EQ(
        sh(fmt::format("ip netns exec {} ip link set wlan0 address {}", ns_full, mac_of(kFull))),
        0);
  }
  void TearDown() override {
    if (!ns_full.empty())
      sh("ip netns del " + ns_full);
    if (!ns_host.empty())
      sh("ip netns del " + ns_host);
    if (!dir.empty() && !HasFailure())
      fs::remove_all(dir);
  }

  void write_scenario(bool signed_mode, bool range_channel) {
    nlohmann::json v = nlohmann::json::array();
    auto vehicle = [](std::uint32_t id, int lane, double s, bool pooled) {
      nlohmann::json j{{"id", fmt::format("v{}", id)},
                       {"station_id", id},
                       {"spawn", {{"lane", lane}, {"s", s}}},
                       {"driver",
                        {{"type", "lane_follow"},
                         {"speed_profile", nlohmann::json::array({{{"t", 0}, {"speed", 10}}})}}}};
      if (pooled)
        j["station"] = {{"kind", "pooled"}};
      return j;
    };
    v.push_back(vehicle(kFull, 0, 20, false));
    for (int i = 0; i < kPooled; ++i)
      v.push_back(vehicle(kFirstPooled + i, i % 2, 40.0 + 10.0 * i, true));
    nlohmann::json s{{"name", "station-host-it"},
                     {"map", {{"type", "straight"}, {"lanes", 2}, {"length", 1000}}},
                     {"origin", {{"lat", kOriginLat}, {"lon", kOriginLon}, {"alt", kOriginAlt}}},
                     {"vehicles", v}};
    if (signed_mode)
      s["security"] = "signed";
    if (range_channel)  // radio-medium forwards then, per receiver
      s["channel"] = {{"model", "range"}, {"range_m", 400}};
    std::ofstream(dir / "scenario.json") << s.dump(2);
  }

  void make_pki() {
    std::string cmd = fmt::format("{} make --dir {} --station {}", pki_bin.string(),
                                  (dir / "pki").string(), kFull);
    for (int i = 0; i < kPooled; ++i)
      cmd += fmt::format(" --station {}", kFirstPooled + i);
    ASSERT_EQ(sh(cmd), 0) << cmd;
    for (int i = 0; i < kPooled; ++i) {
      const std::uint32_t id = kFirstPooled + i;
      const std::string e = fmt::format("{} export --dir {} --station {} --out {}",
                                        pki_bin.string(), (dir / "pki").string(), id,
                                        (dir / "pooled-pki" / std::to_string(id)).string());
      ASSERT_EQ(sh(e), 0) << e;
    }
  }

  int socket_in(const std::string& ns) {
    int fd = -1;
    auto ec = tb::can::run_in_netns(ns, [&] { fd = ::socket(AF_INET, SOCK_DGRAM, 0); });
    EXPECT_FALSE(ec) << ec.message();
    return fd;
  }

  nlohmann::json read_json(const fs::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in, nullptr, false);
  }

  fs::path host_bin, station_bin, pki_bin, medium_bin, dir;
  std::string ns_full, ns_host;
};

TEST_P(StationHostIt, CamsBothWaysEachPooledStationWithItsOwnIdAndMac) {
  const bool signed_mode = GetParam().signed_mode;
  const bool radio_medium = GetParam().radio_medium;
  write_scenario(signed_mode, radio_medium);
  if (signed_mode)
    make_pki();
  std::string ids;
  for (int i = 0; i < kPooled; ++i)
    ids += (i ? "," : "") + std::to_string(kFirstPooled + i);
  std::optional<Medium> medium;
  const auto positions_port = static_cast<unsigned short>(20000 + getpid() % 20000);
  if (radio_medium) {
    medium.emplace(std::vector<std::string>{medium_bin.string(), "--scenario",
                                            (dir / "scenario.json").string(), "--mode", "veth",
                                            "--prefix", fmt::format("tbs{:02d}", getpid() % 100),
                                            "--stations", fmt::format("{}={}", kFull, ns_full),
                                            "--pooled", ns_host + "=" + ids, "--positions",
                                            fmt::format("udp://127.0.0.1:{}", positions_port)},
                   dir / "medium.log");
    ASSERT_TRUE(medium->wait_ready()) << output_of("cat " + (dir / "medium.log").string());
  }
  const fs::path pcap = dir / "air.pcap";
  const pid_t capture =
      spawn({"ip", "netns", "exec", ns_full, "tshark", "-i", "wlan0", "-q", "-w", pcap.string()},
            dir / "tshark.log");
  ASSERT_GT(capture, 0);
  for (int i = 0; i < 100 && !fs::exists(pcap); ++i)
    std::this_thread::sleep_for(100ms);

  std::vector<std::string> full_args{"ip",
                                     "netns",
                                     "exec",
                                     ns_full,
                                     station_bin.string(),
                                     "--station-id",
                                     std::to_string(kFull),
                                     "--scenario",
                                     (dir / "scenario.json").string(),
                                     "--radio",
                                     "wlan0",
                                     "--can",
                                     "none",
                                     "--no-lcrw",
                                     "--duration",
                                     "90",
                                     "--status-file",
                                     (dir / "full.json").string()};
  std::vector<std::string> host_args{"ip",
                                     "netns",
                                     "exec",
                                     ns_host,
                                     host_bin.string(),
                                     "--scenario",
                                     (dir / "scenario.json").string(),
                                     "--stations",
                                     ids,
                                     "--radio",
                                     "wlan0",
                                     "--states",
                                     "udp://127.0.0.1:4710",
                                     "--forwarding",
                                     radio_medium ? "user" : "kernel",
                                     "--duration",
                                     "90",
                                     "--status-file",
                                     (dir / "host.json").string()};
  if (signed_mode) {
    full_args.insert(full_args.end(), {"--pki-dir", (dir / "pki").string()});
    host_args.insert(host_args.end(), {"--pki-dir", (dir / "pooled-pki").string()});
  }
  const pid_t full = spawn(full_args, dir / "full.log");
  const pid_t host = spawn(host_args, dir / "host.log");
  ASSERT_GT(full, 0);
  ASSERT_GT(host, 0);

  const int nmea_fd = socket_in(ns_full), state_fd = socket_in(ns_host);
  ASSERT_GE(nmea_fd, 0);
  ASSERT_GE(state_fd, 0);
  sockaddr_in gpsd{};
  gpsd.sin_family = AF_INET;
  gpsd.sin_port = htons(10110);
  gpsd.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  sockaddr_in states_to = gpsd;
  states_to.sin_port = htons(4710);
  sockaddr_in positions_to = gpsd;
  positions_to.sin_port = htons(positions_port);
  const int positions_fd = ::socket(AF_INET, SOCK_DGRAM, 0);  // radio-medium's, this namespace

  const tb::geodesy::LocalFrame frame({kOriginLat, kOriginLon, kOriginAlt});
  const auto t0 = std::chrono::system_clock::now();
  const std::int64_t world_start = tb::clock::to_unix_ns(t0);
  auto all_heard = [&] {
    const auto f = read_json(dir / "full.json");
    const auto h = read_json(dir / "host.json");
    if (!f.is_object() || !h.is_object() || f["neighbours"].size() != kPooled)
      return false;
    for (const auto& s : h["stations"])
      if (s["neighbours"].get<int>() != kPooled || s["cams_sent"].get<int>() < 3)
        return false;
    return true;
  };
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; std::chrono::steady_clock::now() < start + 60s; ++k) {
    if (k >= 30 && k % 5 == 0 && all_heard())
      break;
    const double t = k * 0.1;
    const auto now = t0 + std::chrono::milliseconds(100 * k);
    const auto p = frame.to_geodetic({20.0 + 10.0 * t, 0.0, 0.0});
    const auto e =
        tb::its::facilities::testing::nmea_epoch(now, p.latitude_deg, p.longitude_deg, 10.0, 90.0);
    ::sendto(nmea_fd, e.datagram.data(), e.datagram.size(), 0,
             reinterpret_cast<const sockaddr*>(&gpsd), sizeof gpsd);
    std::vector<tb::wire::VehicleState> batch;
    for (int i = 0; i < kPooled; ++i) {
      tb::wire::VehicleState s;
      s.station_id = kFirstPooled + i;
      s.tick = static_cast<std::uint64_t>(k);
      s.sim_time_ns = static_cast<std::int64_t>(k) * 100'000'000;
      s.step_wall_ns = s.send_wall_ns = world_start + s.sim_time_ns;
      s.position = {40.0 + 10.0 * i + 10.0 * t, (i % 2) * 3.5, 0.0};
      s.velocity = {10.0f, 0.0f, 0.0f};
      s.speed = 10.0f;
      s.gear = 1;
      batch.push_back(s);
    }
    // The full station's state too: the host skips it, the medium places it.
    tb::wire::VehicleState full_state = batch.front();
    full_state.station_id = kFull;
    full_state.position = {20.0 + 10.0 * t, 0.0, 0.0};
    batch.push_back(full_state);
    // Datagrams of at most an Ethernet MTU (9 states), as network-emulator forwards them.
    const std::size_t per = tb::wire::states_per_batch(tb::wire::kDefaultBatchDatagramSize);
    for (std::size_t first = 0; first < batch.size(); first += per) {
      const auto bytes = tb::wire::encode_batch(
          std::span(batch).subspan(first, std::min(per, batch.size() - first)), world_start);
      ::sendto(state_fd, bytes.data(), bytes.size(), 0,
               reinterpret_cast<const sockaddr*>(&states_to), sizeof states_to);
      if (radio_medium)
        ::sendto(positions_fd, bytes.data(), bytes.size(), 0,
                 reinterpret_cast<const sockaddr*>(&positions_to), sizeof positions_to);
    }
    std::this_thread::sleep_until(start + (k + 1) * 100ms);
  }
  ::close(nmea_fd);
  ::close(state_fd);
  ::close(positions_fd);
  kill(full, SIGTERM);
  kill(host, SIGTERM);
  EXPECT_EQ(wait_for(full, 10s), 0);
  EXPECT_EQ(wait_for(host, 10s), 0) << output_of("cat " + (dir / "host.log").string());
  kill(capture, SIGINT);
  wait_for(capture, 10s);

  // CAMs both ways: the full station hears all 20, each pooled one hears the full one and its
  // 19 siblings (looped back in the host).
  const auto f = read_json(dir / "full.json");
  const auto h = read_json(dir / "host.json");
  ASSERT_TRUE(f.is_object()) << "no status from the full station";
  ASSERT_TRUE(h.is_object()) << "no status from the host";
  std::set<std::uint32_t> heard_by_full;
  for (const auto& n : f["neighbours"])
    heard_by_full.insert(n["station_id"].get<std::uint32_t>());
  std::set<std::uint32_t> pooled_ids;
  for (int i = 0; i < kPooled; ++i)
    pooled_ids.insert(kFirstPooled + i);
  EXPECT_EQ(heard_by_full, pooled_ids);
  ASSERT_EQ(h["stations"].size(), static_cast<std::size_t>(kPooled));
  for (const auto& s : h["stations"]) {
    const auto id = s["station_id"].get<std::uint32_t>();
    std::set<std::uint32_t> heard;
    for (const auto& n : s["neighbour_ids"])
      heard.insert(n.get<std::uint32_t>());
    std::set<std::uint32_t> expected = pooled_ids;
    expected.erase(id);
    expected.insert(kFull);
    EXPECT_EQ(heard, expected) << "station " << id;
    EXPECT_GT(s["cams_sent"].get<int>(), 3) << "station " << id;
    if (signed_mode) {
      // Pooled stations verify on demand (security/README.md): without LCRW nothing of theirs
      // needs a CAM's signature checked, so the CAMs go up unverified, none refused; the full
      // station below verifies every one of theirs.
      ASSERT_TRUE(s.contains("security")) << s.dump();
      EXPECT_EQ(s["security"]["verify_policy"], "on-demand") << s.dump();
      EXPECT_GT(s["security"]["verify"].value("not_verified", 0), 0) << s.dump();
      for (const auto& [outcome, n] : s["security"]["verify"].items())
        EXPECT_TRUE(outcome == "not_verified" || outcome == "ok" || outcome == "unknown_signer")
            << "station " << id << " refused " << n << " packet(s): " << outcome;
    }
  }
  // How the frames came: pooled deliveries from radio-medium, or plain frames and the host's
  // own loopback on the veth pair.
  const auto& link = h["link"];
  if (radio_medium) {
    EXPECT_GT(link["pooled"].get<int>(), 0) << link.dump();
    EXPECT_EQ(link["looped_back"].get<int>(), 0) << link.dump();
  } else {
    EXPECT_GT(link["plain"].get<int>(), 0) << link.dump();
    EXPECT_GT(link["looped_back"].get<int>(), 0) << link.dump();
  }
  EXPECT_EQ(link["malformed_pooled"].get<int>(), 0) << link.dump();
  if (signed_mode) {
    ASSERT_TRUE(f.contains("security")) << f.dump();
    EXPECT_GT(f["security"]["verify"].value("ok", 0), 0) << f.dump();
    for (const auto& [outcome, n] : f["security"]["verify"].items())
      EXPECT_TRUE(outcome == "ok" || outcome == "unknown_signer")
          << "the full station refused " << n << " pooled packet(s): " << outcome;
  }

  // The air: every CAM's source MAC is 02:00 + the CAM's station id, and each pooled station
  // sent some; signed mode: every CAM is signed (PSID 36).
  const std::string fields =
      output_of(fmt::format("tshark -r '{}' -Y its.messageID==2 -T fields -E separator='|' "
                            "-E occurrence=f -e eth.src -e its.stationID -e ieee1609dot2.psid "
                            "2>/dev/null",
                            pcap.string()));
  std::map<std::uint32_t, int> cams_on_air;
  std::istringstream lines(fields);
  for (std::string line; std::getline(lines, line);) {
    const auto a = line.find('|'), b = line.rfind('|');
    ASSERT_NE(a, std::string::npos) << line;
    const std::string mac = line.substr(0, a);
    const auto id = static_cast<std::uint32_t>(std::stoul(line.substr(a + 1, b - a - 1)));
    EXPECT_EQ(mac, mac_of(id)) << line;
    if (signed_mode) {
      EXPECT_EQ(line.substr(b + 1), "36") << line;
    }
    ++cams_on_air[id];
  }
  for (const std::uint32_t id : pooled_ids)
    EXPECT_GT(cams_on_air[id], 0) << "no CAM of station " << id << " on the air";
  EXPECT_GT(cams_on_air[kFull], 0);
}

INSTANTIATE_TEST_SUITE_P(Media, StationHostIt,
                         ::testing::Values(Case{false, false}, Case{true, false}, Case{false, true},
                                           Case{true, true}),
                         [](const auto& info) {
                           return std::string(info.param.radio_medium ? "RadioMedium" : "Veth") +
                                  (info.param.signed_mode ? "Signed" : "Unsigned");
                         });

}  // namespace
