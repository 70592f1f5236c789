#pragma once
// For tests that render: an Xvfb X server (Mesa's llvmpipe renders GL into it) that the test
// starts itself, on a free display that Xvfb picks (-displayfd), with DISPLAY pointing at it.

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <optional>
#include <string>
#include <thread>

namespace tb::client::testing {

class Xvfb {
 public:
  explicit Xvfb(const std::string& screen = "1280x720x24") {
    if (const char* d = std::getenv("DISPLAY"))
      previous_ = d;
    int fds[2];
    if (::pipe(fds) != 0)
      return;
    pid_ = ::fork();
    if (pid_ == 0) {
      ::close(fds[0]);
      const std::string fd = std::to_string(fds[1]);
      ::execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", screen.c_str(),
               "-nolisten", "tcp", "-noreset", static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ::close(fds[1]);
    // Xvfb writes the display number once it accepts connections.
    std::string number;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (std::chrono::steady_clock::now() < deadline) {
      pollfd p{fds[0], POLLIN, 0};
      if (::poll(&p, 1, 200) <= 0)
        continue;
      char c = 0;
      if (::read(fds[0], &c, 1) != 1)
        break;
      if (c == '\n') {
        display_ = ":" + number;
        break;
      }
      number += c;
    }
    ::close(fds[0]);
    if (!display_.empty())
      ::setenv("DISPLAY", display_.c_str(), 1);
  }
  ~Xvfb() {
    if (previous_)
      ::setenv("DISPLAY", previous_->c_str(), 1);
    else
      ::unsetenv("DISPLAY");
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      int status = 0;
      ::waitpid(pid_, &status, 0);
    }
  }
  Xvfb(const Xvfb&) = delete;
  Xvfb& operator=(const Xvfb&) = delete;
  bool running() const { return !display_.empty(); }
  const std::string& display() const { return display_; }

 private:
  pid_t pid_ = -1;
  std::string display_;
  std::optional<std::string> previous_;
};

}  // namespace tb::client::testing
