// Integration test of the veth stand-in medium: three network namespaces, radio-medium from
// $TESTBED_BIN, frames sent on wlan0 inside the namespaces with AF_PACKET. Runs as root.

#include <arpa/inet.h>
#include <fcntl.h>
#include <net/if.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/wire/pooled_delivery.hpp"
#include "common/wire/vehicle_state.hpp"
#include "network-emulator/radio/netns.hpp"
#include "network-emulator/radio/packet_socket.hpp"
#include "network-emulator/radio/rtnl.hpp"
#include "network-emulator/radio/tests/medium_it_support.hpp"
#include "network-emulator/radio/veth_radios.hpp"

namespace tb::emu::radio {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> host_links_with_prefix() {
  std::vector<std::string> out;
  for (const auto& l : RouteSocket().links())
    if (l.name.starts_with(kPrefix))
      out.push_back(l.name);
  return out;
}

fs::path write_scenario(const std::string& channel) {
  const fs::path dir = fs::temp_directory_path() / ("radio-it-" + kTag);
  fs::create_directories(dir);
  const fs::path file = dir / "scenario.json";
  std::ofstream(file) << R"({
  "name": "radio-it",
  "map": { "type": "straight", "lanes": 2, "lane_width": 3.5, "length": 2000 },
  "origin": { "lat": 41.1, "lon": 29.0, "alt": 60 },
  "start_time": "2025-06-02T09:00:00Z",
  "channel": )" << channel
                      << R"(,
  "vehicles": [
    { "id": "a", "station_id": 11, "spawn": { "x": 10, "y": 0, "heading_deg": 90 }, "driver": "human" },
    { "id": "b", "station_id": 12, "spawn": { "x": 210, "y": 0, "heading_deg": 90 }, "driver": "human" },
    { "id": "c", "station_id": 13, "spawn": { "x": 460, "y": 0, "heading_deg": 90 }, "driver": "human" }
  ]
})";
  return file;
}

class VethMediumIT : public ::testing::Test {
 protected:
  void SetUp() override {
    if (::geteuid() != 0)
      GTEST_SKIP() << "needs root (network namespaces, veth)";
    test_support::remove_stale_netns({"tbrit"});
    for (const char* s : {"a", "b", "c"})
      ns_.push_back(std::make_unique<TestNetns>("tbrit" + kTag + s));
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(fs::temp_directory_path() / ("radio-it-" + kTag), ignored);
    // Whatever happened, no interface of ours is left behind.
    EXPECT_TRUE(host_links_with_prefix().empty());
    for (const auto& n : ns_)
      EXPECT_FALSE(n->has(kStationIfname)) << n->name();
  }
  std::vector<std::string> args(const fs::path& scenario, const fs::path& stats,
                                unsigned short port) {
    return {
        "--scenario",  scenario.string(),
        "--mode",      "veth",
        "--prefix",    kPrefix,
        "--stations",  "11=" + ns_[0]->name() + ",12=" + ns_[1]->name() + ",c=" + ns_[2]->name(),
        "--stats",     stats.string(),
        "--positions", "udp://127.0.0.1:" + std::to_string(port),
        "--log-level", "warn"};
  }
  std::vector<std::unique_ptr<TestNetns>> ns_;

 public:
  const std::vector<std::unique_ptr<TestNetns>>& namespaces() const { return ns_; }
};

nlohmann::json read_json(const fs::path& f) {
  std::ifstream in(f);
  return nlohmann::json::parse(in);
}

const nlohmann::json& link(const nlohmann::json& stats, StationId from, StationId to) {
  for (const auto& l : stats["links"])
    if (l["from"] == from && l["to"] == to)
      return l;
  throw std::runtime_error("no link " + std::to_string(from) + "→" + std::to_string(to));
}

void expect_links_add_up(const nlohmann::json& stats) {
  for (const auto& l : stats["links"]) {
    std::uint64_t dropped = 0;
    for (const auto& [reason, n] : l["dropped"].items())
      dropped += n.get<std::uint64_t>();
    EXPECT_EQ(l["sent"].get<std::uint64_t>(), l["delivered"].get<std::uint64_t>() + dropped)
        << l.dump();
  }
}

TEST_F(VethMediumIT, RangeModelReachesStationsInRangeAndNoneBeyond) {
  const fs::path scenario = write_scenario(R"({ "model": "range", "range_m": 300 })");
  const fs::path stats = scenario.parent_path() / "range-stats.json";
  const fs::path trace = scenario.parent_path() / "range-trace.jsonl";
  fs::remove(trace);
  const unsigned short port = free_udp_port();
  auto argv = args(scenario, stats, port);
  argv.insert(argv.end(), {"--trace", trace.string()});
  MediumProcess medium(argv);
  ASSERT_TRUE(medium.wait_ready());
  Station a(11, ns_[0]->name()), b(12, ns_[1]->name()), c(13, ns_[2]->name());
  std::vector<Station*> all{&a, &b, &c};

  // a at 10 m, b at 210 m, c at 460 m: a–b 200 m and b–c 250 m in range, a–c 450 m not.
  send_paced(a, 300, all, {&b});
  send_paced(b, 300, all, {&a, &c});
  EXPECT_EQ(b.count_from(11), 300u);
  EXPECT_EQ(c.count_from(11), 0u);
  EXPECT_EQ(a.count_from(12), 300u);
  EXPECT_EQ(c.count_from(12), 300u);
  EXPECT_EQ(a.count_from(11), 0u);  // a station never hears itself

  // A vehicle state moves c to 110 m: from then on it hears a.
  wire::VehicleState s;
  s.station_id = 13;
  s.sim_time_ns = 1'000'000'000;
  s.position = {110.0, 0.0, 0.0};
  const auto bytes = wire::encode_batch({&s, 1});
  const int udp = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(port);
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(
      ::sendto(udp, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to),
      static_cast<ssize_t>(bytes.size()));
  ::close(udp);
  std::uint32_t probes = 0;
  const auto deadline = Clock::now() + 5s;
  while (c.count_from(11) == 0 && Clock::now() < deadline) {
    a.send(1000 + probes++);
    for (Station* st : all)
      st->poll_frames(10ms);
  }
  ASSERT_GT(c.count_from(11), 0u) << "the position update never took effect";

  ASSERT_TRUE(WIFEXITED(medium.stop()));
  const auto j = read_json(stats);
  expect_links_add_up(j);
  EXPECT_EQ(link(j, 11, 12)["delivered"], 300u + probes);
  // Out of range, a's frames were not offered to c at all (range culling): no drops on the
  // link, only the frames after the move, all delivered; the rest counted as culled.
  EXPECT_EQ(link(j, 11, 13)["sent"], c.count_from(11));
  EXPECT_EQ(link(j, 11, 13)["delivered"], c.count_from(11));
  EXPECT_EQ(j["culled"], 300u + probes - c.count_from(11));
  EXPECT_EQ(link(j, 12, 11)["delivered"], 300u);
  EXPECT_EQ(link(j, 12, 13)["delivered"], 300u);
  EXPECT_EQ(j["totals"]["sent"], 300u + probes + c.count_from(11) + 2 * 300u);

  // One medium.frame trace record per decision, agreeing with the statistics, and one
  // medium.rx per frame that came in (these test frames are no CAMs: no station or gdt).
  std::map<std::pair<int, int>, std::pair<std::uint64_t, std::uint64_t>> traced;  // ok, dropped
  std::map<int, std::uint64_t> came_in;
  std::ifstream lines(trace);
  std::string line;
  while (std::getline(lines, line)) {
    const auto r = nlohmann::json::parse(line);
    ASSERT_EQ(r["proc"], "radio-medium");
    if (r["ev"] == "medium.rx") {
      EXPECT_FALSE(r.contains("gdt")) << line;
      ++came_in[r["src"].get<int>()];
      continue;
    }
    ASSERT_EQ(r["ev"], "medium.frame");
    auto& n = traced[std::make_pair(r["src"].get<int>(), r["dst"].get<int>())];
    (r["ok"].get<bool>() ? n.first : n.second)++;
  }
  EXPECT_EQ(came_in[11], 300u + probes);
  EXPECT_EQ(came_in[12], 300u);
  const auto a_b = traced[std::make_pair(11, 12)];
  const auto a_c = traced[std::make_pair(11, 13)];
  const auto b_c = traced[std::make_pair(12, 13)];
  EXPECT_EQ(a_b.first, link(j, 11, 12)["delivered"].get<std::uint64_t>());
  EXPECT_EQ(a_c.first, c.count_from(11));
  EXPECT_EQ(a_c.second, 0u);  // culled links are not decided, so not traced
  EXPECT_EQ(b_c.first, 300u);
}

// The ideal channel in both places: the kernel bridge (what auto picks for it) and the
// program's own forwarding (--forwarding user, what every other channel gets).
void ideal_loses_none_of_ten_thousand_frames(VethMediumIT& t, MediumProcess& medium,
                                             const fs::path& stats, const char* forwarding);

TEST_F(VethMediumIT, IdealModelInTheKernelLosesNoneOfTenThousandFrames) {
  const fs::path scenario = write_scenario(R"({ "model": "ideal" })");
  const fs::path stats = scenario.parent_path() / "ideal-stats.json";
  MediumProcess medium(args(scenario, stats, free_udp_port()));
  ASSERT_TRUE(medium.wait_ready());
  const auto links = host_links_with_prefix();
  EXPECT_NE(std::find(links.begin(), links.end(), std::string(kPrefix) + "br"), links.end())
      << "no bridge " << kPrefix << "br";
  ideal_loses_none_of_ten_thousand_frames(*this, medium, stats, "kernel");
}

TEST_F(VethMediumIT, IdealModelInTheProgramLosesNoneOfTenThousandFrames) {
  const fs::path scenario = write_scenario(R"({ "model": "ideal" })");
  const fs::path stats = scenario.parent_path() / "ideal-user-stats.json";
  auto argv = args(scenario, stats, free_udp_port());
  argv.insert(argv.end(), {"--forwarding", "user"});
  MediumProcess medium(argv);
  ASSERT_TRUE(medium.wait_ready());
  ideal_loses_none_of_ten_thousand_frames(*this, medium, stats, "radio-medium");
}

void ideal_loses_none_of_ten_thousand_frames(VethMediumIT& t, MediumProcess& medium,
                                             const fs::path& stats, const char* forwarding) {
  const auto& ns_ = t.namespaces();
  Station a(11, ns_[0]->name()), b(12, ns_[1]->name()), c(13, ns_[2]->name());
  std::vector<Station*> all{&a, &b, &c};
  constexpr std::uint32_t kFrames = 10'000;
  send_paced(a, kFrames, all, {&b, &c});
  EXPECT_EQ(b.count_from(11), kFrames);
  EXPECT_EQ(c.count_from(11), kFrames);
  EXPECT_EQ(b.out_of_order_from(11), 0u);
  EXPECT_EQ(c.out_of_order_from(11), 0u);

  ASSERT_TRUE(WIFEXITED(medium.stop()));
  const auto j = read_json(stats);
  expect_links_add_up(j);
  EXPECT_EQ(link(j, 11, 12)["delivered"], kFrames);
  EXPECT_EQ(link(j, 11, 13)["delivered"], kFrames);
  EXPECT_EQ(j["totals"]["sent"], 2 * kFrames);
  EXPECT_EQ(j["totals"]["delivered"], 2 * kFrames);
  EXPECT_EQ(j["forwarding"], forwarding);
  if (j.contains("kernel_dropped")) {
    for (const auto& [station, n] : j["kernel_dropped"].items()) {
      EXPECT_EQ(n, 0u) << "station " << station;
    }
  }
}

// In the kernel the program reads the frames late, in blocks: the trace still stamps each
// `medium.rx` with the time the kernel received it, and decides (`medium.frame`) every link.
TEST_F(VethMediumIT, IdealModelInTheKernelTracesEachFrameAtItsKernelTime) {
  const fs::path scenario = write_scenario(R"({ "model": "ideal" })");
  const fs::path stats = scenario.parent_path() / "trace-stats.json";
  const fs::path trace = scenario.parent_path() / "kernel-trace.jsonl";
  fs::remove(trace);
  auto argv = args(scenario, stats, free_udp_port());
  argv.insert(argv.end(), {"--trace", trace.string()});
  MediumProcess medium(argv);
  ASSERT_TRUE(medium.wait_ready());
  Station a(11, ns_[0]->name()), b(12, ns_[1]->name()), c(13, ns_[2]->name());
  std::vector<Station*> all{&a, &b, &c};
  const auto unix_now = [] {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
  };
  // Ten frames, each sent only once the one before has reached both others: every frame's
  // kernel time lies between its send and its arrival, which the test knows.
  std::vector<std::pair<std::int64_t, std::int64_t>> windows;
  for (std::uint32_t i = 0; i < 10; ++i) {
    const std::int64_t before = unix_now();
    send_paced(a, 1, all, {&b, &c});
    windows.emplace_back(before, unix_now());
  }
  ASSERT_EQ(b.count_from(11), 10u);
  ASSERT_EQ(c.count_from(11), 10u);
  ASSERT_TRUE(WIFEXITED(medium.stop()));

  std::vector<std::int64_t> came_in;
  std::map<int, std::uint64_t> decided;
  std::ifstream lines(trace);
  std::string line;
  while (std::getline(lines, line)) {
    const auto r = nlohmann::json::parse(line);
    if (r["ev"] == "medium.rx") {
      EXPECT_EQ(r["src"], 11);
      came_in.push_back(r["ts"].get<std::int64_t>());
    } else if (r["ev"] == "medium.frame") {
      EXPECT_EQ(r["src"], 11);
      EXPECT_TRUE(r["ok"].get<bool>());
      ++decided[r["dst"].get<int>()];
    }
  }
  ASSERT_EQ(came_in.size(), 10u);
  std::sort(came_in.begin(), came_in.end());
  for (std::size_t i = 0; i < 10; ++i) {
    EXPECT_GE(came_in[i], windows[i].first) << "frame " << i;
    EXPECT_LE(came_in[i], windows[i].second) << "frame " << i;
  }
  EXPECT_EQ(decided[12], 10u);
  EXPECT_EQ(decided[13], 10u);
}

TEST_F(VethMediumIT, KernelForwardingOfAChannelThatDecidesIsRefused) {
  const fs::path scenario = write_scenario(R"({ "model": "range", "range_m": 300 })");
  auto argv = args(scenario, scenario.parent_path() / "refused.json", free_udp_port());
  argv.insert(argv.end(), {"--forwarding", "kernel"});
  MediumProcess medium(argv);
  EXPECT_FALSE(medium.wait_ready());
  const int status = medium.stop();
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
}

TEST_F(VethMediumIT, RestartRemovesWhatACrashedRunLeft) {
  const fs::path scenario = write_scenario(R"({ "model": "ideal" })");
  const fs::path stats = scenario.parent_path() / "crash-stats.json";
  {
    MediumProcess crashed(args(scenario, stats, free_udp_port()));
    ASSERT_TRUE(crashed.wait_ready());
    crashed.stop(SIGKILL);
  }
  EXPECT_EQ(host_links_with_prefix().size(), 4u) << "SIGKILL leaves the pairs and the bridge";
  EXPECT_TRUE(ns_[0]->has(kStationIfname));
  MediumProcess again(args(scenario, stats, free_udp_port()));
  ASSERT_TRUE(again.wait_ready()) << "a restart must clear the leftovers and start";
  Station a(11, ns_[0]->name()), b(12, ns_[1]->name());
  std::vector<Station*> all{&a, &b};
  send_paced(a, 10, all, {&b});
  EXPECT_EQ(b.count_from(11), 10u);
  EXPECT_TRUE(WIFEXITED(again.stop(SIGINT)));
}

TEST_F(VethMediumIT, SighupGivesARestartedStationARadioInItsNewNamespace) {
  const fs::path scenario = write_scenario(R"({ "model": "ideal" })");
  const fs::path stats = scenario.parent_path() / "hup-stats.json";
  MediumProcess medium(args(scenario, stats, free_udp_port()));
  ASSERT_TRUE(medium.wait_ready());
  ns_[0]->replace();
  EXPECT_FALSE(ns_[0]->has(kStationIfname));
  medium.signal(SIGHUP);
  const auto deadline = Clock::now() + 10s;
  while (!ns_[0]->has(kStationIfname) && Clock::now() < deadline)
    std::this_thread::sleep_for(20ms);
  ASSERT_TRUE(ns_[0]->has(kStationIfname)) << "no wlan0 in the new namespace after SIGHUP";

  // Both ways, and the station that kept its namespace still hears the third.
  Station a(11, ns_[0]->name()), b(12, ns_[1]->name()), c(13, ns_[2]->name());
  std::vector<Station*> all{&a, &b, &c};
  send_paced(a, 100, all, {&b, &c});
  send_paced(b, 100, all, {&a, &c});
  EXPECT_EQ(b.count_from(11), 100u);
  EXPECT_EQ(c.count_from(11), 100u);
  EXPECT_EQ(a.count_from(12), 100u);
  EXPECT_EQ(c.count_from(12), 100u);

  // A second SIGHUP with nothing moved changes nothing.
  medium.signal(SIGHUP);
  send_paced(c, 50, all, {&a, &b});
  EXPECT_EQ(a.count_from(13), 50u);
  EXPECT_EQ(b.count_from(13), 50u);
  ASSERT_TRUE(WIFEXITED(medium.stop()));
  EXPECT_EQ(host_links_with_prefix().size(), 0u);
}

TEST_F(VethMediumIT, MissingNamespaceFailsWithAClearMessageAndLeavesNothing) {
  const fs::path scenario = write_scenario(R"({ "model": "ideal" })");
  MediumProcess medium({"--scenario", scenario.string(), "--mode", "veth", "--prefix", kPrefix,
                        "--stations", "11=" + ns_[0]->name() + ",12=tbrit-does-not-exist",
                        "--log-level", "warn"});
  EXPECT_FALSE(medium.wait_ready());
  const int status = medium.stop();
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 3);
}

// --- Station-hosts (issue 33): one namespace, one veth pair, several pooled stations ---------

// 11 is a full station at x = 10 m; 21, 22, 23 are pooled at 60, 110 and 160 m.
fs::path write_pooled_scenario(const std::string& channel) {
  const fs::path dir = fs::temp_directory_path() / ("radio-it-" + kTag);
  fs::create_directories(dir);
  const fs::path file = dir / "pooled-scenario.json";
  std::ofstream(file) << R"({
  "name": "radio-it-pooled",
  "map": { "type": "straight", "lanes": 2, "lane_width": 3.5, "length": 2000 },
  "origin": { "lat": 41.1, "lon": 29.0, "alt": 60 },
  "start_time": "2025-06-02T09:00:00Z",
  "channel": )" << channel
                      << R"(,
  "vehicles": [
    { "id": "full", "station_id": 11, "spawn": { "x": 10, "y": 0, "heading_deg": 90 }, "driver": "human" },
    { "id": "p1", "station_id": 21, "spawn": { "x": 60, "y": 0, "heading_deg": 90 }, "driver": { "type": "lane_follow", "speed_profile": [{ "t": 0, "speed": 0 }] }, "station": { "kind": "pooled" } },
    { "id": "p2", "station_id": 22, "spawn": { "x": 110, "y": 0, "heading_deg": 90 }, "driver": { "type": "lane_follow", "speed_profile": [{ "t": 0, "speed": 0 }] }, "station": { "kind": "pooled" } },
    { "id": "p3", "station_id": 23, "spawn": { "x": 160, "y": 0, "heading_deg": 90 }, "driver": { "type": "lane_follow", "speed_profile": [{ "t": 0, "speed": 0 }] }, "station": { "kind": "pooled" } }
  ]
})";
  return file;
}

std::vector<std::string> pooled_args(const fs::path& scenario, const fs::path& stats,
                                     unsigned short port, const std::string& full_ns,
                                     const std::string& host_ns) {
  return {"--scenario",  scenario.string(),
          "--mode",      "veth",
          "--prefix",    kPrefix,
          "--stations",  "11=" + full_ns,
          "--pooled",    host_ns + "=21,p2,23",
          "--stats",     stats.string(),
          "--positions", "udp://127.0.0.1:" + std::to_string(port),
          "--log-level", "warn"};
}

void send_state(unsigned short port, StationId id, double x) {
  wire::VehicleState s;
  s.station_id = id;
  s.sim_time_ns = 1'000'000'000;
  s.position = {x, 0.0, 0.0};
  const auto bytes = wire::encode_batch({&s, 1});
  const int udp = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(port);
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(
      ::sendto(udp, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to),
      static_cast<ssize_t>(bytes.size()));
  ::close(udp);
}

// Polls @p a and @p h until @p done or 5 s.
template <typename Done>
void poll_until(Station& a, RawHost& h, Done done) {
  const auto deadline = Clock::now() + 5s;
  while (!done() && Clock::now() < deadline) {
    a.poll_frames(2ms);
    h.poll(2ms);
  }
  for (int i = 0; i < 10; ++i) {  // and a little longer for frames that must not come
    a.poll_frames(5ms);
    h.poll(5ms);
  }
}

bool has_link(const nlohmann::json& stats, StationId from, StationId to) {
  for (const auto& l : stats["links"])
    if (l["from"] == from && l["to"] == to)
      return true;
  return false;
}

TEST_F(VethMediumIT, PooledHostInTheKernelIsAPortLikeAnyOther) {
  const fs::path scenario = write_pooled_scenario(R"({ "model": "ideal" })");
  const fs::path stats = scenario.parent_path() / "pooled-kernel-stats.json";
  MediumProcess medium(
      pooled_args(scenario, stats, free_udp_port(), ns_[0]->name(), ns_[1]->name()));
  ASSERT_TRUE(medium.wait_ready());
  EXPECT_TRUE(ns_[1]->has(kStationIfname));
  Station a(11, ns_[0]->name());
  RawHost h(ns_[1]->name());

  // A frame with a pooled MAC reaches the full station, attributed to that pooled station.
  for (std::uint32_t i = 0; i < 20; ++i)
    h.send_as(22, i);
  // The full station's frames reach the host plain, once each.
  for (std::uint32_t i = 0; i < 20; ++i)
    a.send(i);
  poll_until(a, h, [&] { return a.count_from(22) == 20 && h.got.size() >= 20; });
  EXPECT_EQ(a.count_from(22), 20u);
  ASSERT_EQ(h.got.size(), 20u);
  for (std::uint32_t i = 0; i < 20; ++i) {
    EXPECT_FALSE(h.got[i].pooled);
    EXPECT_EQ(h.got[i].from, 11u);
    EXPECT_EQ(h.got[i].seq, i);
  }
  h.send_as(99, 0);  // a MAC that names no station: the kernel forwards it, nobody counts it
  poll_until(a, h, [&] { return a.count_from(99) == 1; });

  ASSERT_TRUE(WIFEXITED(medium.stop()));
  const auto j = read_json(stats);
  expect_links_add_up(j);
  EXPECT_EQ(j["forwarding"], "kernel");
  EXPECT_EQ(link(j, 22, 11)["delivered"], 20u);
  for (StationId p : {21u, 22u, 23u})
    EXPECT_EQ(link(j, 11, p)["delivered"], 20u) << p;
  // Between the host's own stations the kernel carries nothing: the host loops them back.
  EXPECT_FALSE(has_link(j, 22, 21));
  EXPECT_FALSE(has_link(j, 22, 23));
  EXPECT_EQ(j["unknown_sender"], 1u);
  EXPECT_EQ(j["totals"]["sent"], 20u + 3 * 20u);
}

TEST_F(VethMediumIT, PooledHostInTheProgramGetsOneFrameListingItsStationsInRange) {
  const fs::path scenario = write_pooled_scenario(R"({ "model": "range", "range_m": 300 })");
  const fs::path stats = scenario.parent_path() / "pooled-user-stats.json";
  const unsigned short port = free_udp_port();
  MediumProcess medium(pooled_args(scenario, stats, port, ns_[0]->name(), ns_[1]->name()));
  ASSERT_TRUE(medium.wait_ready());
  Station a(11, ns_[0]->name());
  RawHost h(ns_[1]->name());

  // 23 moves to 1500 m: out of everyone's range. Probe until a delivery leaves it out.
  send_state(port, 23, 1500.0);
  std::uint32_t probes = 0;
  const auto moved = [&] {
    return !h.got.empty() && h.got.back().listed == std::vector<StationId>{21, 22};
  };
  const auto deadline = Clock::now() + 5s;
  while (!moved() && Clock::now() < deadline) {
    a.send(1000 + probes++);
    h.poll(10ms);
  }
  ASSERT_TRUE(moved()) << "the position update never took effect";
  h.got.clear();

  for (std::uint32_t i = 0; i < 20; ++i)
    a.send(i);
  for (std::uint32_t i = 0; i < 20; ++i)
    h.send_as(21, i);
  for (std::uint32_t i = 0; i < 5; ++i)
    h.send_as(23, i);  // heard by nobody
  h.send_as(99, 0);    // no such station: dropped
  poll_until(a, h, [&] { return a.count_from(21) == 20 && h.got.size() >= 40; });

  EXPECT_EQ(a.count_from(21), 20u);
  EXPECT_EQ(a.count_from(23), 0u);
  EXPECT_EQ(a.count_from(99), 0u);
  std::uint32_t from_full = 0, from_own = 0;
  for (const auto& g : h.got) {
    ASSERT_TRUE(g.pooled) << "a plain frame on a host's port in the program's forwarding";
    EXPECT_EQ(g.outer_src, station_mac(g.from));
    if (g.from == 11) {
      EXPECT_EQ(g.listed, (std::vector<StationId>{21, 22}));
      EXPECT_EQ(g.seq, from_full++);
    } else {
      EXPECT_EQ(g.from, 21u);
      EXPECT_EQ(g.listed, std::vector<StationId>{22});  // its own host's other station in range
      EXPECT_EQ(g.seq, from_own++);
    }
  }
  EXPECT_EQ(from_full, 20u);
  EXPECT_EQ(from_own, 20u);

  ASSERT_TRUE(WIFEXITED(medium.stop()));
  const auto j = read_json(stats);
  expect_links_add_up(j);
  EXPECT_EQ(j["forwarding"], "radio-medium");
  EXPECT_EQ(j["unknown_sender"], 1u);
  EXPECT_EQ(link(j, 21, 11)["delivered"], 20u);
  EXPECT_EQ(link(j, 21, 22)["delivered"], 20u);
  EXPECT_EQ(link(j, 11, 22)["delivered"], 20u + probes);
  EXPECT_FALSE(has_link(j, 23, 11));  // 1.5 km away: culled, not a link
  // Culled: 21's 20 frames to 23, 23's 5 to each of 11, 21, 22, and a's frames to 23 after
  // the move.
  EXPECT_GE(j["culled"].get<std::uint64_t>(), 20u + 15u + 20u);
}

TEST_F(VethMediumIT, PooledHostsAreRefusedOnHwsimAndCheckedAgainstTheScenario) {
  const fs::path scenario = write_pooled_scenario(R"({ "model": "ideal" })");
  auto run = [&](std::vector<std::string> argv) {
    MediumProcess medium(argv);
    EXPECT_FALSE(medium.wait_ready());
    const int status = medium.stop();
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  auto argv = pooled_args(scenario, scenario.parent_path() / "x.json", free_udp_port(),
                          ns_[0]->name(), ns_[1]->name());
  argv[3] = "hwsim";  // --mode hwsim
  EXPECT_EQ(run(argv), 1);
  EXPECT_EQ(run({"--scenario", scenario.string(), "--mode", "veth", "--prefix", kPrefix,
                 "--stations", "11=" + ns_[0]->name(), "--pooled", ns_[1]->name() + "=21,11"}),
            1);  // 11 is a full station already
  EXPECT_EQ(run({"--scenario", scenario.string(), "--mode", "veth", "--prefix", kPrefix, "--pooled",
                 ns_[1]->name() + "=21,777"}),
            1);  // not in the scenario
  EXPECT_EQ(run({"--scenario", scenario.string(), "--mode", "veth", "--prefix", kPrefix, "--pooled",
                 ns_[1]->name() + "=21,full"}),
            1);  // a full station's vehicle
  EXPECT_EQ(run({"--scenario", scenario.string(), "--mode", "veth", "--prefix", kPrefix, "--pooled",
                 ns_[1]->name()}),
            1);
}

}  // namespace
}  // namespace tb::emu::radio
