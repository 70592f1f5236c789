// The driver's view of every shipped scenario (scenarios/*.json), as CI leaves it for a
// reviewer to look at: the real sim-server runs the scenario, the real sim-client drives its
// vehicles (--scripted) and writes a 3D screenshot from the first human vehicle (else the
// first one) under an Xvfb this test starts. The PNGs go to the test log folder,
// <build>/Testing/Temporary/driver-views/<scenario>.png.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "common/scenario/loader.hpp"
#include "sim-client/app/tests/run_program.hpp"
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
    const scenario::Vehicle* who = &sc.vehicles.front();
    for (const auto& v : sc.vehicles)
      if (std::holds_alternative<scenario::HumanDriver>(v.driver)) {
        who = &v;
        break;
      }
    testing::SimServerProcess server(file.string());
    if (!server.available())
      GTEST_SKIP() << "no sim-server in " << bin();
    ASSERT_NE(server.port(), 0) << server.log();
    const std::string png = (out / (file.stem().string() + ".png")).string();
    const std::string log = (out / (file.stem().string() + ".log")).string();
    fs::remove(png);
    const auto r = testing::run(
        {(bin() / "sim-client").string(), "--server", "127.0.0.1:" + std::to_string(server.port()),
         "--vehicle", who->id, "--scripted", "--no-forward", "--headless", "--screenshot", png,
         "--after", "2.5", "--duration", "2.6"},
        60s, {{"ASAN_OPTIONS", "detect_leaks=0"}});  // Mesa and D-Bus leak at exit, not we
    std::ofstream(log) << r.out << r.err;
    ASSERT_EQ(r.code, 0) << r.err;
    testing::Image im;
    ASSERT_TRUE(testing::read_png(png, im)) << r.err;
    EXPECT_EQ(im.width, 1280);
    EXPECT_EQ(im.height, 720);
    EXPECT_GT(testing::distinct_colours(im), 30);
    // The chase camera follows that car: its colour (its roof, lit by the sun) is just below
    // the middle of the picture.
    const unsigned rgb = std::stoul(who->color.substr(1), nullptr, 16);
    const int roof = testing::count_near(im, 640, 410, 60, static_cast<std::uint8_t>(rgb >> 16),
                                         static_cast<std::uint8_t>(rgb >> 8),
                                         static_cast<std::uint8_t>(rgb), 40);
    EXPECT_GT(roof, 500) << who->id << " (" << who->color << ") is not where the camera looks";
    std::cout << "driver's view of " << file.filename().string() << " (" << who->id
              << "): " << fs::canonical(png).string() << "\n";
  }
}

}  // namespace
}  // namespace tb::client
