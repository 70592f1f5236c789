// network-emulator under load, as a real process: writes a scenario with N stations, starts
// the program with every station's NMEA and CAN pointed at sockets of this process, sends
// each station's state at R Hz in real time for S seconds, and reports the emulator's CPU use
// (utime + stime from /proc/PID/stat), the states it took in (its final status line) and what
// arrived.
//
//   network-emulator-load --emulator build/bin/network-emulator [--emulator OTHER]...
//                         [--stations 1000] [--rate 100] [--seconds 10] [--runs 1]
//                         [--namespaces K] [--batch N] [--emulator-arg ARG]... [--perf FILE]
//
// States go out as a sim-client sends them: the states of one tick in batch datagrams of up to
// --batch states (default 9, as many as wire::kDefaultBatchDatagramSize holds; docs/wire.md).
//
// --namespaces K (root) spreads the stations over K network namespaces, each with its own
// receivers on 127.0.0.1:10110 (NMEA) and :20000 (CAN): the deployment of the native launcher
// and of Docker, where each station has a namespace of its own (K = stations). Without it,
// every station's feeds go to two sockets in this process's namespace.
//
// With several --emulator and --runs K, the programs take turns (A B A B ...), so that on a
// shared machine each sees the same mix of neighbours; the summary gives each one's median and
// 90th percentile of CPU and the states it lost.

#include <arpa/inet.h>
#include <fcntl.h>
#include <net/if.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/epoll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "common/can/netns.hpp"
#include "common/test_support/stale_netns.hpp"
#include "common/wire/vehicle_state.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

int udp_socket(int port, sockaddr_in* bound) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  const int big = 16 << 20;
  // Beyond net.core.rmem_max only with CAP_NET_ADMIN (SO_RCVBUFFORCE); plain otherwise.
  if (::setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &big, sizeof big) != 0)
    ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &big, sizeof big);
  if (::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0)
    return -1;
  socklen_t len = sizeof a;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  if (bound)
    *bound = a;
  return fd;
}

/// utime + stime of @p pid in seconds; with @p kernel, stime alone.
double cpu_seconds(pid_t pid, bool kernel = false) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::istringstream rest(text.substr(text.rfind(')') + 2));
  std::string field;
  std::vector<std::string> f;
  while (rest >> field)
    f.push_back(field);
  // After "pid (comm) ": state is field 3, utime 14, stime 15 → indexes 11 and 12 here.
  if (f.size() < 13)
    return 0;
  return static_cast<double>((kernel ? 0 : std::stoll(f[11])) + std::stoll(f[12])) /
         static_cast<double>(::sysconf(_SC_CLK_TCK));
}

std::size_t drain(int fd) {
  std::size_t n = 0;
  char buf[4096];
  while (::recv(fd, buf, sizeof buf, 0) > 0)
    ++n;
  return n;
}

/// The stations' receivers: two sockets in this namespace, or two in each of K namespaces.
class Receivers {
 public:
  /// @p namespaces 0: two sockets here on free ports.
  explicit Receivers(int namespaces) {
    epoll_ = ::epoll_create1(EPOLL_CLOEXEC);
    if (namespaces == 0) {
      sockaddr_in nmea{}, can{};
      add(udp_socket(0, &nmea), false);
      add(udp_socket(0, &can), true);
      nmea_port_ = ntohs(nmea.sin_port);
      can_port_ = ntohs(can.sin_port);
      return;
    }
    nmea_port_ = 10110;
    can_port_ = 20000;
    tb::test_support::remove_stale_netns({"tbload"});
    std::string batch;
    for (int i = 0; i < namespaces; ++i) {
      names_.push_back("tbload" + std::to_string(::getpid()) + "-" + std::to_string(i));
      batch += "netns add " + names_.back() + "\n";
    }
    if (!ip_batch(batch)) {
      std::fprintf(stderr, "cannot make %d network namespaces (ip netns add; root?)\n", namespaces);
      return;
    }
    for (const std::string& ns : names_) {
      int nmea = -1, can = -1;
      const auto ec = tb::can::run_in_netns(ns, [&] {
        lo_up();
        nmea = udp_socket(nmea_port_, nullptr);
        can = udp_socket(can_port_, nullptr);
      });
      if (ec || nmea < 0 || can < 0) {
        std::fprintf(stderr, "cannot listen in netns %s: %s\n", ns.c_str(),
                     ec ? ec.message().c_str() : "bind failed");
        return;
      }
      add(nmea, false);
      add(can, true);
    }
  }
  ~Receivers() {
    for (const auto& [fd, is_can] : fds_)
      ::close(fd);
    ::close(epoll_);
    if (!names_.empty()) {
      std::string batch;
      for (const std::string& ns : names_)
        batch += "netns del " + ns + "\n";
      ip_batch(batch);
    }
  }
  Receivers(const Receivers&) = delete;
  Receivers& operator=(const Receivers&) = delete;

  bool ok() const {
    return !fds_.empty() && fds_.size() == 2 * std::max<std::size_t>(1, names_.size());
  }
  int nmea_port() const { return nmea_port_; }
  int can_port() const { return can_port_; }
  /// The namespace of station @p i ("" for none).
  std::string netns_of(int i) const {
    return names_.empty() ? "" : names_[static_cast<std::size_t>(i) % names_.size()];
  }
  /// Reads what has arrived; adds the datagrams to @p nmea and @p can.
  void drain_all(std::size_t& nmea, std::size_t& can) {
    epoll_event ev[256];
    for (;;) {
      const int n = ::epoll_wait(epoll_, ev, 256, 0);
      if (n <= 0)
        return;
      for (int i = 0; i < n; ++i) {
        const auto& [fd, is_can] = fds_[ev[i].data.u32];
        (is_can ? can : nmea) += drain(fd);
      }
      if (n < 256)
        return;
    }
  }

 private:
  void add(int fd, bool is_can) {
    epoll_event ev{};
    ev.events = EPOLLIN;
    ev.data.u32 = static_cast<std::uint32_t>(fds_.size());
    ::epoll_ctl(epoll_, EPOLL_CTL_ADD, fd, &ev);
    fds_.emplace_back(fd, is_can);
  }
  static void lo_up() {
    const int s = ::socket(AF_INET, SOCK_DGRAM, 0);
    ifreq ifr{};
    std::snprintf(ifr.ifr_name, sizeof ifr.ifr_name, "lo");
    if (::ioctl(s, SIOCGIFFLAGS, &ifr) == 0) {
      ifr.ifr_flags = static_cast<short>(ifr.ifr_flags | IFF_UP);
      ::ioctl(s, SIOCSIFFLAGS, &ifr);
    }
    ::close(s);
  }
  static bool ip_batch(const std::string& commands) {
    FILE* p = ::popen("ip -batch - 2>&1", "w");
    if (!p)
      return false;
    std::fwrite(commands.data(), 1, commands.size(), p);
    return ::pclose(p) == 0;
  }

  int epoll_ = -1;
  std::vector<std::pair<int, bool>> fds_;  // socket, carries CAN
  std::vector<std::string> names_;
  int nmea_port_ = 0, can_port_ = 0;
};

struct RunResult {
  double cpu_percent = 0;
  double cpu_us_per_state = 0;     // CPU time over the states taken in: comparable across losses
  double kernel_us_per_state = 0;  // of which in the kernel (stime)
  std::size_t sent = 0, received = 0;  // states sent, states the emulator decoded
  std::size_t nmea = 0, can = 0;       // datagrams that arrived here
  std::uint64_t overflows = 0;         // UDP datagrams dropped by full receive buffers
  double expected_nmea = 0;
};

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// UDP RcvbufErrors of the whole network namespace (/proc/net/snmp): where a lost state went.
std::uint64_t receive_buffer_errors() {
  std::istringstream in(read_text("/proc/net/snmp"));
  std::vector<std::string> names;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("Udp: ", 0) != 0)
      continue;
    std::istringstream fields(line.substr(5));
    std::vector<std::string> f{std::istream_iterator<std::string>(fields), {}};
    if (names.empty()) {
      names = f;
      continue;
    }
    for (std::size_t i = 0; i < names.size() && i < f.size(); ++i)
      if (names[i] == "RcvbufErrors")
        return std::stoull(f[i]);
  }
  return 0;
}

std::string load_average() {
  std::istringstream in(read_text("/proc/loadavg"));
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

/// Starts `perf record -g` of @p pid into @p file; returns its pid, or -1.
pid_t start_perf(pid_t pid, const std::string& file) {
  std::vector<std::string> args{"perf", "record", "-g", "-o", file, "-p", std::to_string(pid)};
  std::vector<char*> argv_c;
  for (auto& a : args)
    argv_c.push_back(a.data());
  argv_c.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
  pid_t perf = -1;
  if (::posix_spawnp(&perf, "perf", &fa, nullptr, argv_c.data(), environ) != 0)
    perf = -1;
  posix_spawn_file_actions_destroy(&fa);
  if (perf < 0)
    std::fprintf(stderr, "cannot start perf (Debian's linux-perf, scripts/install-deps)\n");
  return perf;
}

/// One run of @p emulator; nullopt when it did not come up.
std::optional<RunResult> run_once(const std::string& emulator,
                                  const std::vector<std::string>& extra_args, int stations,
                                  int rate, double seconds, int namespaces, int batch,
                                  const std::string& perf_file) {
  Receivers receivers(namespaces);
  if (!receivers.ok())
    return std::nullopt;
  sockaddr_in listen_addr{};
  const int probe = udp_socket(0, &listen_addr);  // a free port for the emulator to listen on
  ::close(probe);
  const int listen_port = ntohs(listen_addr.sin_port);

  const fs::path dir = fs::temp_directory_path() / ("emu_load_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  {
    std::ofstream sc(dir / "scenario.json"), st(dir / "stations.json");
    sc << R"({"name": "load", "map": {"type": "straight", "length": 60000},
      "origin": {"lat": 48.1, "lon": 11.5}, "rates": {"physics_hz": )"
       << rate << R"(},
      "vehicles": [)";
    st << "{\"stations\": [";
    for (int i = 0; i < stations; ++i) {
      sc << (i ? "," : "") << "{\"id\": \"v" << i << "\", \"station_id\": " << 1000 + i
         << ", \"spawn\": {\"x\": " << i * 10 << ", \"y\": -1.75, \"heading_deg\": 90}}";
      st << (i ? "," : "") << "{\"station_id\": " << 1000 + i
         << ", \"gnss_port\": " << receivers.nmea_port()
         << ", \"can_port\": " << receivers.can_port();
      if (const std::string ns = receivers.netns_of(i); !ns.empty())
        st << ", \"netns\": \"" << ns << "\"";
      st << "}";
    }
    sc << "]}";
    st << "]}";
  }
  std::vector<std::string> args{emulator,
                                "--scenario",
                                (dir / "scenario.json").string(),
                                "--stations",
                                (dir / "stations.json").string(),
                                "--listen",
                                "127.0.0.1:" + std::to_string(listen_port),
                                "--can",
                                "udp",
                                "--status-interval",
                                "0",
                                "--log-level",
                                "info"};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  std::vector<char*> argv_c;
  for (auto& a : args)
    argv_c.push_back(a.data());
  argv_c.push_back(nullptr);
  const fs::path log = dir / "emulator.log";
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  pid_t pid = -1;
  const int spawned = ::posix_spawn(&pid, emulator.c_str(), &fa, nullptr, argv_c.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  auto cleanup = [&] { fs::remove_all(dir); };
  if (spawned != 0 || pid <= 0) {
    std::fprintf(stderr, "cannot start %s\n", emulator.c_str());
    cleanup();
    return std::nullopt;
  }
  // Up when it says that it listens (the socket is bound and read by then), so that no
  // state is sent to a closed port and every state sent counts.
  bool up = false, exited = false;
  for (int i = 0; i < 1000 && !up && !exited; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    up = read_text(log).find("listening on") != std::string::npos;
    exited = ::waitpid(pid, nullptr, WNOHANG) == pid;
  }
  if (!up) {
    std::fprintf(stderr, "network-emulator did not come up:\n%s\n", read_text(log).c_str());
    if (!exited) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
    }
    cleanup();
    return std::nullopt;
  }

  const int tx = ::socket(AF_INET, SOCK_DGRAM, 0);
  const int big = 16 << 20;
  ::setsockopt(tx, SOL_SOCKET, SO_SNDBUF, &big, sizeof big);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  to.sin_port = htons(static_cast<std::uint16_t>(listen_port));
  std::vector<tb::wire::VehicleState> pending;
  std::vector<std::uint8_t> datagram;
  auto flush = [&] {
    if (pending.empty())
      return;
    datagram.resize(tb::wire::batch_datagram_size(pending.size()));
    tb::wire::encode_batch(pending, datagram);
    ::sendto(tx, datagram.data(), datagram.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
    pending.clear();
  };
  auto send_state = [&](std::uint32_t id, std::uint64_t tick) {
    tb::wire::VehicleState s;
    s.station_id = id;
    s.tick = tick;
    s.sim_time_ns = static_cast<std::int64_t>(tick) * (1'000'000'000 / rate);
    s.position = {static_cast<double>(id - 1000), -1.75 + static_cast<double>(tick) * 0.1, 0.0};
    s.velocity = {0.0f, 10.0f, 0.0f};
    s.speed = 10.0f;
    pending.push_back(s);
    if (pending.size() >= static_cast<std::size_t>(batch))
      flush();
  };

  // The profile covers the measured window only: the start-up's namespaces and sockets are not
  // what is asked about.
  const pid_t perf = perf_file.empty() ? -1 : start_perf(pid, perf_file);
  RunResult r;
  const std::uint64_t overflows0 = receive_buffer_errors();
  const double cpu0 = cpu_seconds(pid), sys0 = cpu_seconds(pid, true);
  const auto t0 = Clock::now();
  const auto period = std::chrono::nanoseconds(1'000'000'000 / rate);
  std::uint64_t tick = 1;
  for (auto next = t0; Clock::now() - t0 < std::chrono::duration<double>(seconds); ++tick) {
    for (int i = 0; i < stations; ++i) {
      send_state(static_cast<std::uint32_t>(1000 + i), tick);
      ++r.sent;
      if (i % 100 == 99)
        receivers.drain_all(r.nmea, r.can);
    }
    flush();  // the tick's last, partly filled datagram: no state waits for the next tick
    next += period;
    std::this_thread::sleep_until(next);
  }
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  if (perf > 0) {
    ::kill(perf, SIGINT);
    ::waitpid(perf, nullptr, 0);
  }
  // Let it finish what is still queued (a backlog on a busy machine is late, not lost): done
  // when no CAN datagram came for 200 ms, or after 3 s.
  for (int quiet = 0, i = 0; quiet < 4 && i < 60; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const std::size_t can_before = r.can;
    receivers.drain_all(r.nmea, r.can);
    quiet = r.can == can_before ? quiet + 1 : 0;
  }
  const double cpu = cpu_seconds(pid) - cpu0, sys = cpu_seconds(pid, true) - sys0;
  ::kill(pid, SIGTERM);
  ::waitpid(pid, nullptr, 0);
  ::close(tx);
  r.overflows = receive_buffer_errors() - overflows0;
  // "final: states N (...": the states the emulator decoded, all of them this run's.
  const std::string text = read_text(log);
  std::smatch m;
  if (std::regex_search(text, m, std::regex(R"(final: states (\d+))")))
    r.received = std::stoull(m[1]);
  cleanup();

  r.cpu_percent = 100.0 * cpu / wall;
  r.cpu_us_per_state = r.received ? 1e6 * cpu / static_cast<double>(r.received) : 0;
  r.kernel_us_per_state = r.received ? 1e6 * sys / static_cast<double>(r.received) : 0;
  r.expected_nmea = static_cast<double>(r.sent) * 10.0 / rate;
  std::printf("%s: stations %d, %d Hz, %.1f s: states sent %zu (%.0f/s), taken in %zu (lost %zu)\n",
              emulator.c_str(), stations, rate, wall, r.sent, static_cast<double>(r.sent) / wall,
              r.received, r.sent - std::min(r.sent, r.received));
  std::printf(
      "  NMEA datagrams received %zu (%.1f %% of %.0f), CAN datagrams received %zu; UDP "
      "receive-buffer overflows (system-wide) %llu\n",
      r.nmea, 100.0 * static_cast<double>(r.nmea) / r.expected_nmea, r.expected_nmea, r.can,
      static_cast<unsigned long long>(r.overflows));
  std::printf(
      "  network-emulator CPU: %.2f s in %.2f s = %.1f %% of one core, %.2f us per state (%.2f "
      "in the kernel)\n",
      cpu, wall, r.cpu_percent, r.cpu_us_per_state, r.kernel_us_per_state);
  std::fflush(stdout);
  return r;
}

/// The @p q quantile (0..1) of @p v, nearest rank.
double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::clamp<std::size_t>(rank, 1, v.size()) - 1];
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"network-emulator load test"};
  std::vector<std::string> emulators;
  int stations = 1000, rate = 100, runs = 1, namespaces = 0;
  int batch = static_cast<int>(tb::wire::states_per_batch(tb::wire::kDefaultBatchDatagramSize));
  std::vector<std::string> extra_args;
  std::string perf_file;
  double seconds = 10;
  app.add_option("--emulator", emulators, "path of network-emulator (repeatable: take turns)")
      ->required();
  app.add_option("--stations", stations)->check(CLI::Range(1, 60000))->capture_default_str();
  app.add_option("--rate", rate, "states per station per second")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  app.add_option("--seconds", seconds)->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--runs", runs, "runs of each emulator")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  app.add_option("--namespaces", namespaces,
                 "spread the stations over this many network namespaces (root; 0: none)")
      ->check(CLI::Range(0, 60000))
      ->capture_default_str();
  app.add_option("--batch", batch, "states per datagram (1: one datagram per state)")
      ->check(CLI::Range(1, batch))
      ->capture_default_str();
  // Written --emulator-arg=--flag=value, so that the value is not taken for an option here.
  app.add_option("--emulator-arg", extra_args, "passed on to every emulator (repeatable)");
  app.add_option("--perf", perf_file,
                 "perf record -g of each emulator's first run into FILE (FILE.1, FILE.2, ... "
                 "for the second --emulator and on)");
  CLI11_PARSE(app, argc, argv);

  std::printf("load average before: %s; %d stations in %s\n", load_average().c_str(), stations,
              namespaces ? (std::to_string(namespaces) + " network namespaces").c_str()
                         : "this network namespace");
  std::vector<std::vector<RunResult>> results(emulators.size());
  for (int run = 0; run < runs; ++run)
    for (std::size_t e = 0; e < emulators.size(); ++e) {
      // A port taken between the probe and the emulator's bind: try again with another.
      std::optional<RunResult> r;
      for (int attempt = 0; attempt < 3 && !r; ++attempt)
        r = run_once(emulators[e], extra_args, stations, rate, seconds, namespaces, batch,
                     run == 0 && !perf_file.empty()
                         ? perf_file + (e == 0 ? "" : "." + std::to_string(e))
                         : "");
      if (!r)
        return 1;
      results[e].push_back(*r);
    }
  std::printf("load average after: %s\n", load_average().c_str());
  for (std::size_t e = 0; e < emulators.size(); ++e) {
    std::vector<double> cpu, lost, per_state, kernel;
    std::size_t sent = 0, received = 0;
    for (const RunResult& r : results[e]) {
      cpu.push_back(r.cpu_percent);
      per_state.push_back(r.cpu_us_per_state);
      kernel.push_back(r.kernel_us_per_state);
      lost.push_back(100.0 * static_cast<double>(r.sent - std::min(r.sent, r.received)) /
                     static_cast<double>(r.sent));
      sent += r.sent;
      received += r.received;
    }
    std::printf(
        "%s: %d runs: CPU median %.1f %%, p90 %.1f %% of one core (%.2f / %.2f us per state "
        "taken in, median %.2f in the kernel); states lost median %.2f %%, max %.2f %% (%zu of "
        "%zu in all)\n",
        emulators[e].c_str(), runs, quantile(cpu, 0.5), quantile(cpu, 0.9),
        quantile(per_state, 0.5), quantile(per_state, 0.9), quantile(kernel, 0.5),
        quantile(lost, 0.5), quantile(lost, 1.0), sent - std::min(sent, received), sent);
  }
  return 0;
}
