// radio-federation-bench: the federated medium's hop (issue 35) — how long a frame takes from a
// station's wlan0 on node a to a station's wlan0 on node b, through two real radio-medium
// processes, each in its own node namespace, joined by a veth pair. Needs root and
// $TESTBED_BIN (or --bin). Frames go one at a time (the next after the previous arrived or was
// given up), each stamped with CLOCK_REALTIME when sent; the receiver subtracts it on arrival.
// Also the hop's own trace stage (medium.hop at b: rx - tx). Results: README.md, "Federated
// medium".
//
// radio-federation-bench [--samples N] [--repetitions R] [--forwarding user|kernel|both]
//                        [--frame-bytes B] [--link-mtu M]
// --frame-bytes: the frame's size on wlan0 (default 100, a CAM's order; up to 1514); --link-mtu:
// the MTU of the link between the nodes (default 1500; 1450 is a VXLAN overlay's, docker's
// default), so that a full-size frame's datagram is IP-fragmented as on the swarm's overlay.

#include <time.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "network-emulator/radio/tests/medium_it_support.hpp"

namespace radio = tb::emu::radio;
namespace fs = std::filesystem;
using namespace std::chrono_literals;

namespace {

std::int64_t realtime_ns() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return ts.tv_sec * 1'000'000'000LL + ts.tv_nsec;
}

std::string loadavg() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty())
    return 0;
  std::sort(v.begin(), v.end());
  const auto k = static_cast<std::size_t>(p / 100.0 * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(k, v.size() - 1)];
}

// One station's raw socket on wlan0 in its namespace; frames carry (seq, send time).
class Endpoint {
 public:
  Endpoint(radio::StationId id, const std::string& netns, std::size_t frame_bytes)
      : id_(id), frame_bytes_(frame_bytes) {
    socket_ = radio::in_netns(radio::NetnsFd::open(netns), [] {
      return std::make_unique<radio::PacketSocket>(radio::kStationIfname,
                                                   radio::kEthertypeGeoNetworking, 4 << 20);
    });
  }
  bool send(std::uint32_t seq) {
    std::vector<std::uint8_t> f(frame_bytes_, 0);
    std::fill_n(f.begin(), 6, 0xff);
    const auto src = radio::station_mac(id_);
    std::copy(src.begin(), src.end(), f.begin() + 6);
    f[12] = 0x89;
    f[13] = 0x47;
    const std::int64_t now = realtime_ns();
    std::memcpy(&f[14], &seq, 4);
    std::memcpy(&f[18], &now, 8);
    return socket_->send(f);
  }
  // The latency in µs of frame @p seq, or a negative number if it did not come within @p wait.
  double receive(std::uint32_t seq, std::chrono::milliseconds wait) {
    std::array<std::uint8_t, 2048> buf{};
    const auto deadline = std::chrono::steady_clock::now() + wait;
    while (std::chrono::steady_clock::now() < deadline) {
      pollfd p{socket_->fd(), POLLIN, 0};
      if (::poll(&p, 1, 10) <= 0)
        continue;
      const long n = socket_->receive(buf);
      const std::int64_t at = realtime_ns();
      if (n < 26)
        continue;
      std::uint32_t got;
      std::int64_t sent;
      std::memcpy(&got, &buf[14], 4);
      std::memcpy(&sent, &buf[18], 8);
      if (got == seq)
        return static_cast<double>(at - sent) / 1000.0;
    }
    return -1;
  }

 private:
  radio::StationId id_;
  std::size_t frame_bytes_;
  std::unique_ptr<radio::PacketSocket> socket_;
};

struct Result {
  std::vector<std::vector<double>> runs;  // end-to-end µs per run
  std::vector<double> hop;                // medium.hop rx - tx, µs
  std::size_t lost = 0;
};

Result measure(const std::string& forwarding, int repetitions, int samples, std::size_t frame_bytes,
               int link_mtu) {
  using radio::TestNetns;
  const fs::path dir = fs::temp_directory_path() / ("federation-bench-" + radio::kTag);
  fs::create_directories(dir);
  tb::test_support::remove_stale_netns({"tbfba", "tbfbb", "tbfbs"});
  TestNetns node_a("tbfba" + radio::kTag), node_b("tbfbb" + radio::kTag);
  TestNetns st_a("tbfbs" + radio::kTag + "a"), st_b("tbfbs" + radio::kTag + "b");
  const std::string a = node_a.name(), b = node_b.name();
  const std::string cmd = "ip link add fed0 netns " + a + " type veth peer name fed0 netns " + b +
                          " && ip -n " + a + " addr add 10.77.0.1/24 dev fed0 && ip -n " + b +
                          " addr add 10.77.0.2/24 dev fed0 && ip -n " + a +
                          " link set fed0 up && ip -n " + b + " link set fed0 up && ip -n " + a +
                          " link set lo up && ip -n " + b + " link set lo up && ip -n " + a +
                          " link set fed0 mtu " + std::to_string(link_mtu) + " && ip -n " + b +
                          " link set fed0 mtu " + std::to_string(link_mtu);
  if (std::system(cmd.c_str()) != 0)
    throw std::runtime_error("cannot join the node namespaces: " + cmd);
  const bool user = forwarding == "user";
  std::ofstream(dir / "scenario.json") << R"({
  "name": "federation-bench",
  "map": { "type": "straight", "lanes": 2, "lane_width": 3.5, "length": 2000 },
  "origin": { "lat": 41.1, "lon": 29.0, "alt": 60 },
  "start_time": "2025-06-02T09:00:00Z",
  "channel": )" << (user ? R"({ "model": "range", "range_m": 300 })" : R"({ "model": "ideal" })")
                                       << R"(,
  "vehicles": [
    { "id": "a1", "station_id": 11, "spawn": { "x": 10, "y": 0, "heading_deg": 90 }, "driver": "human" },
    { "id": "b1", "station_id": 21, "spawn": { "x": 210, "y": 0, "heading_deg": 90 }, "driver": "human" }
  ]
})";
  std::ofstream(dir / "placement.json") << R"({"nodes": [
      {"name": "a", "medium": "10.77.0.1:4730", "stations": [11]},
      {"name": "b", "medium": "10.77.0.2:4730", "stations": [21]}]})";
  auto args = [&](const std::string& node, const std::string& stations) {
    return std::vector<std::string>{"--scenario",   (dir / "scenario.json").string(),
                                    "--mode",       "veth",
                                    "--prefix",     radio::kPrefix,
                                    "--forwarding", forwarding,
                                    "--stations",   stations,
                                    "--federation", (dir / "placement.json").string(),
                                    "--node",       node,
                                    "--positions",  "udp://127.0.0.1:4702",
                                    "--trace",      (dir / ("trace-" + node + ".jsonl")).string(),
                                    "--log-level",  "info"};
  };
  Result r;
  {
    radio::MediumProcess ma(args("a", "11=" + st_a.name()), a);
    radio::MediumProcess mb(args("b", "21=" + st_b.name()), b);
    if (!ma.wait_ready() || !mb.wait_ready())
      throw std::runtime_error("radio-medium did not start:\n" + ma.output() + mb.output());
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (ma.output().find("peer node b is up") == std::string::npos ||
           mb.output().find("peer node a is up") == std::string::npos) {
      if (std::chrono::steady_clock::now() > deadline)
        throw std::runtime_error("the media did not hear from each other");
      std::this_thread::sleep_for(20ms);
    }
    Endpoint tx(11, st_a.name(), frame_bytes), rx(21, st_b.name(), frame_bytes);
    std::uint32_t seq = 0;
    for (int i = 0; i < 50; ++i) {  // warm-up: caches, ARP, first wake-ups
      tx.send(++seq);
      rx.receive(seq, 200ms);
    }
    for (int run = 0; run < repetitions; ++run) {
      std::vector<double> lat;
      for (int i = 0; i < samples; ++i) {
        tx.send(++seq);
        const double us = rx.receive(seq, 200ms);
        if (us < 0)
          ++r.lost;
        else
          lat.push_back(us);
        std::this_thread::sleep_for(1ms);  // a station sends at most every few ms
      }
      r.runs.push_back(std::move(lat));
    }
    mb.stop();
    ma.stop();
  }
  std::ifstream in(dir / "trace-b.jsonl");
  for (std::string line; std::getline(in, line);) {
    const auto j = nlohmann::json::parse(line, nullptr, false);
    if (!j.is_discarded() && j.value("ev", "") == "medium.hop")
      r.hop.push_back(
          static_cast<double>(j["ts"].get<std::int64_t>() - j["tx_ns"].get<std::int64_t>()) /
          1000.0);
  }
  std::error_code ignored;
  fs::remove_all(dir, ignored);
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"radio-federation-bench: latency of the federated medium's hop between two nodes"};
  int samples = 2000, repetitions = 3;
  std::string forwarding = "both";
  std::size_t frame_bytes = 100;
  int link_mtu = 1500;
  app.add_option("--samples", samples, "frames per run")->check(CLI::PositiveNumber);
  app.add_option("--repetitions", repetitions, "runs per forwarding")->check(CLI::PositiveNumber);
  app.add_option("--forwarding", forwarding, "user, kernel or both")
      ->check(CLI::IsMember({"user", "kernel", "both"}));
  app.add_option("--frame-bytes", frame_bytes, "frame size on wlan0, 26..1514")
      ->check(CLI::Range(26, 1514));
  app.add_option("--link-mtu", link_mtu, "MTU of the link between the nodes")
      ->check(CLI::Range(1280, 9000));
  CLI11_PARSE(app, argc, argv);
  if (::geteuid() != 0) {
    std::fprintf(stderr, "radio-federation-bench: needs root (namespaces, veth)\n");
    return 1;
  }
  if (!std::getenv("TESTBED_BIN")) {
    std::fprintf(stderr, "radio-federation-bench: set TESTBED_BIN to the folder of radio-medium\n");
    return 1;
  }
  std::printf("load average before: %s; frames of %zu bytes, link MTU %d\n", loadavg().c_str(),
              frame_bytes, link_mtu);
  std::vector<std::string> modes = forwarding == "both" ? std::vector<std::string>{"user", "kernel"}
                                                        : std::vector<std::string>{forwarding};
  for (const auto& mode : modes) {
    Result r;
    try {
      r = measure(mode, repetitions, samples, frame_bytes, link_mtu);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "radio-federation-bench: %s\n", e.what());
      return 1;
    }
    std::vector<double> p50s, p99s;
    for (std::size_t k = 0; k < r.runs.size(); ++k) {
      const auto& v = r.runs[k];
      p50s.push_back(percentile(v, 50));
      p99s.push_back(percentile(v, 99));
      std::printf(
          "%-6s run %zu: %zu frames, wlan0(a) -> wlan0(b) p50 %.1f us, p90 %.1f, p99 %.1f, max "
          "%.1f\n",
          mode.c_str(), k + 1, v.size(), percentile(v, 50), percentile(v, 90), percentile(v, 99),
          percentile(v, 100));
    }
    std::printf(
        "%-6s median of runs: p50 %.1f us, p99 %.1f us; lost %zu; medium.hop stage (%zu): p50 "
        "%.1f us, p99 %.1f us\n",
        mode.c_str(), percentile(p50s, 50), percentile(p99s, 50), r.lost, r.hop.size(),
        percentile(r.hop, 50), percentile(r.hop, 99));
  }
  std::printf("load average after: %s\n", loadavg().c_str());
  return 0;
}
