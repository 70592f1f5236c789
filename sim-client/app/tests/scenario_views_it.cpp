// The driver's view of every shipped scenario (scenarios/*.json), as CI leaves it for a
// reviewer to look at: the real sim-server runs the scenario, the real sim-client drives its
// vehicles (--scripted) and writes a 3D screenshot from the first human vehicle (else the
// first one) under an Xvfb this test starts. The PNGs go to the test log folder,
// <build>/Testing/Temporary/driver-views/<scenario>.png.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "common/scenario/loader.hpp"
#include "sim-client/app/tests/sim_server_process.hpp"
#include "sim-client/view/tests/png_reader.hpp"
#include "sim-client/view3d/tests/xvfb.hpp"

namespace tb::client {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

fs::path root() {
  const char* r = std::getenv("TESTBED_ROOT");
  return r != nullptr ? fs::path(r) : fs::current_path();
}

fs::path bin() {
  const char* b = std::getenv("TESTBED_BIN");
  return b != nullptr ? fs::path(b) : fs::path("build/bin");
}

// Runs a program to its end (at most @p limit); returns the exit code, stderr in @p err.
int run(std::vector<std::string> args, const std::string& err_file, std::chrono::seconds limit) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int e = open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(e, 2);
    dup2(e, 1);
    setenv("ASAN_OPTIONS", "detect_leaks=0", 1);  // Mesa and D-Bus leak at exit, not we
    std::vector<char*> argv;
    for (auto& a : args)
      argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + limit;
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(20ms);
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(ScenarioViews, EveryShippedScenarioHasADriversViewInTheTestLog) {
  testing::Xvfb xvfb;
  if (!xvfb.running())
    GTEST_SKIP() << "Xvfb did not start (scripts/install-deps installs xvfb)";
  const fs::path out = bin() / ".." / "Testing" / "Temporary" / "driver-views";
  fs::create_directories(out);
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(root() / "scenarios"))
    if (e.path().extension() == ".json")
      files.push_back(e.path());
  std::sort(files.begin(), files.end());
  ASSERT_FALSE(files.empty());
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.filename().string());
    const scenario::Scenario sc = scenario::load_file(file);
    std::string who = sc.vehicles.front().id;
    for (const auto& v : sc.vehicles)
      if (std::holds_alternative<scenario::HumanDriver>(v.driver)) {
        who = v.id;
        break;
      }
    testing::SimServerProcess server(file.string());
    if (!server.available())
      GTEST_SKIP() << "no sim-server in " << bin();
    ASSERT_NE(server.port(), 0) << server.log();
    const std::string png = (out / (file.stem().string() + ".png")).string();
    const std::string log = (out / (file.stem().string() + ".log")).string();
    fs::remove(png);
    const int code = run(
        {(bin() / "sim-client").string(), "--server", "127.0.0.1:" + std::to_string(server.port()),
         "--vehicle", who, "--scripted", "--no-forward", "--headless", "--screenshot", png,
         "--after", "2.5", "--duration", "2.6"},
        log, 60s);
    ASSERT_EQ(code, 0) << slurp(log);
    testing::Image im;
    ASSERT_TRUE(testing::read_png(png, im)) << slurp(log);
    EXPECT_EQ(im.width, 1280);
    EXPECT_EQ(im.height, 720);
    EXPECT_GT(testing::distinct_colours(im), 30);
    std::cout << "driver's view of " << file.filename().string() << " (" << who
              << "): " << fs::canonical(png).string() << "\n";
  }
}

}  // namespace
}  // namespace tb::client
