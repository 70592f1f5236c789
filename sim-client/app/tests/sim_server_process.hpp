#pragma once
// For sim-client's integration tests and benchmarks: the real sim-server program from
// $TESTBED_BIN on a free loopback port (read from its log), stopped with SIGTERM (then
// SIGKILL) when the object goes.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace tb::client::testing {

class SimServerProcess {
 public:
  /// Runs the scenario whose JSON text is @p scenario_json.
  static SimServerProcess with_text(const std::string& scenario_json) {
    SimServerProcess p;
    p.start_text(scenario_json);
    return p;
  }
  explicit SimServerProcess(const std::string& scenario_file = "") {
    if (!scenario_file.empty())
      start(scenario_file);
  }
  SimServerProcess(SimServerProcess&& o) noexcept
      : exe_(std::move(o.exe_)),
        dir_(std::move(o.dir_)),
        log_(std::move(o.log_)),
        pid_(o.pid_),
        port_(o.port_) {
    o.pid_ = -1;
    o.dir_.clear();
  }
  SimServerProcess& operator=(SimServerProcess&&) = delete;

  void start_text(const std::string& scenario_json, const std::vector<std::string>& extra = {}) {
    make_dir();
    std::ofstream(dir_ + "/scenario.json") << scenario_json;
    start(dir_ + "/scenario.json", extra);
  }

  /// @p extra: more options for sim-server (e.g. --trace FILE).
  void start(const std::string& scenario_file, const std::vector<std::string>& extra = {}) {
    const char* b = std::getenv("TESTBED_BIN");
    exe_ = std::string(b != nullptr ? b : "build/bin") + "/sim-server";
    if (!std::filesystem::exists(exe_))
      return;
    make_dir();
    log_ = dir_ + "/server.log";
    pid_ = fork();
    if (pid_ == 0) {
      const int fd = ::open(log_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      dup2(fd, 1);
      dup2(fd, 2);
      std::vector<std::string> args = {exe_, "--scenario", scenario_file, "--port",
                                       "0",  "--bind",     "127.0.0.1"};
      args.insert(args.end(), extra.begin(), extra.end());
      std::vector<char*> argv;
      for (auto& a : args)
        argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(argv[0], argv.data());
      _exit(127);
    }
    const std::regex listening(R"(listening on [^ ]*:(\d+))");
    for (int i = 0; i < 250 && port_ == 0; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      std::ifstream in(log_);
      std::stringstream s;
      s << in.rdbuf();
      const std::string text = s.str();
      std::smatch m;
      if (std::regex_search(text, m, listening))
        port_ = static_cast<std::uint16_t>(std::stoi(m[1]));
    }
  }
  ~SimServerProcess() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      int status = 0;
      for (int i = 0; i < 100 && waitpid(pid_, &status, WNOHANG) == 0; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      if (waitpid(pid_, &status, WNOHANG) == 0) {
        kill(pid_, SIGKILL);
        waitpid(pid_, &status, 0);
      }
    }
    if (!dir_.empty())
      std::filesystem::remove_all(dir_);
  }
  bool available() const { return !exe_.empty() && std::filesystem::exists(exe_); }
  std::uint16_t port() const { return port_; }
  std::string log() const {
    std::ifstream in(log_);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

 private:
  void make_dir() {
    if (!dir_.empty())
      return;
    static int n = 0;
    dir_ = (std::filesystem::temp_directory_path() /
            ("simclient_server_" + std::to_string(getpid()) + "_" + std::to_string(n++)))
               .string();
    std::filesystem::create_directories(dir_);
  }
  std::string exe_, dir_, log_;
  pid_t pid_ = -1;
  std::uint16_t port_ = 0;
};

}  // namespace tb::client::testing
