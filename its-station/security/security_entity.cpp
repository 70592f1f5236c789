#include "its-station/security/security_entity.hpp"

#include <algorithm>

#include "common/trace/tracer.hpp"

namespace tb::its::security {

std::string_view to_string(SecurityMode m) {
  switch (m) {
    case SecurityMode::kNone:
      return "none";
    case SecurityMode::kSigned:
      return "signed";
    case SecurityMode::kSignedPermissive:
      return "signed-permissive";
  }
  return "unknown";
}

std::optional<SecurityMode> parse_security_mode(std::string_view s) {
  for (auto m : {SecurityMode::kNone, SecurityMode::kSigned, SecurityMode::kSignedPermissive})
    if (s == to_string(m))
      return m;
  return std::nullopt;
}

std::string_view to_string(VerifyPolicy p) {
  return p == VerifyPolicy::kEvery ? "every" : "on-demand";
}

SecurityEntity::SecurityEntity(SecurityMode mode, Signer signer, Verifier verifier)
    : mode_(mode), signer_(std::move(signer)), verifier_(std::move(verifier)) {}

Bytes SecurityEntity::encapsulate(Psid psid, std::span<const std::uint8_t> payload, Time64 now,
                                  const std::optional<ThreeDLocation>& where) {
  // Tracing: the sign stage of the latency chain (inside t4, its.cam_tx -> sent_ns).
  const std::int64_t start_ns = trace::Tracer::now_ns();
  Bytes out = psid == kPsidCam               ? signer_.sign_cam(payload, now)
              : (psid == kPsidDenm && where) ? signer_.sign_denm(payload, now, *where)
              : psid == kPsidDenm            ? signer_.sign(psid, payload, now, where, true)
                                             : signer_.sign_other(psid, payload, now);
  trace::global().record_at(start_ns, "its.sign",
                            {{"station", trace_station_},
                             {"psid", psid},
                             {"bytes", out.size()},
                             {"certificate", signer_.last_with_certificate()},
                             {"end_ns", trace::Tracer::now_ns()}});
  return out;
}

SecuredIndication SecurityEntity::outcome(Verification& v, std::uint64_t ticket) {
  SecuredIndication ind;
  ind.reason = v.result;
  ind.time_base = v.time_base;
  ind.ticket = ticket;
  ind.ssp = std::move(v.ssp);
  if (v.result != VerifyResult::kMalformed &&
      v.data.content == Ieee1609Dot2Data::Content::kSignedData)
    ind.psid = v.data.signed_data.tbs.header.psid;
  const auto p = v.payload();
  const bool ok = v.result == VerifyResult::kOk;
  // Not verified is not a failure: it was not asked for (verification on demand).
  ind.pass_up = !p.empty() && (ok || v.result == VerifyResult::kNotVerified ||
                               mode_ == SecurityMode::kSignedPermissive);
  if (ind.pass_up) {
    ind.payload.assign(p.begin(), p.end());
    if (!ok && v.result != VerifyResult::kNotVerified)
      ++passed_unverified_;
  }
  return ind;
}

bool SecurityEntity::verifies(Psid psid) const {
  if (policy_ == VerifyPolicy::kEvery)
    return true;
  if (psid == kPsidCam)
    return cam_consumer_;
  if (psid == kPsidSpatem || psid == kPsidMapem)
    return signal_consumer_;
  return psid != kPsidGnMgmt;  // beacons feed only the location table
}

Verification SecurityEntity::check(std::span<const std::uint8_t> secured, Time64 now) {
  Verification v = verifier_.decode(secured);
  // Unsecured data goes through verify_decoded(), which names it not_signed.
  if (v.data.content == Ieee1609Dot2Data::Content::kSignedData &&
      !verifies(v.data.signed_data.tbs.header.psid))
    verifier_.accept_unverified(v, now);
  else
    verifier_.verify_decoded(v, now);
  return v;
}

std::vector<SecuredIndication> SecurityEntity::decapsulate(std::span<const std::uint8_t> secured,
                                                           Time64 now, std::uint64_t ticket) {
  std::vector<SecuredIndication> out = expire(now);
  // Tracing: the verify stage of the receive path (decode included).
  const std::int64_t start_ns = trace::Tracer::now_ns();
  Verification v = check(secured, now);
  const std::int64_t end_ns = trace::Tracer::now_ns();
  const Psid psid = v.result != VerifyResult::kMalformed &&
                            v.data.content == Ieee1609Dot2Data::Content::kSignedData
                        ? v.data.signed_data.tbs.header.psid
                        : Psid{0};
  if (trace_cam_receptions_ || psid != kPsidCam)
    trace::global().record_at(start_ns, "its.verify",
                              {{"station", trace_station_},
                               {"psid", psid},
                               {"result", to_string(v.result)},
                               {"certificate", v.signer_certificate_included},
                               {"end_ns", end_ns}});
  if (v.result != VerifyResult::kMalformed &&
      v.data.content == Ieee1609Dot2Data::Content::kSignedData) {
    const auto& h = v.data.signed_data.tbs.header;
    // Peers' P2PCD: what they ask of us, and an AA one of them sent.
    if (h.inline_p2pcd_request)
      for (const auto& id : *h.inline_p2pcd_request)
        signer_.on_certificate_request(id);
    if (h.requested_certificate)
      verifier_.add_authority(*h.requested_certificate, now);
  }
  // An AT whose AA we do not know: ask its sender for the AA (1609.2 P2PCD). A peer of our PKI
  // answers with it, a station of another PKI with one that add_authority() refuses and
  // remembers, so that its packets are dropped as untrusted_root from then on.
  if (v.result == VerifyResult::kUnknownIssuer && v.missing_issuer)
    signer_.request_certificate(*v.missing_issuer);
  if (v.result == VerifyResult::kUnknownSigner && mode_ == SecurityMode::kSigned && v.signer) {
    signer_.request_certificate(*v.signer);
    signer_.on_unknown_station();
    if (held_.size() >= kMaxHeld) {
      out.push_back(SecuredIndication{
          false, VerifyResult::kUnknownSigner, 0, {}, {}, held_.front().ticket, {}});
      held_.pop_front();
    }
    held_.push_back(Held{*v.signer, now + kHoldUs, Bytes(secured.begin(), secured.end()), ticket});
    return out;
  }
  // A packet passed up unverified whose digest names an AT we do not know: ask for the AT all
  // the same, so that the sender's DENMs signed with that digest verify without waiting.
  const bool unknown_digest = v.result == VerifyResult::kNotVerified && v.signer &&
                              !v.signer_certificate_included && !verifier_.knows(*v.signer);
  if ((v.result == VerifyResult::kUnknownSigner || unknown_digest) && v.signer) {
    signer_.request_certificate(*v.signer);
    signer_.on_unknown_station();
  }
  out.push_back(outcome(v, ticket));
  if ((v.result == VerifyResult::kOk || v.result == VerifyResult::kNotVerified) &&
      v.signer_learned) {
    signer_.on_unknown_station();  // TS 103 097 7.1.1: a new station hears our AT next
    // Its held packets can be verified now.
    const HashedId8 id = *v.signer;
    for (auto it = held_.begin(); it != held_.end();) {
      if (it->digest != id) {
        ++it;
        continue;
      }
      Verification again = verifier_.verify(it->packet, now);
      out.push_back(outcome(again, it->ticket));
      it = held_.erase(it);
    }
  }
  return out;
}

std::vector<SecuredIndication> SecurityEntity::expire(Time64 now) {
  std::vector<SecuredIndication> out;
  while (!held_.empty() && held_.front().until <= now) {
    out.push_back(SecuredIndication{
        false, VerifyResult::kUnknownSigner, 0, {}, {}, held_.front().ticket, {}});
    held_.pop_front();
  }
  return out;
}

}  // namespace tb::its::security
