#include "its-station/security/pki_files.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>

#include "its-station/security/pki.hpp"

namespace tb::its::security {

namespace fs = std::filesystem;

Certificate read_certificate(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw PkiFileError(file.string() + ": cannot open");
  const Bytes b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto c = decode_certificate(b);
  if (!c)
    throw PkiFileError(file.string() + ": not a COER certificate: " + asn1::to_string(c.error()));
  return std::move(*c);
}

void write_certificate(const fs::path& file, const Certificate& c) {
  const Bytes b = c.encoding.empty() ? encode(c) : c.encoding;
  const fs::path tmp = file.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out)
      throw PkiFileError(tmp.string() + ": cannot create");
    out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    if (!out)
      throw PkiFileError(tmp.string() + ": cannot write");
  }
  fs::rename(tmp, file);  // readers never see half a certificate
}

StationCredentials load_station_credentials(const PkiPaths& paths, std::uint32_t station) {
  StationCredentials c;
  c.root = read_certificate(paths.root_cert());
  c.aa = read_certificate(paths.aa_cert());
  c.at = read_certificate(paths.at_cert(station));
  try {
    c.at_key = EcKey::load_private_pem(paths.at_key(station).string());
  } catch (const CryptoError& e) {
    throw PkiFileError(e.what());
  }
  if (c.at.tbs.verify_key.point != c.at_key.public_point())
    throw PkiFileError(paths.at_key(station).string() + ": not the key of " +
                       paths.at_cert(station).string());
  return c;
}

namespace {

/// Whether @p c is still valid @p margin seconds after @p now.
bool lasts(const Certificate& c, Time32 now, std::uint32_t margin) {
  return c.tbs.validity.start <= now &&
         c.tbs.validity.end_seconds() > static_cast<std::uint64_t>(now) + margin;
}

/// Whether @p aa may issue every psid today's its-pki gives its ATs.
bool issues_all(const Certificate& aa) {
  if (!aa.tbs.cert_issue_permissions)
    return false;
  for (const auto& want : authority_issue_permissions()) {
    bool found = false;
    for (const auto& g : *aa.tbs.cert_issue_permissions)
      for (const auto& p : g.psids)
        found = found || p.psid == want.psid;
    if (!found)
      return false;
  }
  return true;
}

/// Whether @p at has exactly the permissions (with their SSPs) today's its-pki gives the AT of
/// a vehicle or (@p road_side_unit) an RSU: a station that became an RSU or stopped being one
/// gets a new AT.
bool permits_all(const Certificate& at, bool road_side_unit) {
  if (!at.tbs.app_permissions)
    return false;
  const auto want = ticket_permissions(road_side_unit);
  return std::is_permutation(want.begin(), want.end(), at.tbs.app_permissions->begin(),
                             at.tbs.app_permissions->end());
}

}  // namespace

std::vector<fs::path> make_pki(const PkiPaths& paths, const std::vector<std::uint32_t>& stations,
                               const PkiOptions& o) {
  std::vector<fs::path> written;
  std::error_code ec;
  fs::create_directories(paths.dir, ec);
  if (ec)
    throw PkiFileError(paths.dir.string() + ": cannot create (" + ec.message() + ")");
  const Time32 start = o.now > 3600 ? o.now - 3600 : 0;  // tolerate clocks an hour behind
  auto save_key = [&](const EcKey& k, const fs::path& p) {
    try {
      k.save_private_pem(p.string());
    } catch (const CryptoError& e) {
      throw PkiFileError(e.what());
    }
    written.push_back(p);
  };
  constexpr std::uint32_t kCaMargin = 24 * 3600;
  constexpr std::uint32_t kTicketMargin = 3600;

  bool fresh_ca = !fs::exists(paths.root_cert()) || !fs::exists(paths.root_key()) ||
                  !fs::exists(paths.aa_cert()) || !fs::exists(paths.aa_key());
  Certificate root;
  EcKey root_key;
  Certificate aa;
  EcKey aa_key;
  if (!fresh_ca) {
    root = read_certificate(paths.root_cert());
    aa = read_certificate(paths.aa_cert());
    fresh_ca = !lasts(root, o.now, kCaMargin) || !lasts(aa, o.now, kCaMargin) || !issues_all(aa);
  }
  if (fresh_ca) {
    fresh_ca = true;
    root_key = EcKey::generate(EccCurve::kNistP256);
    root = make_root(root_key, o.name + " root", {start, DurationUnit::kHours, o.ca_hours});
    aa_key = EcKey::generate(EccCurve::kNistP256);
    aa = make_authority(aa_key, o.name + " aa", {start, DurationUnit::kHours, o.ca_hours}, root,
                        root_key);
    save_key(root_key, paths.root_key());
    write_certificate(paths.root_cert(), root);
    written.push_back(paths.root_cert());
    save_key(aa_key, paths.aa_key());
    write_certificate(paths.aa_cert(), aa);
    written.push_back(paths.aa_cert());
  } else {
    try {
      aa_key = EcKey::load_private_pem(paths.aa_key().string());
    } catch (const CryptoError& e) {
      throw PkiFileError(e.what());
    }
  }
  const HashedId8 aa_id = certificate_id(aa);
  for (const auto station : stations) {
    const bool rsu = o.road_side_units.contains(station);
    // An AT issued for another stack's key (issue_ticket): renewed for that key.
    const bool outside =
        !fs::exists(paths.at_key(station)) && fs::exists(paths.at_public_key(station));
    if (!fresh_ca && fs::exists(paths.at_cert(station)) &&
        (outside || fs::exists(paths.at_key(station)))) {
      const Certificate at = read_certificate(paths.at_cert(station));
      if (at.issuer.kind == IssuerIdentifier::Kind::kSha256AndDigest && at.issuer.digest == aa_id &&
          lasts(at, o.now, kTicketMargin) && permits_all(at, rsu))
        continue;
    }
    const ValidityPeriod validity{start, DurationUnit::kHours, o.ticket_hours};
    if (outside) {
      EcKey k;
      try {
        k = EcKey::load_public_pem(paths.at_public_key(station).string());
      } catch (const CryptoError& e) {
        throw PkiFileError(e.what());
      }
      write_certificate(paths.at_cert(station), make_ticket(k, validity, aa, aa_key, rsu));
      written.push_back(paths.at_cert(station));
      continue;
    }
    EcKey k = EcKey::generate(EccCurve::kNistP256);
    const Certificate at = make_ticket(k, validity, aa, aa_key, rsu);
    std::error_code gone;
    fs::remove(paths.at_public_key(station), gone);  // the AT is of the PKI's key from now on
    save_key(k, paths.at_key(station));
    write_certificate(paths.at_cert(station), at);
    written.push_back(paths.at_cert(station));
  }
  return written;
}

std::vector<fs::path> issue_ticket(const PkiPaths& paths, std::uint32_t station,
                                   const fs::path& public_key_pem, const PkiOptions& o) {
  EcKey key;
  try {
    key = EcKey::load_public_pem(public_key_pem.string());
  } catch (const CryptoError& e) {
    throw PkiFileError(e.what());
  }
  if (key.curve() != EccCurve::kNistP256)
    throw PkiFileError(public_key_pem.string() +
                       ": a brainpoolP256r1 key; its-pki issues ATs for NIST P-256 keys only");
  std::error_code ec;
  fs::create_directories(paths.dir, ec);
  for (const auto& stale : {paths.at_key(station), paths.at_cert(station)}) {
    fs::remove(stale, ec);
    if (ec)
      throw PkiFileError(stale.string() + ": cannot remove (" + ec.message() + ")");
  }
  try {
    key.save_public_pem(paths.at_public_key(station).string());
  } catch (const CryptoError& e) {
    throw PkiFileError(e.what());
  }
  auto written = make_pki(paths, {station}, o);  // root and AA valid at o.now, then the AT
  written.insert(written.begin(), paths.at_public_key(station));
  return written;
}

std::vector<fs::path> export_station(const PkiPaths& paths, std::uint32_t station,
                                     const fs::path& out) {
  const Certificate aa = read_certificate(paths.aa_cert());
  const Certificate at = read_certificate(paths.at_cert(station));
  read_certificate(paths.root_cert());
  if (at.issuer.kind != IssuerIdentifier::Kind::kSha256AndDigest ||
      at.issuer.digest != certificate_id(aa))
    throw PkiFileError(paths.at_cert(station).string() + ": not issued by " +
                       paths.aa_cert().string() + " (make it anew: its-pki make or issue)");
  const bool with_key = fs::exists(paths.at_key(station));
  if (with_key)
    load_station_credentials(paths, station);  // the key is the AT's
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec)
    throw PkiFileError(out.string() + ": cannot create (" + ec.message() + ")");
  const PkiPaths to{out};
  std::vector<std::pair<fs::path, fs::path>> files{{paths.root_cert(), to.root_cert()},
                                                   {paths.aa_cert(), to.aa_cert()},
                                                   {paths.at_cert(station), to.at_cert(station)}};
  if (with_key)
    files.emplace_back(paths.at_key(station), to.at_key(station));
  else
    fs::remove(to.at_key(station), ec);  // an older export's key is not this AT's
  std::vector<fs::path> written;
  for (const auto& [from, dest] : files) {
    if (fs::exists(dest) && fs::equivalent(from, dest))
      continue;  // exported into the PKI's own directory
    fs::copy_file(from, dest, fs::copy_options::overwrite_existing, ec);
    if (ec)
      throw PkiFileError(dest.string() + ": cannot write (" + ec.message() + ")");
    if (dest == to.at_key(station))
      fs::permissions(dest, fs::perms::owner_read | fs::perms::owner_write, ec);
    written.push_back(dest);
  }
  return written;
}

}  // namespace tb::its::security
