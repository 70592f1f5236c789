#pragma once
/// @file The files of a scenario's test PKI, as its-pki writes them into one directory:
///
///   root.cert  root.pem         the root CA (the scenario's trust anchor)
///   aa.cert    aa.pem           the authorization authority
///   at-<station id>.cert/.pem   each station's authorization ticket
///   at-<station id>.pub.pem     instead of .pem: the other stack's public key it was issued for
///
/// `.cert` files hold a certificate's COER octets (what goes on the air), `.pem` files the
/// P-256 private key (PKCS#8, owner-only). Errors name the file and what was wrong.

#include <cstdint>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>

#include "its-station/security/crypto.hpp"
#include "its-station/security/ieee1609dot2.hpp"

namespace tb::its::security {

class PkiFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PkiPaths {
  std::filesystem::path dir;
  std::filesystem::path root_cert() const { return dir / "root.cert"; }
  std::filesystem::path root_key() const { return dir / "root.pem"; }
  std::filesystem::path aa_cert() const { return dir / "aa.cert"; }
  std::filesystem::path aa_key() const { return dir / "aa.pem"; }
  std::filesystem::path at_cert(std::uint32_t station) const {
    return dir / ("at-" + std::to_string(station) + ".cert");
  }
  std::filesystem::path at_key(std::uint32_t station) const {
    return dir / ("at-" + std::to_string(station) + ".pem");
  }
  /// The outside public key an AT was issued for (its-pki issue), in place of at_key.
  std::filesystem::path at_public_key(std::uint32_t station) const {
    return dir / ("at-" + std::to_string(station) + ".pub.pem");
  }
};

Certificate read_certificate(const std::filesystem::path& file);
void write_certificate(const std::filesystem::path& file, const Certificate& c);

/// What a station needs: the root it trusts, its AA, its AT and the AT's key.
struct StationCredentials {
  Certificate root;
  Certificate aa;
  Certificate at;
  EcKey at_key;
};
StationCredentials load_station_credentials(const PkiPaths& paths, std::uint32_t station);

struct PkiOptions {
  std::string name = "testbed";
  Time32 now = 0;                     ///< TAI seconds; validity starts an hour before
  std::uint16_t ca_hours = 24 * 365;  ///< root and AA
  std::uint16_t ticket_hours = 24 * 7;
  /// Stations that are road-side units: their ATs also carry SPATEM and MAPEM (issue 34).
  std::set<std::uint32_t> road_side_units;
};

/// Makes the root and AA when missing, and the ATs of @p stations that are missing (all of
/// them anew when the root or AA was made). What is there but would not work any more is made
/// anew too: a root or AA that expires within a day or whose AA lacks a permission its-pki gives
/// today (GN-MGMT came later), an AT that expires within an hour, was issued by another AA or
/// lacks a permission. An AT issued for an outside key (issue_ticket) is made anew for that key.
/// Returns the files written.
std::vector<std::filesystem::path> make_pki(const PkiPaths& paths,
                                            const std::vector<std::uint32_t>& stations,
                                            const PkiOptions& options);

/// Issues the AT of @p station for an outside key (another stack's): @p public_key_pem holds a
/// NIST P-256 public key as SubjectPublicKeyInfo PEM (TS 103 097 5.4 / 1609.2 6.4.36 allow
/// brainpoolP256r1 too, but our ATs and the C2C-CC profile use P-256). The AT is our stations'
/// (make_ticket: the same appPermissions and SSPs, valid options.ticket_hours from an hour before
/// options.now), written to at-<station>.cert under the AA; root and AA are made or made anew
/// first as make_pki does. The key is kept as at-<station>.pub.pem, so that make_pki renews the
/// AT for it; a key file the PKI had for that station (at-<station>.pem) is removed: the PKI
/// does not hold the new AT's key. Errors name the key file. Returns the files written.
std::vector<std::filesystem::path> issue_ticket(const PkiPaths& paths, std::uint32_t station,
                                                const std::filesystem::path& public_key_pem,
                                                const PkiOptions& options);

/// Copies what another stack needs to run @p station into @p out (made when missing), under the
/// names of PkiPaths (so that @p out is a PKI directory without the CA keys): root.cert, aa.cert,
/// at-<station>.cert (COER, as our stations read them) and, where the PKI made the AT's key
/// itself, at-<station>.pem (PKCS#8 PEM, owner-only). Checks first that the AT is the AA's and
/// the key the AT's. Returns the files written.
std::vector<std::filesystem::path> export_station(const PkiPaths& paths, std::uint32_t station,
                                                  const std::filesystem::path& out);

}  // namespace tb::its::security
