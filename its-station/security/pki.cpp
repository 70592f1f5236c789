#include "its-station/security/pki.hpp"

namespace tb::its::security {

Octets32 certificate_hash(const Certificate& c) {
  return sha256(canonical_encoding(c));
}

void sign_certificate(Certificate& c, const Certificate* issuer, const EcKey& issuer_key) {
  if (issuer != nullptr) {
    c.issuer.kind = IssuerIdentifier::Kind::kSha256AndDigest;
    c.issuer.digest = certificate_id(*issuer);
  } else {
    c.issuer.kind = IssuerIdentifier::Kind::kSelf;
    c.issuer.self_hash = HashAlgorithm::kSha256;
  }
  const Octets32 signer_hash = issuer != nullptr ? certificate_hash(*issuer) : sha256({});
  // Whatever octets it was decoded from no longer hold: encoded from the fields.
  c.encoding.clear();
  c.tbs_offset = c.tbs_length = c.key_offset = c.key_length = 0;
  c.signature = issuer_key.sign(signed_digest(canonical_tbs(c), signer_hash));
  // Decoded back, so that it carries its octets and their parts like a received one.
  auto decoded = decode_certificate(encode(c));
  if (!decoded)
    throw CryptoError("sign_certificate: the certificate does not encode: " +
                      asn1::to_string(decoded.error()));
  c = std::move(*decoded);
}

namespace {

ToBeSignedCertificate base_tbs(const EcKey& key, ValidityPeriod validity) {
  ToBeSignedCertificate t;
  t.validity = validity;
  t.verify_key.curve = key.curve();
  t.verify_key.point = key.public_point();
  return t;
}

}  // namespace

std::vector<PsidSspRange> authority_issue_permissions() {
  return {PsidSspRange{kPsidCam, SspRange{SspRange::Kind::kAll, {}, {}, {}}},
          PsidSspRange{kPsidDenm, SspRange{SspRange::Kind::kAll, {}, {}, {}}},
          PsidSspRange{kPsidGnMgmt, std::nullopt}, PsidSspRange{kPsidSpatem, std::nullopt},
          PsidSspRange{kPsidMapem, std::nullopt}};
}

std::vector<PsidSsp> ticket_permissions(bool road_side_unit) {
  std::vector<PsidSsp> p{PsidSsp{kPsidCam, Ssp{Ssp::Kind::kBitmap, kCamSsp}},
                         PsidSsp{kPsidDenm, Ssp{Ssp::Kind::kBitmap, kDenmSsp}},
                         PsidSsp{kPsidGnMgmt, std::nullopt}};
  if (road_side_unit) {
    p.push_back(PsidSsp{kPsidSpatem, std::nullopt});
    p.push_back(PsidSsp{kPsidMapem, std::nullopt});
  }
  return p;
}

Certificate make_root(const EcKey& key, const std::string& name, ValidityPeriod validity) {
  Certificate c;
  c.tbs = base_tbs(key, validity);
  c.tbs.id = {CertificateId::Kind::kName, Bytes(name.begin(), name.end())};
  PsidGroupPermissions all;
  all.all_psids = true;
  all.min_chain_length = 2;  // root -> AA -> AT
  c.tbs.cert_issue_permissions = std::vector{all};
  sign_certificate(c, nullptr, key);
  return c;
}

Certificate make_authority(const EcKey& key, const std::string& name, ValidityPeriod validity,
                           const Certificate& root, const EcKey& root_key) {
  Certificate c;
  c.tbs = base_tbs(key, validity);
  c.tbs.id = {CertificateId::Kind::kName, Bytes(name.begin(), name.end())};
  PsidGroupPermissions perms;
  perms.psids = authority_issue_permissions();
  c.tbs.cert_issue_permissions = std::vector{perms};
  sign_certificate(c, &root, root_key);
  return c;
}

Certificate make_ticket(const EcKey& key, ValidityPeriod validity, const Certificate& aa,
                        const EcKey& aa_key, bool road_side_unit) {
  Certificate c;
  c.tbs = base_tbs(key, validity);
  c.tbs.id = {CertificateId::Kind::kNone, {}};
  c.tbs.app_permissions = ticket_permissions(road_side_unit);
  sign_certificate(c, &aa, aa_key);
  return c;
}

}  // namespace tb::its::security
