// network-emulator under load, as a real process: writes a scenario with N stations, starts
// the program with every station's NMEA and CAN pointed at two sockets of this process, sends
// each station's state at R Hz in real time for S seconds, and reports the emulator's CPU use
// (utime + stime from /proc/PID/stat) and what arrived.
//
//   network-emulator-load --emulator build/bin/network-emulator [--stations 1000] [--rate 100]
//                         [--seconds 10]

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

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

/// utime + stime of @p pid in seconds.
double cpu_seconds(pid_t pid) {
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
  return static_cast<double>(std::stoll(f[11]) + std::stoll(f[12])) /
         static_cast<double>(::sysconf(_SC_CLK_TCK));
}

std::size_t drain(int fd) {
  std::size_t n = 0;
  char buf[4096];
  while (::recv(fd, buf, sizeof buf, 0) > 0)
    ++n;
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"network-emulator load test"};
  std::string emulator;
  int stations = 1000, rate = 100;
  double seconds = 10;
  app.add_option("--emulator", emulator, "path of network-emulator")->required();
  app.add_option("--stations", stations)->check(CLI::Range(1, 60000))->capture_default_str();
  app.add_option("--rate", rate, "states per station per second")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  app.add_option("--seconds", seconds)->check(CLI::PositiveNumber)->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  sockaddr_in nmea_addr{}, can_addr{}, listen_addr{};
  const int nmea = udp_socket(0, &nmea_addr), can = udp_socket(0, &can_addr);
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
         << ", \"gnss_port\": " << ntohs(nmea_addr.sin_port)
         << ", \"can_port\": " << ntohs(can_addr.sin_port) << "}";
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
  std::vector<char*> argv_c;
  for (auto& a : args)
    argv_c.push_back(a.data());
  argv_c.push_back(nullptr);
  pid_t pid = -1;
  if (::posix_spawn(&pid, emulator.c_str(), nullptr, nullptr, argv_c.data(), environ) != 0) {
    std::fprintf(stderr, "cannot start %s\n", emulator.c_str());
    return 1;
  }

  const int tx = ::socket(AF_INET, SOCK_DGRAM, 0);
  const int big = 16 << 20;
  ::setsockopt(tx, SOL_SOCKET, SO_SNDBUF, &big, sizeof big);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  to.sin_port = htons(static_cast<std::uint16_t>(listen_port));
  auto send_state = [&](std::uint32_t id, std::uint64_t tick) {
    tb::wire::VehicleState s;
    s.station_id = id;
    s.tick = tick;
    s.sim_time_ns = static_cast<std::int64_t>(tick) * (1'000'000'000 / rate);
    s.position = {static_cast<double>(id - 1000), -1.75 + static_cast<double>(tick) * 0.1, 0.0};
    s.velocity = {0.0f, 10.0f, 0.0f};
    s.speed = 10.0f;
    const auto d = tb::wire::encode(s);
    ::sendto(tx, d.data(), d.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
  };
  // Wait until the emulator answers: a state of station 1000 turns into NMEA.
  bool up = false;
  for (int i = 0; i < 500 && !up; ++i) {
    send_state(1000, 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    up = drain(nmea) > 0;
  }
  if (!up) {
    std::fprintf(stderr, "network-emulator did not answer\n");
    ::kill(pid, SIGKILL);
    return 1;
  }
  drain(can);

  const double cpu0 = cpu_seconds(pid);
  const auto t0 = Clock::now();
  const auto period = std::chrono::nanoseconds(1'000'000'000 / rate);
  std::size_t nmea_rx = 0, can_rx = 0, sent = 0;
  std::uint64_t tick = 1;
  for (auto next = t0; Clock::now() - t0 < std::chrono::duration<double>(seconds); ++tick) {
    for (int i = 0; i < stations; ++i) {
      send_state(static_cast<std::uint32_t>(1000 + i), tick);
      ++sent;
      if (i % 100 == 99) {
        nmea_rx += drain(nmea);
        can_rx += drain(can);
      }
    }
    next += period;
    std::this_thread::sleep_until(next);
  }
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  nmea_rx += drain(nmea);
  can_rx += drain(can);
  const double cpu = cpu_seconds(pid) - cpu0;
  ::kill(pid, SIGTERM);
  ::waitpid(pid, nullptr, 0);
  fs::remove_all(dir);

  const double expected_nmea = static_cast<double>(sent) * 10.0 / rate;
  std::printf("stations %d, %d Hz states, %.1f s: states sent %zu (%.0f/s)\n", stations, rate, wall,
              sent, static_cast<double>(sent) / wall);
  std::printf("NMEA datagrams received %zu (%.1f %% of %.0f), CAN datagrams received %zu\n",
              nmea_rx, 100.0 * static_cast<double>(nmea_rx) / expected_nmea, expected_nmea, can_rx);
  std::printf("network-emulator CPU: %.2f s in %.2f s = %.1f %% of one core\n", cpu, wall,
              100.0 * cpu / wall);
  return 0;
}
