#include "its-station/security/signer.hpp"

#include <algorithm>

#include "its-station/security/pki.hpp"

namespace tb::its::security {

Signer::Signer(Certificate at, EcKey key, std::optional<Certificate> aa)
    : at_(std::move(at)), key_(std::move(key)), aa_(std::move(aa)) {
  if (at_.encoding.empty())
    at_.encoding = encode(at_);
  hash_ = certificate_hash(at_);
  id_ = hashed_id8(hash_);
  if (aa_)
    aa_id3_ = hashed_id3(certificate_id(*aa_));
  if (at_.tbs.verify_key.point != key_.public_point())
    throw CryptoError("signer: the private key is not the AT's verification key");
}

void Signer::on_certificate_request(const HashedId3& id) {
  if (id == hashed_id3(id_))
    certificate_due_ = true;
  else if (aa_id3_ && id == *aa_id3_)
    aa_requested_ = true;
}

void Signer::request_certificate(const HashedId8& unknown) {
  const HashedId3 id = hashed_id3(unknown);
  if (std::find(requests_.begin(), requests_.end(), id) == requests_.end() && requests_.size() < 8)
    requests_.push_back(id);
}

bool Signer::permits(Psid psid) const {
  if (!at_.tbs.app_permissions)
    return false;
  return std::any_of(at_.tbs.app_permissions->begin(), at_.tbs.app_permissions->end(),
                     [&](const PsidSsp& p) { return p.psid == psid; });
}

Bytes Signer::sign_cam(std::span<const std::uint8_t> payload, Time64 now) {
  // "Not in the last second" on the clock going backwards too: send it rather than wait.
  const bool due = certificate_due_ || !last_certificate_ || now < *last_certificate_ ||
                   now - *last_certificate_ >= kCamCertificateInterval;
  return sign(kPsidCam, payload, now, std::nullopt, due);
}

Bytes Signer::sign_other(Psid psid, std::span<const std::uint8_t> payload, Time64 now) {
  const bool due = !last_certificate_ || now < *last_certificate_ ||
                   now - *last_certificate_ >= kCamCertificateInterval;
  return sign(psid, payload, now, std::nullopt, due);
}

Bytes Signer::sign_denm(std::span<const std::uint8_t> payload, Time64 now,
                        const ThreeDLocation& where) {
  return sign(kPsidDenm, payload, now, where, true);
}

Bytes Signer::sign(Psid psid, std::span<const std::uint8_t> payload, Time64 now,
                   const std::optional<ThreeDLocation>& where, bool with_certificate) {
  Ieee1609Dot2Data d;
  d.content = Ieee1609Dot2Data::Content::kSignedData;
  auto& s = d.signed_data;
  s.tbs.payload.data.emplace(payload.begin(), payload.end());
  auto& h = s.tbs.header;
  h.psid = psid;
  h.generation_time = now;
  h.generation_location = where;
  if (psid == kPsidCam) {
    if (!requests_.empty())
      h.inline_p2pcd_request = std::exchange(requests_, {});
    if (aa_requested_ && aa_)
      h.requested_certificate = *aa_;
    aa_requested_ = false;
  }
  last_with_certificate_ = with_certificate;
  if (with_certificate) {
    s.signer.kind = SignerIdentifier::Kind::kCertificate;
    s.signer.certificates = {at_};
    if (psid == kPsidCam) {
      last_certificate_ = now;
      certificate_due_ = false;
    }
  } else {
    s.signer.kind = SignerIdentifier::Kind::kDigest;
    s.signer.digest = id_;
  }
  s.signature = key_.sign(signed_digest(encode(s.tbs), hash_));
  return encode(d);
}

}  // namespace tb::its::security
