#pragma once
/// @file The station's own gpsd, started as a child process (DESIGN.md: "gpsd inside the
/// station, fed NMEA over UDP").

#include <sys/types.h>
#include <string>
#include <vector>

#include "common/util/expected.hpp"

namespace tb::its::facilities {

/// Runs `gpsd -N -n [-G] -S <port> udp://<nmea_bind>:<nmea_port>` and stops it on destruction.
class GpsdProcess {
 public:
  struct Options {
    std::string executable = "gpsd";  ///< looked up in PATH, then /usr/sbin
    std::string client_port = "2947";
    std::string nmea_bind = "0.0.0.0";
    std::string nmea_port = "10110";
    bool listen_any = true;  ///< -G: clients in other namespaces can connect
  };

  /// @returns the running process, or a message naming what could not be started.
  static Expected<GpsdProcess, std::string> start(const Options& options);

  GpsdProcess(GpsdProcess&& other) noexcept;
  GpsdProcess& operator=(GpsdProcess&& other) noexcept;
  GpsdProcess(const GpsdProcess&) = delete;
  GpsdProcess& operator=(const GpsdProcess&) = delete;
  ~GpsdProcess();

  pid_t pid() const { return pid_; }
  /// False once the process has exited (it is reaped).
  bool running();
  /// SIGTERM, then SIGKILL after a grace period; waits for the exit.
  void stop();
  const std::vector<std::string>& argv() const { return argv_; }

 private:
  GpsdProcess(pid_t pid, std::vector<std::string> argv) : pid_(pid), argv_(std::move(argv)) {}
  pid_t pid_ = -1;
  std::vector<std::string> argv_;
};

}  // namespace tb::its::facilities
