// scenario-check: validates scenario files and prints a summary; exit code 2 names the first
// problem (file, JSON path, reason), as every program of the testbed does on a bad scenario.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <variant>

#include "common/scenario/loader.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Validate testbed scenario files"};
  std::vector<std::string> files;
  bool quiet = false;
  app.add_option("files", files, "scenario files (JSON)")->required();
  app.add_flag("-q,--quiet", quiet, "print only errors");
  CLI11_PARSE(app, argc, argv);

  int rc = 0;
  for (const auto& f : files) {
    try {
      const auto s = tb::scenario::load_file(f);
      if (!quiet) {
        std::printf("%s: ok: \"%s\", %zu vehicle(s)\n", f.c_str(), s.name.c_str(),
                    s.vehicles.size());
        for (const auto& v : s.vehicles) {
          const char* driver = std::holds_alternative<tb::scenario::HumanDriver>(v.driver) ? "human"
                               : std::holds_alternative<tb::scenario::TimelineDriver>(v.driver)
                                   ? "timeline"
                                   : "lane_follow";
          std::printf("  %-12s station %-10u driver %s\n", v.id.c_str(), v.station_id, driver);
        }
      }
    } catch (const tb::scenario::ScenarioError& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      rc = tb::scenario::kExitBadScenario;
    }
  }
  return rc;
}
