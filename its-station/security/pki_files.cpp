#include "its-station/security/pki_files.hpp"

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
  bool fresh_ca = false;
  Certificate root;
  EcKey root_key;
  Certificate aa;
  EcKey aa_key;
  if (!fs::exists(paths.root_cert()) || !fs::exists(paths.root_key()) ||
      !fs::exists(paths.aa_cert()) || !fs::exists(paths.aa_key())) {
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
    aa = read_certificate(paths.aa_cert());
    try {
      aa_key = EcKey::load_private_pem(paths.aa_key().string());
    } catch (const CryptoError& e) {
      throw PkiFileError(e.what());
    }
  }
  for (const auto station : stations) {
    if (!fresh_ca && fs::exists(paths.at_cert(station)) && fs::exists(paths.at_key(station)))
      continue;
    EcKey k = EcKey::generate(EccCurve::kNistP256);
    const Certificate at =
        make_ticket(k, {start, DurationUnit::kHours, o.ticket_hours}, aa, aa_key);
    save_key(k, paths.at_key(station));
    write_certificate(paths.at_cert(station), at);
    written.push_back(paths.at_cert(station));
  }
  return written;
}

}  // namespace tb::its::security
