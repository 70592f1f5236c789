#include "its-station/facilities/gpsd_process.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <thread>

#include <fmt/format.h>

extern char** environ;

namespace tb::its::facilities {

Expected<GpsdProcess, std::string> GpsdProcess::start(const Options& o) {
  std::vector<std::string> argv{o.executable, "-N", "-n"};
  if (o.listen_any)
    argv.push_back("-G");
  argv.insert(argv.end(),
              {"-S", o.client_port, fmt::format("udp://{}:{}", o.nmea_bind, o.nmea_port)});
  std::vector<char*> cargv;
  for (auto& a : argv)
    cargv.push_back(a.data());
  cargv.push_back(nullptr);

  pid_t pid = -1;
  int rc = posix_spawnp(&pid, o.executable.c_str(), nullptr, nullptr, cargv.data(), environ);
  if (rc == ENOENT && o.executable.find('/') == std::string::npos) {
    // Debian installs gpsd in /usr/sbin, which a non-root PATH often lacks.
    const std::string sbin = "/usr/sbin/" + o.executable;
    cargv[0] = const_cast<char*>(sbin.c_str());
    rc = posix_spawn(&pid, sbin.c_str(), nullptr, nullptr, cargv.data(), environ);
  }
  if (rc != 0)
    return Unexpected{fmt::format("cannot start {}: {} (is the gpsd package installed?)",
                                  o.executable, std::strerror(rc))};
  return GpsdProcess(pid, std::move(argv));
}

GpsdProcess::GpsdProcess(GpsdProcess&& other) noexcept
    : pid_(other.pid_), argv_(std::move(other.argv_)) {
  other.pid_ = -1;
}

GpsdProcess& GpsdProcess::operator=(GpsdProcess&& other) noexcept {
  if (this != &other) {
    stop();
    pid_ = other.pid_;
    argv_ = std::move(other.argv_);
    other.pid_ = -1;
  }
  return *this;
}

GpsdProcess::~GpsdProcess() {
  stop();
}

bool GpsdProcess::running() {
  if (pid_ <= 0)
    return false;
  int status = 0;
  if (waitpid(pid_, &status, WNOHANG) == pid_) {
    pid_ = -1;
    return false;
  }
  return true;
}

void GpsdProcess::stop() {
  if (pid_ <= 0)
    return;
  ::kill(pid_, SIGTERM);
  // Shutdown is a program's edge, outside the event loop: a bounded blocking wait is fine.
  for (int i = 0; i < 100; ++i) {
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds{20});
  }
  ::kill(pid_, SIGKILL);
  waitpid(pid_, nullptr, 0);
  pid_ = -1;
}

}  // namespace tb::its::facilities
