#pragma once
/// @file For integration tests: a real Mosquitto with the configuration that
/// docker/mosquitto/gen-broker-config renders (station accounts, the read-only `hmi` reader,
/// the ACL), on free loopback ports in a temporary folder; and a wait on a condition with a
/// deadline.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "common/mqtt/mosquitto_client.hpp"

namespace tb::mqtt::testing {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using nlohmann::json;

inline fs::path repo_root() {
  const char* r = std::getenv("TESTBED_ROOT");
  return r ? fs::path(r) : fs::current_path();
}

inline int free_port() {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof a;
  if (::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
      ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &len) != 0) {
    ::close(s);
    return -1;
  }
  ::close(s);
  return ntohs(a.sin_port);
}

inline bool port_open(int port) {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const bool ok = ::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  ::close(s);
  return ok;
}

template <typename Pred>
bool wait_until(Pred pred, std::chrono::milliseconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) {
      return true;
    }
    std::this_thread::sleep_for(20ms);
  }
  return pred();
}

/// A Mosquitto with the configuration gen-broker-config renders, in a temporary folder.
class Broker {
 public:
  explicit Broker(const std::string& stations) {
    char tmpl[] = "/tmp/hmi-broker-XXXXXX";
    dir_ = ::mkdtemp(tmpl);
    // The broker drops root for the "mosquitto" user, which must read the folder and write
    // the persistence file.
    ::chmod(dir_.c_str(), 0777);
    tcp_port_ = free_port();
    ws_port_ = free_port();
    const std::string cmd = (repo_root() / "docker/mosquitto/gen-broker-config").string() +
                            " --stations " + stations + " --out " + dir_.string() +
                            " --bind 127.0.0.1 --tcp-port " + std::to_string(tcp_port_) +
                            " --ws-port " + std::to_string(ws_port_) + " --http-dir " +
                            dir_.string() + " > " + (dir_ / "gen.log").string() + " 2>&1";
    ok_ = std::system(cmd.c_str()) == 0;
    // Sessions survive a broker restart, so that a subscriber misses nothing while the broker
    // is away (the shipped configuration keeps none: the testbed needs no history).
    std::ofstream(dir_ / "mosquitto.conf", std::ios::app)
        << "\npersistence true\npersistence_location " << dir_.string() << "/\n";
    const json creds = json::parse(std::ifstream(dir_ / "credentials.json"), nullptr, false);
    creds_ = creds.is_discarded() ? json::object() : creds;
  }
  ~Broker() {
    stop();
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  bool configured() const { return ok_; }
  int port() const { return tcp_port_; }
  std::string password(std::uint32_t station) const {
    return creds_["stations"][std::to_string(station)]["password"].get<std::string>();
  }
  /// A client of this broker logged in as station @p station (user and client id
  /// "station-<id>"), as its-station connects.
  ClientConfig station_account(std::uint32_t station) const {
    ClientConfig c;
    c.port = tcp_port_;
    c.client_id = c.username = "station-" + std::to_string(station);
    c.password = password(station);
    return c;
  }

  bool start() {
    pid_ = ::fork();
    if (pid_ == 0) {
      const std::string log = (dir_ / "broker.log").string();
      std::freopen(log.c_str(), "a", stderr);
      std::freopen(log.c_str(), "a", stdout);
      ::execlp("mosquitto", "mosquitto", "-c", (dir_ / "mosquitto.conf").c_str(), nullptr);
      ::_exit(127);
    }
    return wait_until([&] { return port_open(tcp_port_); }, 5s);
  }
  void stop() {
    if (pid_ <= 0) {
      return;
    }
    ::kill(pid_, SIGTERM);
    int status = 0;
    for (int i = 0; i < 250 && ::waitpid(pid_, &status, WNOHANG) == 0; ++i) {
      std::this_thread::sleep_for(20ms);
    }
    if (::waitpid(pid_, &status, WNOHANG) == 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, &status, 0);
    }
    pid_ = -1;
  }
  /// SIGSTOP / SIGCONT: a broker that stops reading, as one that is swamped.
  void pause() { ::kill(pid_, SIGSTOP); }
  void resume() { ::kill(pid_, SIGCONT); }
  std::string log() const {
    std::ifstream f(dir_ / "broker.log");
    return std::string(std::istreambuf_iterator<char>(f), {});
  }

 private:
  fs::path dir_;
  int tcp_port_ = -1;
  int ws_port_ = -1;
  pid_t pid_ = -1;
  bool ok_ = false;
  json creds_;
};

}  // namespace tb::mqtt::testing
