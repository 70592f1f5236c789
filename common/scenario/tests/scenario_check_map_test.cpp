// scenario-check's map options, run as the program: --export-xodr, --describe, --where.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "common/map/builtin_network.hpp"
#include "common/map/opendrive/reader.hpp"
#include "common/scenario/loader.hpp"

namespace tb::scenario {
namespace {

namespace fs = std::filesystem;

struct Result {
  int status = -1;
  std::string out;
};

Result run(const std::string& args) {
  const char* bin = std::getenv("TESTBED_BIN");
  Result r;
  if (bin == nullptr)
    return r;
  FILE* p = ::popen((std::string(bin) + "/scenario-check " + args + " 2>&1").c_str(), "r");
  if (p == nullptr)
    return r;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), p) != nullptr)
    r.out += buf.data();
  const int status = ::pclose(p);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

fs::path root() {
  const char* r = std::getenv("TESTBED_ROOT");
  return r != nullptr ? fs::path(r) : fs::current_path();
}

TEST(ScenarioCheckMap, ExportsEveryShippedScenariosMapAsOpenDrive) {
  ASSERT_NE(std::getenv("TESTBED_BIN"), nullptr) << "TESTBED_BIN is set by ctest";
  const fs::path out =
      fs::temp_directory_path() / ("export-" + std::to_string(::getpid()) + ".xodr");
  int n = 0;
  for (const auto& e : fs::directory_iterator(root() / "scenarios")) {
    if (e.path().extension() != ".json")
      continue;
    SCOPED_TRACE(e.path().string());
    const auto spec = load_file(e.path().string()).map;
    if (spec.type == scenario::MapType::kOpenDrive)
      continue;  // its map is a file already; the export is of the built-in layouts
    const Result r = run("--export-xodr " + out.string() + " " + e.path().string());
    ASSERT_EQ(r.status, 0) << r.out;
    const auto net = map::odr::load_opendrive(out.string());
    const auto want = map::generate_network(spec);
    ASSERT_EQ(net.roads.size(), want.roads.size());
    for (std::size_t i = 0; i < net.roads.size(); ++i) {
      EXPECT_DOUBLE_EQ(net.roads[i].length, want.roads[i].length);
      const auto a = net.roads[i].borders(0, 10);
      const auto b = want.roads[i].borders(0, 10);
      EXPECT_EQ(a.left, b.left);
      EXPECT_EQ(a.right, b.right);
    }
    ++n;
  }
  fs::remove(out);
  EXPECT_GE(n, 4);
}

TEST(ScenarioCheckMap, DescribesAndLocates) {
  const std::string frontal = (root() / "scenarios" / "lcrw-frontal.json").string();
  const Result d = run("--describe " + frontal);
  ASSERT_EQ(d.status, 0) << d.out;
  const auto j = nlohmann::json::parse(d.out);
  EXPECT_EQ(j["roads"], 1);
  EXPECT_EQ(j["origin"]["source"], "scenario origin");
  EXPECT_GT(j["lane_metres_by_type"]["driving"].get<double>(), 100.0);
  const Result w = run("--where 100 -1.75 " + frontal);
  ASSERT_EQ(w.status, 0) << w.out;
  const auto at = nlohmann::json::parse(w.out);
  EXPECT_EQ(at["road"], "0");
  EXPECT_EQ(at["lane"], -1);
  EXPECT_NEAR(at["s"].get<double>(), 100.0, 1e-9);
  EXPECT_EQ(nlohmann::json::parse(run("--where 100 50 " + frontal).out), nullptr);
}

TEST(ScenarioCheckMap, BadOpenDriveExitsTwoNamingTheElement) {
  const fs::path bad = fs::temp_directory_path() / ("bad-" + std::to_string(::getpid()) + ".xodr");
  {
    std::FILE* f = std::fopen(bad.c_str(), "w");
    ASSERT_NE(f, nullptr);
    std::fputs(
        R"(<OpenDRIVE><road id="5" length="3"><planView><geometry s="0" x="0" y="0" hdg="0" length="-1"><line/></geometry></planView></road></OpenDRIVE>)",
        f);
    std::fclose(f);
  }
  const Result r = run("--describe " + bad.string());
  fs::remove(bad);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find(bad.string() + ": road[@id='5']/planView/geometry[1]: length must be > 0"),
            std::string::npos)
      << r.out;
}

}  // namespace
}  // namespace tb::scenario
