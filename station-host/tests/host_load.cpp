// station-host under load, as a real process: N pooled stations in one host, every one in range
// of every other (the kernel-forwarding medium: the host loops each station's frames back to its
// N - 1 others), fed states at R Hz in real time for S seconds; reports the host's CPU (utime +
// stime from /proc/PID/stat) per pooled station-second, the CAMs sent and received (its status
// file) and so the CPU per frame a station hears. Needs root (a network namespace).
//
//   station-host-load --host build/bin/station-host [--stations 300] [--rate 100] [--seconds 20]

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "common/can/netns.hpp"
#include "common/clock/clock.hpp"
#include "common/test_support/stale_netns.hpp"
#include "common/wire/vehicle_state.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

int sh(const std::string& cmd) {
  return std::system((cmd + " >/dev/null 2>&1").c_str());
}

/// utime + stime of @p pid in seconds.
double cpu_seconds(pid_t pid) {
  std::ifstream in(fmt::format("/proc/{}/stat", pid));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto close = text.rfind(')');
  if (close == std::string::npos)
    return 0.0;
  std::istringstream rest(text.substr(close + 2));
  std::string field;
  double utime = 0, stime = 0;
  for (int i = 3; rest >> field; ++i) {
    if (i == 14)
      utime = std::stod(field);
    if (i == 15) {
      stime = std::stod(field);
      break;
    }
  }
  return (utime + stime) / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

}  // namespace

int main(int argc, char** argv) {
  std::string host_bin;
  int stations = 300;
  double rate = 100.0;
  double seconds = 20.0;
  CLI::App app{"station-host-load: a station-host's CPU per pooled station-second"};
  app.add_option("--host", host_bin, "path of station-host")->required();
  app.add_option("--stations", stations)->check(CLI::Range(2, 5000))->capture_default_str();
  app.add_option("--rate", rate, "states per station per second")
      ->check(CLI::Range(1.0, 1000.0))
      ->capture_default_str();
  app.add_option("--seconds", seconds)->check(CLI::PositiveNumber)->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (::geteuid() != 0) {
    std::fprintf(stderr, "station-host-load: needs root (a network namespace)\n");
    return 2;
  }

  tb::test_support::remove_stale_netns({"shl"});
  const auto tag = std::to_string(::getpid());
  const std::string ns = "shl" + tag;
  const fs::path dir = fs::temp_directory_path() / ("station-host-load-" + tag);
  fs::create_directories(dir);
  // A ring of vehicles, each on its own 200 m circle around the origin: all within 400 m.
  nlohmann::json vehicles = nlohmann::json::array();
  std::string ids;
  for (int i = 0; i < stations; ++i) {
    const std::uint32_t id = 100000 + static_cast<std::uint32_t>(i);
    vehicles.push_back({{"id", fmt::format("p{}", i)},
                        {"station_id", id},
                        {"spawn", {{"lane", 0}, {"s", 10.0 + 4000.0 * i / stations}}},
                        {"driver",
                         {{"type", "lane_follow"},
                          {"speed_profile", nlohmann::json::array({{{"t", 0}, {"speed", 14}}})}}},
                        {"station", {{"kind", "pooled"}}}});
    ids += (i ? "," : "") + std::to_string(id);
  }
  const nlohmann::json scenario{{"name", "station-host-load"},
                                {"map", {{"type", "straight"}, {"lanes", 1}, {"length", 4100}}},
                                {"origin", {{"lat", 41.1}, {"lon", 29.0}, {"alt", 60}}},
                                {"vehicles", vehicles}};
  std::ofstream(dir / "scenario.json") << scenario.dump();

  auto cleanup = [&] {
    sh("ip netns del " + ns);
    fs::remove_all(dir);
  };
  if (sh("ip netns add " + ns) != 0 ||
      sh(fmt::format("ip link add shla{} type veth peer name shlb{}", tag, tag)) != 0 ||
      sh(fmt::format("ip link set shla{} netns {}", tag, ns)) != 0 ||
      sh(fmt::format("ip netns exec {} ip link set shla{} name wlan0", ns, tag)) != 0 ||
      sh(fmt::format("ip netns exec {} ip link set wlan0 up", ns)) != 0 ||
      sh(fmt::format("ip netns exec {} ip link set lo up", ns)) != 0 ||
      sh(fmt::format("ip link set shlb{} up", tag)) != 0) {
    std::fprintf(stderr, "station-host-load: cannot make the namespace and veth pair\n");
    cleanup();
    return 1;
  }

  std::vector<std::string> args{"ip",
                                "netns",
                                "exec",
                                ns,
                                host_bin,
                                "--scenario",
                                (dir / "scenario.json").string(),
                                "--stations",
                                ids,
                                "--radio",
                                "wlan0",
                                "--states",
                                "udp://127.0.0.1:4710",
                                "--forwarding",
                                "kernel",
                                "--log-level",
                                "warn",
                                "--status-file",
                                (dir / "status.json").string()};
  std::vector<char*> cargs;
  for (auto& a : args)
    cargs.push_back(a.data());
  cargs.push_back(nullptr);
  pid_t pid = -1;
  if (::posix_spawnp(&pid, cargs[0], nullptr, nullptr, cargs.data(), environ) != 0) {
    std::fprintf(stderr, "station-host-load: cannot start %s\n", host_bin.c_str());
    cleanup();
    return 1;
  }
  int fd = -1;
  if (tb::can::run_in_netns(ns, [&] { fd = ::socket(AF_INET, SOCK_DGRAM, 0); }) || fd < 0) {
    std::fprintf(stderr, "station-host-load: no socket in the namespace\n");
    ::kill(pid, SIGKILL);
    cleanup();
    return 1;
  }
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(4710);
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);

  const auto period = std::chrono::duration_cast<std::chrono::nanoseconds>(
      std::chrono::duration<double>(1.0 / rate));
  const std::int64_t world_start = tb::clock::to_unix_ns(tb::clock::WallClock::now());
  const std::size_t per = tb::wire::states_per_batch(tb::wire::kDefaultBatchDatagramSize);
  std::vector<tb::wire::VehicleState> batch(static_cast<std::size_t>(stations));
  const double warmup = 5.0;  // fixes, first CAMs, neighbours learnt
  const auto start = std::chrono::steady_clock::now();
  double cpu_at_warmup = 0.0;
  nlohmann::json status_at_warmup;
  auto read_status = [&] {
    std::ifstream in(dir / "status.json");
    return nlohmann::json::parse(in, nullptr, false);
  };
  bool warm = false;
  for (std::int64_t k = 0;; ++k) {
    const auto due = start + k * period;
    const double t = std::chrono::duration<double>(due - start).count();
    if (t >= warmup + seconds)
      break;
    if (!warm && t >= warmup) {
      warm = true;
      cpu_at_warmup = cpu_seconds(pid);
      status_at_warmup = read_status();
    }
    for (int i = 0; i < stations; ++i) {
      const double a = 14.0 * t / 200.0 + i;
      auto& s = batch[static_cast<std::size_t>(i)];
      s.station_id = 100000 + static_cast<std::uint32_t>(i);
      s.tick = static_cast<std::uint64_t>(k);
      s.sim_time_ns = static_cast<std::int64_t>(t * 1e9);
      s.position = {200.0 * std::cos(a), 200.0 * std::sin(a), 0.0};
      s.velocity = {static_cast<float>(-14.0 * std::sin(a)), static_cast<float>(14.0 * std::cos(a)),
                    0.0f};
      s.yaw = static_cast<float>(a + 1.5707963);
      s.speed = 14.0f;
      s.gear = 1;
    }
    for (std::size_t first = 0; first < batch.size(); first += per) {
      const auto bytes = tb::wire::encode_batch(
          std::span(batch).subspan(first, std::min(per, batch.size() - first)), world_start);
      ::sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to),
               sizeof to);
    }
    std::this_thread::sleep_until(start + (k + 1) * period);
  }
  const double cpu = cpu_seconds(pid) - cpu_at_warmup;
  std::this_thread::sleep_for(600ms);  // one more status file
  const auto status = read_status();
  ::kill(pid, SIGTERM);
  int wstatus = 0;
  ::waitpid(pid, &wstatus, 0);
  ::close(fd);

  auto sum = [](const nlohmann::json& j, const char* key) {
    double total = 0;
    if (j.is_object())
      for (const auto& s : j["stations"])
        total += s[key].get<double>();
    return total;
  };
  const double sent = sum(status, "cams_sent") - sum(status_at_warmup, "cams_sent");
  const double received = sum(status, "cams_received") - sum(status_at_warmup, "cams_received");
  double neighbours = 0;
  if (status.is_object())
    for (const auto& s : status["stations"])
      neighbours += s["neighbours"].get<double>();
  std::printf(
      "station-host-load: %d pooled stations, states at %.0f Hz, %.0f s measured after %.0f s\n"
      "  CPU %.3f s = %.3f ms per pooled station-second\n"
      "  CAMs sent %.2f per station-second; received %.0f per station-second; mean neighbours "
      "%.1f\n"
      "  CPU per CAM received %.2f us (all of the host's CPU over the receptions)\n",
      stations, rate, seconds, warmup, cpu, 1000.0 * cpu / (stations * seconds),
      sent / (stations * seconds), received / (stations * seconds), neighbours / stations,
      received > 0 ? 1e6 * cpu / received : 0.0);
  cleanup();
  return WIFEXITED(wstatus) && WEXITSTATUS(wstatus) == 0 ? 0 : 1;
}
