// its-pki: makes a scenario's test PKI (root CA, AA, one AT per station; TS 103 097 explicit
// certificates with P-256 keys) in a directory, or shows a certificate file.
//
//   its-pki make --dir pki/ --station 1001 --station 1002 [--at 2025-06-02T09:00:00Z]
//   its-pki show pki/at-1001.cert

#include <CLI/CLI.hpp>

#include <ctime>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

#include "common/clock/clock.hpp"
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

/// A UTC instant written YYYY-MM-DDThh:mm:ssZ (a scenario's start_time, whole seconds), or
/// nothing when the text is not one.
std::optional<tb::clock::WallTime> parse_utc(const std::string& text) {
  std::tm tm{};
  const char* end = strptime(text.c_str(), "%Y-%m-%dT%H:%M:%S", &tm);
  if (end == nullptr || std::string(end) != "Z")
    return std::nullopt;
  const std::time_t t = timegm(&tm);
  if (t < kEpoch2004UnixSeconds)
    return std::nullopt;
  return tb::clock::WallClock::from_time_t(t);
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
  make->add_option("--name", options.name, "name in the root's and AA's certificates");
  make->add_option("--ticket-hours", options.ticket_hours, "AT validity in hours")
      ->check(CLI::Range(1, 65535));
  make->add_option("--ca-hours", options.ca_hours, "root and AA validity in hours")
      ->check(CLI::Range(1, 65535));
  std::string at;
  make->add_option("--at", at,
                   "the world's time the PKI must be valid at (a scenario's pinned start_time, "
                   "YYYY-MM-DDThh:mm:ssZ; default: now). Certificates not valid then are "
                   "made again");
  std::string file;
  auto* show_cmd = app.add_subcommand("show", "print a certificate file's fields");
  show_cmd->add_option("file", file, "a .cert file")->required();
  CLI11_PARSE(app, argc, argv);
  try {
    if (*make) {
      auto now = tb::clock::WallClock::now();
      if (!at.empty()) {
        const auto parsed = parse_utc(at);
        if (!parsed) {
          std::cerr << "its-pki: --at '" << at
                    << "': expected a UTC time after 2004 like 2025-06-02T09:00:00Z\n";
          return 2;
        }
        now = *parsed;
      }
      options.now = to_time32(now);
      const auto written = make_pki(PkiPaths{dir}, stations, options);
      for (const auto& p : written)
        std::cout << "wrote " << p.string() << "\n";
      if (written.empty())
        std::cout << "nothing to do: " << dir << " has every file\n";
    } else if (*show_cmd) {
      show(file);
    }
  } catch (const std::exception& e) {
    std::cerr << "its-pki: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
