#include "its-station/security/verifier.hpp"

#include <charconv>
#include <cstring>
#include <system_error>

#include "its-station/security/pki.hpp"

namespace tb::its::security {

std::string_view to_string(VerifyResult r) {
  switch (r) {
    case VerifyResult::kOk:
      return "ok";
    case VerifyResult::kMalformed:
      return "malformed";
    case VerifyResult::kNotSigned:
      return "not_signed";
    case VerifyResult::kUnsupportedHash:
      return "unsupported_hash";
    case VerifyResult::kWrongPsid:
      return "wrong_psid";
    case VerifyResult::kGenerationTimeMissing:
      return "generation_time_missing";
    case VerifyResult::kGenerationTimeOutOfWindow:
      return "generation_time_out_of_window";
    case VerifyResult::kGenerationLocationMissing:
      return "generation_location_missing";
    case VerifyResult::kSelfSigned:
      return "self_signed";
    case VerifyResult::kUnknownSigner:
      return "unknown_signer";
    case VerifyResult::kUnknownIssuer:
      return "unknown_issuer";
    case VerifyResult::kUntrustedRoot:
      return "untrusted_root";
    case VerifyResult::kCertificateSignature:
      return "certificate_signature";
    case VerifyResult::kCertificateNotValid:
      return "certificate_not_valid";
    case VerifyResult::kPsidNotPermitted:
      return "psid_not_permitted";
    case VerifyResult::kSspNotPermitted:
      return "ssp_not_permitted";
    case VerifyResult::kIssuerNotPermitted:
      return "issuer_not_permitted";
    case VerifyResult::kSignatureInvalid:
      return "signature_invalid";
    case VerifyResult::kReplay:
      return "replay";
    case VerifyResult::kNotVerified:
      return "not_verified";
    case VerifyResult::kCount:
      break;
  }
  return "unknown";
}

std::span<const std::uint8_t> Verification::payload() const {
  if (data.content == Ieee1609Dot2Data::Content::kUnsecuredData)
    return data.unsecured_data;
  if (data.signed_data.tbs.payload.data)
    return *data.signed_data.tbs.payload.data;
  return {};
}

TimePolicy default_time_policy(Psid psid) {
  TimePolicy p;  // -2 s .. +40 ms, replay detection on
  if (psid == kPsidDenm)
    p.replay_detection = false;  // forwarded copies are GeoNetworking's (verifier.hpp)
  return p;
}

TimePolicy VerifierConfig::policy(Psid psid) const {
  if (auto it = time_policy.find(psid); it != time_policy.end())
    return it->second;
  return default_time_policy(psid);
}

namespace {

/// The decimal integer @p text in [@p min, @p max], or nothing.
std::optional<std::int64_t> decimal(std::string_view text, std::int64_t min, std::int64_t max) {
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc{} || end != text.data() + text.size() || v < min || v > max)
    return std::nullopt;
  return v;
}

}  // namespace

Expected<std::pair<Psid, TimePolicy>, std::string> parse_time_window(std::string_view spec) {
  using Error = Unexpected<std::string>;
  const auto named = [&](const std::string& why) {
    return Error{"\"" + std::string(spec) + "\": " + why +
                 " (expected PSID=PAST_MS or PSID=PAST_MS:FUTURE_MS, e.g. 37=10000:40)"};
  };
  const auto eq = spec.find('=');
  if (eq == std::string_view::npos)
    return named("no '='");
  const std::string_view psid_text = spec.substr(0, eq);
  const std::string_view rest = spec.substr(eq + 1);
  const auto colon = rest.find(':');
  const std::string_view past_text = rest.substr(0, colon);
  // ITS-AIDs of TS 102 965 are PSIDs of at most four octets (1609.2 6.4.30 Psid, p-encoded).
  const auto psid = decimal(psid_text, 0, 0xffffffffLL);
  if (!psid)
    return named("PSID \"" + std::string(psid_text) + "\" is not an ITS-AID (36 CAM, 37 DENM, " +
                 "141 GN-MGMT, ...)");
  const auto past = decimal(past_text, 0, kMaxWindowPastMs);
  if (!past)
    return named("PAST_MS \"" + std::string(past_text) + "\" is not a number of ms in 0.." +
                 std::to_string(kMaxWindowPastMs));
  TimePolicy p = default_time_policy(static_cast<Psid>(*psid));
  p.past = std::chrono::milliseconds(*past);
  if (colon != std::string_view::npos) {
    const std::string_view future_text = rest.substr(colon + 1);
    const auto future = decimal(future_text, 0, kMaxWindowFutureMs);
    if (!future)
      return named("FUTURE_MS \"" + std::string(future_text) + "\" is not a number of ms in 0.." +
                   std::to_string(kMaxWindowFutureMs));
    p.future = std::chrono::milliseconds(*future);
  }
  return std::pair{static_cast<Psid>(*psid), p};
}

std::size_t Verifier::ReplayKeyHash::operator()(const ReplayKey& k) const {
  return Id8Hash{}(k.signer) ^
         static_cast<std::size_t>((k.generation_time ^ (k.psid << 48)) * 0x9e3779b97f4a7c15ull);
}

bool Verifier::seen_before(const ReplayKey& key, Time64 forget_at, Time64 now) {
  while (!replay_expiry_.empty() && replay_expiry_.begin()->first < now) {
    replay_.erase(replay_expiry_.begin()->second);
    replay_expiry_.erase(replay_expiry_.begin());
  }
  if (replay_.contains(key))
    return true;
  if (config_.replay_capacity == 0)
    return false;
  if (replay_.size() >= config_.replay_capacity) {
    // Full: the entry whose window ends first goes (a replay of it would pass undetected).
    replay_.erase(replay_expiry_.begin()->second);
    replay_expiry_.erase(replay_expiry_.begin());
  }
  replay_.emplace(key, forget_at);
  replay_expiry_.emplace(forget_at, key);
  return false;
}

std::size_t Verifier::Id8Hash::operator()(const HashedId8& id) const {
  std::uint64_t v = 0;
  std::memcpy(&v, id.data(), sizeof v);  // already the tail of a SHA-256: uniform
  return static_cast<std::size_t>(v);
}

namespace {

/// A cache of verified ATs that cannot grow without bound when a peer changes pseudonyms or
/// floods certificates; past it, new ATs are verified every time.
constexpr std::size_t kMaxKnownCertificates = 4096;
/// Refused AAs remembered: a handful of foreign PKIs at most; past it, the set starts again.
constexpr std::size_t kMaxRefusedAuthorities = 64;

bool within_validity(const Certificate& c, Time64 at) {
  const std::uint64_t s = at / 1000000;
  return s >= c.tbs.validity.start && s < c.tbs.validity.end_seconds();
}

bool issuer_permits(const Certificate& aa, Psid psid) {
  if (!aa.tbs.cert_issue_permissions)
    return false;
  for (const auto& g : *aa.tbs.cert_issue_permissions) {
    if (g.all_psids)
      return true;
    for (const auto& p : g.psids)
      if (p.psid == psid)
        return true;
  }
  return false;
}

/// 1609.2 5.2.4.2.3 consistency of the packet with the AT's permissions. The SSP layouts of
/// CAM (TS 103 900 6.2.2.2: version 1) and DENM (TS 103 831 6.2.2.2: version 1, or 2 with a
/// fourth octet) start with their version octet; an SSP of another version is not one the
/// station can read. The bits are the services' to check against the content
/// (facilities/ssp_permissions.hpp): the permission's SSP octets go to @p ssp.
VerifyResult ticket_permits(const Certificate& at, Psid psid, Bytes& ssp) {
  if (!at.tbs.app_permissions)
    return VerifyResult::kPsidNotPermitted;
  for (const auto& p : *at.tbs.app_permissions) {
    if (p.psid != psid)
      continue;
    const bool readable =
        p.ssp && !p.ssp->bytes.empty() &&
        (p.ssp->bytes[0] == 0x01 || (psid == kPsidDenm && p.ssp->bytes[0] == 0x02));
    if (p.ssp && (psid == kPsidCam || psid == kPsidDenm) && !readable)
      return VerifyResult::kSspNotPermitted;
    if (p.ssp)
      ssp = p.ssp->bytes;
    return VerifyResult::kOk;
  }
  return VerifyResult::kPsidNotPermitted;
}

}  // namespace

Verifier::Verifier(std::vector<Certificate> trusted_roots, VerifierConfig config)
    : config_(config) {
  for (auto& root : trusted_roots) {
    if (root.issuer.kind != IssuerIdentifier::Kind::kSelf || !root.signature)
      throw CryptoError("trusted root: not a self-signed certificate");
    Entry e;
    e.hash = certificate_hash(root);
    e.key = EcKey::from_point(root.tbs.verify_key.curve, root.tbs.verify_key.point);
    if (!e.key.verify(signed_digest(canonical_tbs(root), sha256({})), *root.signature))
      throw CryptoError("trusted root: its self-signature does not verify");
    e.cert = std::move(root);
    const HashedId8 id = hashed_id8(e.hash);
    entries_.emplace(id, std::move(e));
  }
}

VerifyResult Verifier::check_issued(const Certificate& c, const Entry& issuer, Time64 at) const {
  if (!c.signature || c.issuer.kind != IssuerIdentifier::Kind::kSha256AndDigest)
    return VerifyResult::kCertificateSignature;
  if (!within_validity(c, at) || !within_validity(issuer.cert, at))
    return VerifyResult::kCertificateNotValid;
  // 1609.2 6.4.3, 5.3.1: over toBeSigned as received (COER, canonical by the decoder's rules),
  // not a re-encoding of what the decoder understood: extension additions it skips count.
  ++ecdsa_verifications_;
  if (!issuer.key.verify(signed_digest(canonical_tbs(c), issuer.hash), *c.signature))
    return VerifyResult::kCertificateSignature;
  return VerifyResult::kOk;
}

std::optional<VerifyResult> Verifier::refused_authority(const HashedId8& id) const {
  if (auto it = refused_.find(id); it != refused_.end())
    return it->second;
  return std::nullopt;
}

VerifyResult Verifier::add_authority(const Certificate& aa, Time64 now) {
  const Octets32 hash = certificate_hash(aa);
  const HashedId8 id = hashed_id8(hash);
  if (entries_.contains(id))
    return VerifyResult::kOk;
  const auto refuse = [&](VerifyResult r) {
    if (refused_.size() >= kMaxRefusedAuthorities)
      refused_.clear();
    refused_[id] = r;
    return r;
  };
  if (aa.issuer.kind != IssuerIdentifier::Kind::kSha256AndDigest)
    return refuse(VerifyResult::kUntrustedRoot);
  auto root = entries_.find(aa.issuer.digest);
  if (root == entries_.end() || root->second.issuer != nullptr)
    return refuse(VerifyResult::kUntrustedRoot);
  // Expiry is not remembered: the same AA may be valid for the next packet's time.
  if (const auto r = check_issued(aa, root->second, now); r != VerifyResult::kOk)
    return r == VerifyResult::kCertificateNotValid ? r : refuse(r);
  Entry e;
  e.cert = aa;
  e.hash = hash;
  try {
    e.key = EcKey::from_point(aa.tbs.verify_key.curve, aa.tbs.verify_key.point);
  } catch (const CryptoError&) {
    return refuse(VerifyResult::kCertificateSignature);
  }
  refused_.erase(id);
  e.issuer = &root->second;
  entries_.emplace(id, std::move(e));
  return VerifyResult::kOk;
}

VerifyResult Verifier::ticket_entry(const Certificate& c, Psid psid, Time64 at, const Entry** out) {
  const Octets32 hash = certificate_hash(c);
  const HashedId8 id = hashed_id8(hash);
  if (auto it = entries_.find(id); it != entries_.end()) {
    *out = &it->second;
    return VerifyResult::kOk;
  }
  if (c.issuer.kind != IssuerIdentifier::Kind::kSha256AndDigest)
    return VerifyResult::kUnknownIssuer;
  auto aa = entries_.find(c.issuer.digest);
  if (aa == entries_.end()) {
    if (auto why = refused_authority(c.issuer.digest))
      return *why;
    return VerifyResult::kUnknownIssuer;
  }
  if (aa->second.issuer == nullptr)
    return VerifyResult::kUnknownIssuer;  // an AT straight under a root is not the EU chain
  if (!issuer_permits(aa->second.cert, psid))
    return VerifyResult::kIssuerNotPermitted;
  if (const auto r = check_issued(c, aa->second, at); r != VerifyResult::kOk)
    return r;
  Entry e;
  e.cert = c;
  e.hash = hash;
  try {
    e.key = EcKey::from_point(c.tbs.verify_key.curve, c.tbs.verify_key.point);
  } catch (const CryptoError&) {
    return VerifyResult::kCertificateSignature;
  }
  e.issuer = &aa->second;
  if (entries_.size() >= kMaxKnownCertificates) {
    // Not cached: verified on every packet that carries it; digest-signed ones stay unknown.
    static thread_local Entry overflow;
    overflow = std::move(e);
    *out = &overflow;
    return VerifyResult::kOk;
  }
  *out = &entries_.emplace(id, std::move(e)).first->second;
  return VerifyResult::kOk;
}

VerifyResult Verifier::check_header(Verification& v, std::optional<Psid> expected, Time64 now,
                                    Time64& at) {
  const auto& d = v.data;
  if (d.content != Ieee1609Dot2Data::Content::kSignedData)
    return VerifyResult::kNotSigned;
  const auto& s = d.signed_data;
  if (s.hash_id != HashAlgorithm::kSha256)
    return VerifyResult::kUnsupportedHash;
  if (!s.tbs.payload.data)
    return VerifyResult::kNotSigned;
  const auto& h = s.tbs.header;
  if (expected && h.psid != *expected)
    return VerifyResult::kWrongPsid;
  const Psid psid = h.psid;
  if (!h.generation_time)
    return VerifyResult::kGenerationTimeMissing;
  const TimePolicy policy = config_.policy(psid);
  // The window on TAI, then on UTC without leap seconds (5 s behind since 2017).
  const auto in_window = [&](Time64 t_now) {
    const auto g = static_cast<std::int64_t>(*h.generation_time);
    const auto n = static_cast<std::int64_t>(t_now);
    return g >= n - policy.past.count() && g <= n + policy.future.count();
  };
  const Time64 leap = Time64{static_cast<std::uint64_t>(leap_seconds_since_2004(
                          static_cast<std::int64_t>(now / 1000000) + kEpoch2004UnixSeconds))} *
                      1000000;
  if (in_window(now))
    v.time_base = TimeBase::kTai;
  else if (config_.accept_utc_time_base && now >= leap && in_window(now - leap))
    v.time_base = TimeBase::kUtcNoLeapSeconds;
  if (!v.time_base)
    return VerifyResult::kGenerationTimeOutOfWindow;
  if (psid == kPsidDenm && !h.generation_location)
    return VerifyResult::kGenerationLocationMissing;
  // Certificate validity is checked at the generation time, on TAI (1609.2 5.2.4.2.3).
  at = *v.time_base == TimeBase::kTai ? *h.generation_time : *h.generation_time + leap;
  if (s.signer.kind == SignerIdentifier::Kind::kSelf)
    return VerifyResult::kSelfSigned;
  return VerifyResult::kOk;
}

VerifyResult Verifier::included_ticket(Verification& v, Psid psid, Time64 at, const Entry** out) {
  // TS 103 097 5.2: exactly one certificate, the AT.
  const auto& at_cert = v.data.signed_data.signer.certificates.front();
  v.signer_certificate_included = true;
  v.signer = certificate_id(at_cert);
  const bool known = entries_.contains(*v.signer);
  if (const auto r = ticket_entry(at_cert, psid, at, out); r != VerifyResult::kOk) {
    if (r == VerifyResult::kUnknownIssuer &&
        at_cert.issuer.kind == IssuerIdentifier::Kind::kSha256AndDigest)
      v.missing_issuer = at_cert.issuer.digest;
    return r;
  }
  v.signer_learned = !known && entries_.contains(*v.signer);
  if (!within_validity((*out)->cert, at) || !within_validity((*out)->issuer->cert, at))
    return VerifyResult::kCertificateNotValid;
  return VerifyResult::kOk;
}

VerifyResult Verifier::check(Verification& v, std::optional<Psid> expected, Time64 now) {
  Time64 at = 0;
  if (const auto r = check_header(v, expected, now, at); r != VerifyResult::kOk)
    return r;
  const auto& s = v.data.signed_data;
  const auto& h = s.tbs.header;
  const Psid psid = h.psid;
  const TimePolicy policy = config_.policy(psid);

  const Entry* signer = nullptr;
  if (s.signer.kind == SignerIdentifier::Kind::kDigest) {
    v.signer = s.signer.digest;
    auto it = entries_.find(s.signer.digest);
    if (it == entries_.end() || it->second.issuer == nullptr ||
        it->second.issuer->issuer == nullptr)
      return VerifyResult::kUnknownSigner;  // roots and AAs do not sign CAMs or DENMs
    signer = &it->second;
    if (!within_validity(signer->cert, at) || !within_validity(signer->issuer->cert, at))
      return VerifyResult::kCertificateNotValid;
  } else if (const auto r = included_ticket(v, psid, at, &signer); r != VerifyResult::kOk) {
    return r;
  }
  if (const auto r = ticket_permits(signer->cert, psid, v.ssp); r != VerifyResult::kOk)
    return r;
  if (!issuer_permits(signer->issuer->cert, psid))
    return VerifyResult::kIssuerNotPermitted;
  const Bytes& tbs = s.tbs_encoding.empty() ? encode(s.tbs) : s.tbs_encoding;
  ++ecdsa_verifications_;
  if (!signer->key.verify(signed_digest(tbs, signer->hash), s.signature))
    return VerifyResult::kSignatureInvalid;
  // Replay: checked on packets that verified, so that only the signer's own packets count. An
  // entry is kept while a packet with its generationTime could still be in the window (`at` is
  // that time on TAI, like `now`).
  if (policy.replay_detection && seen_before(ReplayKey{*v.signer, psid, *h.generation_time},
                                             at + static_cast<Time64>(policy.past.count()), now))
    return VerifyResult::kReplay;
  return VerifyResult::kOk;
}

Verification Verifier::decode(std::span<const std::uint8_t> secured) {
  Verification v;
  auto d = decode_data(secured);
  if (!d) {
    v.decode_error = d.error();
    v.result = VerifyResult::kMalformed;
    ++counts_[static_cast<std::size_t>(v.result)];
  } else {
    v.data = std::move(*d);
    v.result = VerifyResult::kNotVerified;
  }
  return v;
}

void Verifier::verify_decoded(Verification& v, Time64 now) {
  if (v.result == VerifyResult::kMalformed)
    return;
  v.result = check(v, std::nullopt, now);
  ++counts_[static_cast<std::size_t>(v.result)];
}

void Verifier::accept_unverified(Verification& v, Time64 now) {
  if (v.result == VerifyResult::kMalformed)
    return;
  v.result = [&] {
    Time64 at = 0;
    if (const auto r = check_header(v, std::nullopt, now, at); r != VerifyResult::kOk)
      return r;
    const auto& s = v.data.signed_data;
    if (s.signer.kind == SignerIdentifier::Kind::kDigest) {
      v.signer = s.signer.digest;  // known or not: nothing is checked against it
      return VerifyResult::kNotVerified;
    }
    const Entry* signer = nullptr;
    if (const auto r = included_ticket(v, s.tbs.header.psid, at, &signer); r != VerifyResult::kOk)
      return r;
    return VerifyResult::kNotVerified;
  }();
  ++counts_[static_cast<std::size_t>(v.result)];
}

Verification Verifier::verify_for(std::span<const std::uint8_t> secured, std::optional<Psid> psid,
                                  Time64 now) {
  Verification v;
  auto d = decode_data(secured);
  if (!d) {
    v.decode_error = d.error();
    v.result = VerifyResult::kMalformed;
  } else {
    v.data = std::move(*d);
    v.result = check(v, psid, now);
  }
  ++counts_[static_cast<std::size_t>(v.result)];
  return v;
}

const Certificate* Verifier::find(const HashedId3& id) const {
  for (const auto& [id8, e] : entries_)
    if (id8[5] == id[0] && id8[6] == id[1] && id8[7] == id[2])
      return &e.cert;
  return nullptr;
}

}  // namespace tb::its::security
