// scenario-check: validates scenario files and prints a summary; exit code 2 names the first
// problem (file, JSON path, reason), as every program of the testbed does on a bad scenario.
// With --describe / --where / --export-xodr it prints or writes the scenario's road network
// (an .xodr file may be given instead of a scenario for --describe and --where).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <fstream>
#include <string>
#include <variant>

#include "common/map/describe.hpp"
#include "common/map/opendrive/reader.hpp"
#include "common/map/opendrive/writer.hpp"
#include "common/map/scenario_map.hpp"
#include "common/scenario/loader.hpp"

namespace {

bool is_xodr(const std::string& f) {
  return f.size() > 5 && f.compare(f.size() - 5, 5, ".xodr") == 0;
}

/// The road network of a scenario or .xodr file, and where its geographic origin comes from.
struct LoadedNetwork {
  std::shared_ptr<const tb::map::odr::RoadNetwork> net;
  tb::map::OriginSource origin;
};

LoadedNetwork load_network(const std::string& f) {
  if (is_xodr(f)) {
    const tb::map::ScenarioMap m(
        std::make_shared<const tb::map::odr::RoadNetwork>(tb::map::odr::load_opendrive(f)),
        std::nullopt);
    return {m.shared_network(), m.origin()};
  }
  const auto s = tb::scenario::load_file(f);
  const tb::map::ScenarioMap m(s);
  return {m.shared_network(), m.origin()};
}

int summary(const std::string& f, bool quiet) {
  const auto s = tb::scenario::load_file(f);
  if (!quiet) {
    std::printf("%s: ok: \"%s\", %zu vehicle(s)\n", f.c_str(), s.name.c_str(), s.vehicles.size());
    for (const auto& v : s.vehicles) {
      const char* driver = std::holds_alternative<tb::scenario::HumanDriver>(v.driver) ? "human"
                           : std::holds_alternative<tb::scenario::TimelineDriver>(v.driver)
                               ? "timeline"
                               : "lane_follow";
      const bool pooled = v.station_kind == tb::scenario::StationKind::kPooled;
      std::printf("  %-12s station %-10u driver %-11s %s%s%s\n", v.id.c_str(), v.station_id, driver,
                  pooled ? "pooled" : "full", v.station_mqtt ? " mqtt" : "",
                  v.station_lcrw ? " lcrw" : "");
    }
    for (const auto& p : s.signals) {
      std::string phases;
      for (const auto& ph : p.phases) {
        std::string g;
        for (int id : ph.green)
          g += (g.empty() ? "" : ",") + std::to_string(id);
        char d[32];
        std::snprintf(d, sizeof d, "%g", ph.duration_s);
        phases += (phases.empty() ? "" : ", ") + ("[" + g + "] " + d + " s");
      }
      std::printf(
          "  signals at junction %s%s: %s; amber %g s, all-red %g s, red+amber %g s, "
          "offset %g s, cycle %g s\n",
          p.junction.c_str(), p.default_plan ? " (default plan)" : "", phases.c_str(), p.amber_s,
          p.all_red_s, p.red_amber_s, p.offset_s, p.cycle_s());
    }
    for (const auto& r : s.rsus)
      std::printf("  %-12s station %-10u rsu at junction %s, (%g, %g), %g m up\n", r.id.c_str(),
                  r.station_id, r.junction.c_str(), r.x, r.y, r.height_m);
  }
  return 0;
}

int export_xodr(const std::string& f, const std::string& out) {
  const auto loaded = load_network(f);
  std::ofstream o(out, std::ios::binary);
  o << tb::map::odr::write_opendrive(*loaded.net);
  o.close();
  if (!o) {
    std::fprintf(stderr, "error: %s: cannot write\n", out.c_str());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Validate testbed scenario files"};
  std::vector<std::string> files;
  bool quiet = false;
  bool describe = false;
  std::vector<double> where;
  std::string export_to;
  app.add_option("files", files, "scenario files (JSON), or .xodr for --describe/--where")
      ->required();
  app.add_flag("-q,--quiet", quiet, "print only errors");
  app.add_flag("--describe", describe, "print each file's road network as JSON");
  app.add_option("--where", where, "print the lane under the point X Y (m, map frame) as JSON")
      ->expected(2);
  app.add_option("--export-xodr", export_to, "write the (one) scenario's map as an OpenDRIVE file");
  CLI11_PARSE(app, argc, argv);
  if (!export_to.empty() && files.size() != 1) {
    std::fprintf(stderr, "error: --export-xodr takes exactly one scenario file\n");
    return tb::scenario::kExitBadScenario;
  }

  int rc = 0;
  for (const auto& f : files) {
    try {
      if (!export_to.empty()) {
        rc = std::max(rc, export_xodr(f, export_to));
      } else if (describe || !where.empty()) {
        const auto loaded = load_network(f);
        if (describe)
          std::printf("%s\n", tb::map::describe(*loaded.net, loaded.origin).dump(2).c_str());
        if (!where.empty()) {
          std::printf("%s\n", tb::map::where(*loaded.net, where[0], where[1]).dump().c_str());
        }
      } else {
        summary(f, quiet);
      }
    } catch (const tb::scenario::ScenarioError& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      rc = tb::scenario::kExitBadScenario;
    } catch (const tb::map::odr::MapError& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      rc = tb::scenario::kExitBadScenario;
    }
  }
  return rc;
}
