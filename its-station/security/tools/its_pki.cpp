// its-pki: makes a scenario's test PKI (root CA, AA, one AT per station; TS 103 097 explicit
// certificates with P-256 keys) in a directory, issues an AT for another stack's key, exports
// what another stack needs, or shows a certificate file.
//
//   its-pki make --dir pki/ --station 1001 --station 1002 [--at 2025-06-02T09:00:00Z]
//   its-pki issue --dir pki/ --station 9001 --public-key key.pem [--at UTC]
//   its-pki export --dir pki/ --station 9001 --out probe/
//   its-pki show pki/at-1001.cert

#include <CLI/CLI.hpp>

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "common/clock/clock.hpp"
#include "common/clock/utc.hpp"
#include "its-station/security/pki.hpp"
#include "its-station/security/pki_files.hpp"
#include "its-station/security/time.hpp"

namespace {

using namespace tb::its::security;

std::string hex(std::span<const std::uint8_t> b) {
  std::ostringstream s;
  for (auto v : b)
    s << std::hex << std::setw(2) << std::setfill('0') << static_cast<unsigned>(v);
  return s.str();
}

void show(const std::string& file) {
  const Certificate c = read_certificate(file);
  std::cout << "file: " << file << "\n";
  std::cout << "hashedId8: " << hex(certificate_id(c)) << "\n";
  std::cout << "size: " << canonical_encoding(c).size() << " octets\n";
  std::cout << "issuer: "
            << (c.issuer.kind == IssuerIdentifier::Kind::kSelf ? "self" : hex(c.issuer.digest))
            << "\n";
  std::cout << "id: "
            << (c.tbs.id.kind == CertificateId::Kind::kName
                    ? std::string(c.tbs.id.value.begin(), c.tbs.id.value.end())
                    : std::string(c.tbs.id.kind == CertificateId::Kind::kNone ? "none" : "other"))
            << "\n";
  std::cout << "validity: start " << c.tbs.validity.start << " s TAI since 2004, end "
            << c.tbs.validity.end_seconds() << "\n";
  if (c.tbs.app_permissions)
    for (const auto& p : *c.tbs.app_permissions)
      std::cout << "appPermission: psid " << p.psid
                << (p.ssp ? " ssp " + hex(p.ssp->bytes) : std::string()) << "\n";
  if (c.tbs.cert_issue_permissions)
    std::cout << "certIssuePermissions: " << c.tbs.cert_issue_permissions->size() << " group(s)\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"its-pki: a test PKI (root, AA, ATs) for the testbed's signed V2X"};
  app.require_subcommand(1);
  std::string dir;
  std::vector<std::uint32_t> stations;
  PkiOptions options;
  auto* make = app.add_subcommand("make", "make what is missing of root, AA and the stations' ATs");
  make->add_option("--dir", dir, "directory of the PKI files")->required();
  make->add_option("--station", stations, "station id that gets an AT (repeatable)");
  std::vector<std::uint32_t> rsu_stations;
  make->add_option("--rsu-station", rsu_stations,
                   "station id of a road-side unit: its AT also carries SPATEM (137) and MAPEM "
                   "(138) (repeatable; implies --station)");
  make->add_option("--name", options.name, "name in the root's and AA's certificates");
  make->add_option("--ticket-hours", options.ticket_hours, "AT validity in hours")
      ->check(CLI::Range(1, 65535));
  make->add_option("--ca-hours", options.ca_hours, "root and AA validity in hours")
      ->check(CLI::Range(1, 65535));
  std::string at_text;
  make->add_option("--at", at_text,
                   "UTC instant (ISO 8601, 2025-06-02T09:00:00Z) taken as now instead of the "
                   "host's clock: the world's start time of a scenario that pins one");
  std::uint32_t station = 0;
  std::string public_key;
  auto* issue = app.add_subcommand(
      "issue", "issue the AT of a station for an outside P-256 public key (another stack's)");
  issue->add_option("--dir", dir, "directory of the PKI files")->required();
  issue->add_option("--station", station, "station id of the AT (file at-ID.cert)")->required();
  issue->add_option("--public-key", public_key, "P-256 public key, SubjectPublicKeyInfo PEM")
      ->required();
  issue->add_option("--at", at_text, "UTC instant taken as now (as for make)");
  bool issue_rsu = false;
  issue->add_flag("--rsu", issue_rsu, "the station is a road-side unit (SPATEM and MAPEM too)");
  issue->add_option("--ticket-hours", options.ticket_hours, "AT validity in hours")
      ->check(CLI::Range(1, 65535));
  std::string out;
  auto* export_cmd = app.add_subcommand(
      "export",
      "copy root.cert, aa.cert, at-ID.cert (COER) and at-ID.pem (when the PKI made the "
      "key) into a folder for another stack");
  export_cmd->add_option("--dir", dir, "directory of the PKI files")->required();
  export_cmd->add_option("--station", station, "station id of the AT")->required();
  export_cmd->add_option("--out", out, "folder to write the files to")->required();
  std::string file;
  auto* show_cmd = app.add_subcommand("show", "print a certificate file's fields");
  show_cmd->add_option("file", file, "a .cert file")->required();
  CLI11_PARSE(app, argc, argv);
  tb::clock::WallTime now = tb::clock::WallClock::now();
  if (!at_text.empty()) {
    const auto at = tb::clock::parse_utc(at_text);
    // 1609.2 times count from 2004 (6.4.12): an earlier "now" has no Time32.
    if (!at || tb::clock::to_unix_ns(*at) < kEpoch2004UnixSeconds * 1'000'000'000) {
      std::cerr << "its-pki: --at '" << at_text
                << "': not a UTC time after 2004 like 2025-06-02T09:00:00Z (ISO 8601, ending in "
                   "Z)\n";
      return 2;
    }
    now = *at;
  }
  options.now = to_time32(now);
  auto print_written = [](const std::vector<std::filesystem::path>& written) {
    for (const auto& p : written)
      std::cout << "wrote " << p.string() << "\n";
  };
  try {
    if (*make) {
      for (const std::uint32_t id : rsu_stations) {
        options.road_side_units.insert(id);
        if (std::find(stations.begin(), stations.end(), id) == stations.end())
          stations.push_back(id);
      }
      const auto written = make_pki(PkiPaths{dir}, stations, options);
      print_written(written);
      if (written.empty())
        std::cout << "nothing to do: " << dir << " has every file\n";
    } else if (*issue) {
      if (issue_rsu)
        options.road_side_units.insert(station);
      print_written(issue_ticket(PkiPaths{dir}, station, public_key, options));
    } else if (*export_cmd) {
      print_written(export_station(PkiPaths{dir}, station, out));
    } else if (*show_cmd) {
      show(file);
    }
  } catch (const std::exception& e) {
    std::cerr << "its-pki: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
