// Integration test of the federated medium (issue 35): two nodes, each a network namespace with
// its own radio-medium (from $TESTBED_BIN), joined by a veth pair with 10.x addresses; each node
// has two station namespaces. Frames are sent on wlan0 with AF_PACKET. Runs as root.

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "network-emulator/radio/rtnl.hpp"
#include "network-emulator/radio/tests/medium_it_support.hpp"

namespace tb::emu::radio {
namespace {

namespace fs = std::filesystem;

// Stations on a straight road (spawn x, the channel's positions until a state arrives):
// node a: 11 at x=10, 12 at x=110; node b: 21 at x=210, 22 at x=460. Range model, 300 m: a
// frame from 11 reaches 12 (100 m) and 21 (200 m), never 22 (450 m).
fs::path write_scenario(const fs::path& dir, const std::string& channel) {
  const fs::path file = dir / "scenario.json";
  std::ofstream(file) << R"({
  "name": "federation-it",
  "map": { "type": "straight", "lanes": 2, "lane_width": 3.5, "length": 2000 },
  "origin": { "lat": 41.1, "lon": 29.0, "alt": 60 },
  "start_time": "2025-06-02T09:00:00Z",
  "channel": )" << channel
                      << R"(,
  "vehicles": [
    { "id": "a1", "station_id": 11, "spawn": { "x": 10, "y": 0, "heading_deg": 90 }, "driver": "human" },
    { "id": "a2", "station_id": 12, "spawn": { "x": 110, "y": 0, "heading_deg": 90 }, "driver": "human" },
    { "id": "b1", "station_id": 21, "spawn": { "x": 210, "y": 0, "heading_deg": 90 }, "driver": "human" },
    { "id": "b2", "station_id": 22, "spawn": { "x": 460, "y": 0, "heading_deg": 90 }, "driver": "human" }
  ]
})";
  return file;
}

std::string read_file(const fs::path& f) {
  std::ifstream in(f);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Two node namespaces joined by a veth pair (10.77.0.1 and .2), and a station namespace for
// each station.
class FederationIT : public ::testing::Test {
 protected:
  void SetUp() override {
    if (::geteuid() != 0)
      GTEST_SKIP() << "needs root (network namespaces, veth)";
    test_support::remove_stale_netns({"tbfa", "tbfb", "tbfs"});
    dir_ = fs::temp_directory_path() / ("federation-it-" + kTag);
    fs::create_directories(dir_);
    node_a_ = std::make_unique<TestNetns>("tbfa" + kTag);
    node_b_ = std::make_unique<TestNetns>("tbfb" + kTag);
    for (const char* s : {"11", "12", "21", "22"})
      st_ns_.push_back(std::make_unique<TestNetns>("tbfs" + kTag + "-" + s));
    const std::string a = node_a_->name(), b = node_b_->name();
    const std::string cmd = "ip link add fed0 netns " + a + " type veth peer name fed0 netns " + b +
                            " && ip -n " + a + " addr add 10.77.0.1/24 dev fed0 && ip -n " + b +
                            " addr add 10.77.0.2/24 dev fed0 && ip -n " + a +
                            " link set fed0 up && ip -n " + b + " link set fed0 up && ip -n " + a +
                            " link set lo up && ip -n " + b + " link set lo up";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ofstream(dir_ / "placement.json") << R"({"nodes": [
      {"name": "a", "medium": "10.77.0.1:4730", "stations": [11, 12]},
      {"name": "b", "medium": "10.77.0.2:4730", "stations": [21, 22]}]})";
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  std::vector<std::string> args(const fs::path& scenario, const std::string& node,
                                const std::string& forwarding) {
    const bool a = node == "a";
    const auto& s = st_ns_;
    return {"--scenario",
            scenario.string(),
            "--mode",
            "veth",
            "--prefix",
            kPrefix,
            "--forwarding",
            forwarding,
            "--stations",
            a ? "11=" + s[0]->name() + ",12=" + s[1]->name()
              : "21=" + s[2]->name() + ",22=" + s[3]->name(),
            "--federation",
            (dir_ / "placement.json").string(),
            "--node",
            node,
            "--positions",
            "udp://127.0.0.1:4702",
            "--stats",
            (dir_ / ("stats-" + node + ".json")).string(),
            "--trace",
            (dir_ / ("trace-" + node + ".jsonl")).string(),
            "--log-level",
            "info"};
  }
  std::unique_ptr<MediumProcess> start(const fs::path& scenario, const std::string& node,
                                       const std::string& forwarding) {
    auto p = std::make_unique<MediumProcess>(args(scenario, node, forwarding),
                                             node == "a" ? node_a_->name() : node_b_->name());
    EXPECT_TRUE(p->wait_ready()) << p->output();
    return p;
  }
  // Until both media have heard from each other (heartbeats every 0.5 s).
  void wait_federated(MediumProcess& a, MediumProcess& b) {
    const auto deadline = Clock::now() + 10s;
    while (Clock::now() < deadline) {
      if (a.output().find("peer node b is up") != std::string::npos &&
          b.output().find("peer node a is up") != std::string::npos)
        return;
      std::this_thread::sleep_for(50ms);
    }
    FAIL() << "the media did not hear from each other:\n" << a.output() << b.output();
  }
  std::vector<nlohmann::json> trace(const std::string& node, const std::string& event) {
    std::vector<nlohmann::json> out;
    std::ifstream in(dir_ / ("trace-" + node + ".jsonl"));
    for (std::string line; std::getline(in, line);) {
      auto j = nlohmann::json::parse(line, nullptr, false);
      if (!j.is_discarded() && j.value("ev", "") == event)
        out.push_back(std::move(j));
    }
    return out;
  }
  void exchange_in_range(const std::string& forwarding, const std::string& channel, bool ideal);
  void pooled_across_nodes(const std::string& forwarding, const std::string& channel, bool ideal);

  fs::path dir_;
  std::unique_ptr<TestNetns> node_a_, node_b_;
  std::vector<std::unique_ptr<TestNetns>> st_ns_;
};

void FederationIT::exchange_in_range(const std::string& forwarding, const std::string& channel,
                                     bool ideal) {
  const auto scenario = write_scenario(dir_, channel);
  auto a = start(scenario, "a", forwarding);
  auto b = start(scenario, "b", forwarding);
  wait_federated(*a, *b);
  Station s11(11, st_ns_[0]->name()), s12(12, st_ns_[1]->name()), s21(21, st_ns_[2]->name()),
      s22(22, st_ns_[3]->name());
  std::vector<Station*> all{&s11, &s12, &s21, &s22};
  constexpr std::uint32_t kFrames = 300;
  // From node a to node b: 21 in range (200 m), 22 beyond (450 m) unless the channel is ideal.
  std::vector<Station*> expect{&s12, &s21};
  if (ideal)
    expect.push_back(&s22);
  send_paced(s11, kFrames, all, expect);
  EXPECT_EQ(s12.count_from(11), kFrames);
  EXPECT_EQ(s21.count_from(11), kFrames);
  EXPECT_EQ(s22.count_from(11), ideal ? kFrames : 0u);
  EXPECT_EQ(s21.out_of_order_from(11), 0u);
  // And back: from 21 (node b) to 11 (200 m) and 12 (100 m) on node a.
  send_paced(s21, kFrames, all, {&s11, &s12, &s22});
  EXPECT_EQ(s11.count_from(21), kFrames);
  EXPECT_EQ(s12.count_from(21), kFrames);
  EXPECT_EQ(s22.count_from(21), kFrames);  // local on b, 250 m
  ASSERT_EQ(WEXITSTATUS(a->stop()), 0);
  ASSERT_EQ(WEXITSTATUS(b->stop()), 0);

  // The hop has its own trace stage at the receiving medium: one medium.hop per frame from the
  // other node, sent before it was received; the kernel took the datagram in between (its
  // stamp splits the hop into the way and the receiving medium's wake-up).
  const auto hops_b = trace("b", "medium.hop");
  ASSERT_EQ(hops_b.size(), kFrames);
  for (const auto& h : hops_b) {
    EXPECT_EQ(h["src"], 11);
    EXPECT_EQ(h["node"], "a");
    const auto tx = h["tx_ns"].get<std::int64_t>();
    const auto kernel = h["kernel_rx_ns"].get<std::int64_t>();
    const auto read = h["ts"].get<std::int64_t>();
    EXPECT_GT(kernel, tx);
    EXPECT_GE(read, kernel);
  }
  EXPECT_EQ(trace("a", "medium.hop").size(), kFrames);
  // medium.rx only where the frame was put on the air.
  std::size_t rx_of_11_at_b = 0;
  for (const auto& r : trace("b", "medium.rx"))
    rx_of_11_at_b += r["src"] == 11;
  EXPECT_EQ(rx_of_11_at_b, 0u);
  // The receiving node's channel decided (and counted) the links of the remote sender.
  const auto stats_b = nlohmann::json::parse(read_file(dir_ / "stats-b.json"));
  bool link_11_21 = false;
  for (const auto& l : stats_b["links"])
    if (l["from"] == 11 && l["to"] == 21) {
      link_11_21 = true;
      EXPECT_EQ(l["delivered"], kFrames);
    }
  EXPECT_TRUE(link_11_21) << stats_b.dump();
  EXPECT_EQ(stats_b["federation"]["frames_in"], kFrames);
  EXPECT_EQ(stats_b["federation"]["rejected"], 0);
}

TEST_F(FederationIT, RangeModelInTheProgramDeliversAcrossNodesWithinRangeOnly) {
  exchange_in_range("user", R"({ "model": "range", "range_m": 300 })", false);
}

TEST_F(FederationIT, IdealModelInTheKernelDeliversAcrossNodesToEveryStation) {
  exchange_in_range("kernel", R"({ "model": "ideal" })", true);
}

TEST_F(FederationIT, APeerThatGoesAwayIsLoggedAndLocalDeliveryGoesOn) {
  const auto scenario = write_scenario(dir_, R"({ "model": "range", "range_m": 300 })");
  // A third node whose medium's name does not resolve (swarm's DNS does not know it yet).
  std::ofstream(dir_ / "placement.json") << R"({"nodes": [
      {"name": "a", "medium": "10.77.0.1:4730", "stations": [11, 12]},
      {"name": "b", "medium": "10.77.0.2:4730", "stations": [21, 22]},
      {"name": "c", "medium": "tb-no-such-node.invalid:4730", "stations": []}]})";
  auto a = start(scenario, "a", "user");
  auto b = start(scenario, "b", "user");
  wait_federated(*a, *b);
  b->stop(SIGKILL);  // its veths stay behind; its restart below removes them
  b.reset();
  // a's next heartbeat finds nothing listening on 10.77.0.2:4730 (ICMP port unreachable).
  const auto deadline = Clock::now() + 6s;
  std::string log;
  while (Clock::now() < deadline) {
    log = a->output();
    if (log.find("peer node b is down") != std::string::npos)
      break;
    std::this_thread::sleep_for(50ms);
  }
  ASSERT_NE(log.find("peer node b is down"), std::string::npos) << log;
  EXPECT_NE(log.find("connection refused"), std::string::npos) << log;
  EXPECT_NE(log.find("peer node c is down: its medium's name tb-no-such-node.invalid does not "
                     "resolve"),
            std::string::npos)
      << log;
  // Said once, however many frames and heartbeats fail after.
  Station s11(11, st_ns_[0]->name()), s12(12, st_ns_[1]->name());
  std::vector<Station*> all{&s11, &s12};
  send_paced(s11, 200, all, {&s12});
  EXPECT_EQ(s12.count_from(11), 200u);
  std::this_thread::sleep_for(1s);
  log = a->output();
  std::size_t downs = 0;
  for (auto at = log.find("peer node b is down"); at != std::string::npos;
       at = log.find("peer node b is down", at + 1))
    ++downs;
  EXPECT_EQ(downs, 1u) << log;
  // b comes back: said again, and frames cross again.
  b = start(scenario, "b", "user");
  const auto back = Clock::now() + 6s;
  while (Clock::now() < back &&
         a->output().find("peer node b is up (heard from again)") == std::string::npos)
    std::this_thread::sleep_for(50ms);
  EXPECT_NE(a->output().find("peer node b is up (heard from again)"), std::string::npos)
      << a->output();
  Station s21(21, st_ns_[2]->name());
  all.push_back(&s21);
  send_paced(s11, 100, all, {&s12, &s21});
  EXPECT_EQ(s21.count_from(11), 100u);
}

// Pooled stations federate like full ones: node b runs 21 and a station-host with 22 (240 m
// from 11) and 23 (450 m from 11, 350 m from 12).
void FederationIT::pooled_across_nodes(const std::string& forwarding, const std::string& channel,
                                       bool ideal) {
  const fs::path scenario = dir_ / "pooled-scenario.json";
  const std::string pooled =
      R"(, "driver": { "type": "lane_follow", "speed_profile": [{ "t": 0, "speed": 0 }] }, "station": { "kind": "pooled" } })";
  std::ofstream(scenario) << R"({
  "name": "federation-it-pooled",
  "map": { "type": "straight", "lanes": 2, "lane_width": 3.5, "length": 2000 },
  "origin": { "lat": 41.1, "lon": 29.0, "alt": 60 },
  "start_time": "2025-06-02T09:00:00Z",
  "channel": )" << channel << R"(,
  "vehicles": [
    { "id": "a1", "station_id": 11, "spawn": { "x": 10, "y": 0, "heading_deg": 90 }, "driver": "human" },
    { "id": "a2", "station_id": 12, "spawn": { "x": 110, "y": 0, "heading_deg": 90 }, "driver": "human" },
    { "id": "b1", "station_id": 21, "spawn": { "x": 210, "y": 0, "heading_deg": 90 }, "driver": "human" },
    { "id": "p2", "station_id": 22, "spawn": { "x": 250, "y": 0, "heading_deg": 90 })"
                          << pooled << R"(,
    { "id": "p3", "station_id": 23, "spawn": { "x": 460, "y": 0, "heading_deg": 90 })"
                          << pooled << R"(
  ]
})";
  std::ofstream(dir_ / "placement.json") << R"({"nodes": [
      {"name": "a", "medium": "10.77.0.1:4730", "stations": [11, 12]},
      {"name": "b", "medium": "10.77.0.2:4730", "stations": [21], "pooled": [22, 23],
       "station_hosts": 1}]})";
  auto a = start(scenario, "a", forwarding);
  auto b_args = args(scenario, "b", forwarding);
  for (std::size_t i = 0; i < b_args.size(); ++i)
    if (b_args[i] == "--stations")
      b_args[i + 1] = "21=" + st_ns_[2]->name();
  b_args.push_back("--pooled");
  b_args.push_back(st_ns_[3]->name() + "=22,23");
  auto b = std::make_unique<MediumProcess>(b_args, node_b_->name());
  ASSERT_TRUE(b->wait_ready()) << b->output();
  wait_federated(*a, *b);
  Station s11(11, st_ns_[0]->name()), s12(12, st_ns_[1]->name());
  RawHost host(st_ns_[3]->name());
  constexpr std::uint32_t kFrames = 20;
  for (std::uint32_t i = 0; i < kFrames; ++i) {
    s11.send(i);
    host.send_as(22, i);
    host.send_as(23, i);
  }
  const auto deadline = Clock::now() + 5s;
  const auto from11 = [&] {
    return std::count_if(host.got.begin(), host.got.end(),
                         [](const RawHost::Got& g) { return g.from == 11; });
  };
  while (Clock::now() < deadline && (s11.count_from(22) < kFrames || from11() < kFrames)) {
    s11.poll_frames(2ms);
    s12.poll_frames(2ms);
    host.poll(2ms);
  }
  for (int i = 0; i < 20; ++i) {  // a little longer for frames that must not come
    s11.poll_frames(5ms);
    s12.poll_frames(5ms);
    host.poll(5ms);
  }
  // The pooled station's frames, attributed by source MAC, reach node a's stations in range.
  EXPECT_EQ(s11.count_from(22), kFrames);
  EXPECT_EQ(s12.count_from(22), kFrames);
  EXPECT_EQ(s11.count_from(23), ideal ? kFrames : 0u);
  EXPECT_EQ(s12.count_from(23), ideal ? kFrames : 0u);
  // Node a's station reaches the host: plain from the bridge, or one TBPD listing those in range.
  EXPECT_EQ(from11(), kFrames);
  for (const auto& g : host.got)
    if (g.from == 11) {
      EXPECT_EQ(g.pooled, !ideal);
      if (!ideal) {
        EXPECT_EQ(g.listed, std::vector<StationId>{22});
      }
    }
  ASSERT_EQ(WEXITSTATUS(a->stop()), 0);
  ASSERT_EQ(WEXITSTATUS(b->stop()), 0);
  const auto stats_b = nlohmann::json::parse(read_file(dir_ / "stats-b.json"));
  // Frames sent to at least one peer: 22's, and 23's only where everyone hears.
  EXPECT_EQ(stats_b["federation"]["frames_out"], ideal ? 2 * kFrames : kFrames);
  if (!ideal) {  // 23's frames: no station of node a within 300 m, so node a was not sent them
    EXPECT_EQ(stats_b["federation"]["peers_skipped"], kFrames);
  }
}

TEST_F(FederationIT, PooledStationsInTheProgramFederateByTheirOwnMac) {
  pooled_across_nodes("user", R"({ "model": "range", "range_m": 300 })", false);
}

TEST_F(FederationIT, PooledStationsInTheKernelFederateByTheirOwnMac) {
  pooled_across_nodes("kernel", R"({ "model": "ideal" })", true);
}

TEST_F(FederationIT, StationsThatAreNotTheNodesEntryAreRefusedNamingTheStation) {
  const auto scenario = write_scenario(dir_, R"({ "model": "range", "range_m": 300 })");
  auto bad = args(scenario, "a", "user");
  for (std::size_t i = 0; i < bad.size(); ++i)
    if (bad[i] == "--stations")
      bad[i + 1] = "11=" + st_ns_[0]->name() + ",21=" + st_ns_[2]->name();
  MediumProcess p(bad, node_a_->name());
  EXPECT_FALSE(p.wait_ready());
  const std::string log = p.output();
  EXPECT_EQ(WEXITSTATUS(p.stop()), 1);
  EXPECT_NE(log.find("station 21"), std::string::npos) << log;
  EXPECT_NE(log.find("node b"), std::string::npos) << log;
  EXPECT_FALSE(st_ns_[0]->has(kStationIfname));
}

}  // namespace
}  // namespace tb::emu::radio
