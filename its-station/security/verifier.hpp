#pragma once
/// @file Verification of signed CAMs and DENMs (IEEE 1609.2 5.2, TS 103 097 v1.3.1 clause 7):
/// the packet's signature, the signer's certificate chain AT -> AA -> a trusted root, validity,
/// permissions and the generation time. Every rejection is a named VerifyResult, counted.
///
/// Certificates are verified once: a certificate whose chain checked out is kept with its parsed
/// public key under its HashedId8, so that a CAM with a digest signer costs one ECDSA verify.
/// Time comes from the caller (Time64 TAI), never from a clock of its own.

#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "common/util/expected.hpp"
#include "its-station/security/crypto.hpp"
#include "its-station/security/ieee1609dot2.hpp"
#include "its-station/security/time.hpp"

namespace tb::its::security {

enum class VerifyResult : std::uint8_t {
  kOk,
  kMalformed,              ///< not a COER Ieee1609Dot2Data TS 103 097 allows
  kNotSigned,              ///< unsecuredData (or extDataHash only): nothing to verify
  kUnsupportedHash,        ///< hashId other than sha256
  kWrongPsid,              ///< headerInfo.psid is not the service the packet is for
  kGenerationTimeMissing,  ///< TS 103 097 7.1.1/7.1.2: CAM and DENM carry generationTime
  kGenerationTimeOutOfWindow,
  kGenerationLocationMissing,  ///< TS 103 097 7.1.2: DENM carries generationLocation
  kSelfSigned,                 ///< signer self: no certificate vouches for the key
  kUnknownSigner,              ///< signer digest of a certificate not seen yet
  kUnknownIssuer,              ///< the AT's AA is not known (yet: it is asked for)
  kUntrustedRoot,              ///< an AA whose issuer is not a trusted root (another PKI's)
  kCertificateSignature,       ///< a certificate in the chain whose signature fails
  kCertificateNotValid,        ///< generation time outside the AT's (or its AA's) validity
  kPsidNotPermitted,           ///< the AT's appPermissions lack the psid
  kSspNotPermitted,            ///< the AT's SSP for the psid is not one the station accepts
  kIssuerNotPermitted,         ///< the AA's certIssuePermissions lack the psid
  kSignatureInvalid,           ///< the packet's signature does not verify
  /// A packet that verified, from a signer, for an ITS-AID and with a generationTime already
  /// accepted within the window (1609.2 5.2.4.2.3 replay detection; see
  /// VerifierConfig::time_policy).
  kReplay,
  /// Parsed and passed up without the packet's signature checked: a station that verifies on
  /// demand (SecurityEntity, VerifyPolicy::kOnDemand) for a packet nothing of it trusts.
  kNotVerified,
  kCount
};

std::string_view to_string(VerifyResult r);

/// How a service's packets are held against time (IEEE 1609.2 5.2.4.2.3: the generation-time
/// relevance check and replay detection are the security profile's to set, per PSID).
struct TimePolicy {
  /// How far before / after the receiver's time a generationTime may lie.
  std::chrono::microseconds past{2'000'000};
  std::chrono::microseconds future{40'000};
  /// Drop a second packet of one signer with one generationTime (kReplay).
  bool replay_detection = true;
  bool operator==(const TimePolicy&) const = default;
};

/// The defaults, per ITS-AID. No standard fixes a receiver's window: TS 103 097 v1.3.1 clause 7
/// makes generationTime mandatory for CAM (7.1.1), DENM (7.1.2) and other messages (7.1.3)
/// without a tolerance, IEEE 1609.2 leaves it to the service's profile, and the C2C-CC Basic
/// System Profile adds none. So every service gets the window issue 20 chose for CAMs,
/// -2 s .. +40 ms (a CAM is at most 1 s apart from the next, EN 302 637-2 6.1.3; +40 ms covers
/// clocks a GNSS fix keeps within a few ms). The 5 s between TAI and UTC without leap seconds is
/// not in the window: the verifier tries both bases (accept_utc_time_base).
/// Replay detection is off for DENM: DENMs travel in GeoBroadcast, whose forwarded copies are
/// the same signed octets and must reach GeoNetworking, which drops them by sequence number
/// (EN 302 636-4-1 Annex A.2) and stops its own contention-based forward on hearing one
/// (Annex F.3). CAMs (SHB, EN 302 637-2 5.3) and beacons are never forwarded.
TimePolicy default_time_policy(Psid psid);

struct VerifierConfig {
  /// Per-ITS-AID settings (CAM 36, DENM 37, GN-MGMT 141, ...); a PSID not named here gets
  /// default_time_policy().
  std::map<Psid, TimePolicy> time_policy;
  /// Accept generation times on the UTC-without-leap-seconds base (Vanetza) as well as TAI.
  bool accept_utc_time_base = true;
  /// Accepted (signer, generationTime) pairs remembered for replay detection: each until its
  /// window has passed; past this many, the one whose window ends first is forgotten early.
  std::size_t replay_capacity = 4096;

  TimePolicy policy(Psid psid) const;
};

/// Bounds of a window a station or scenario sets (ms): beyond them a "window" would be no
/// freshness check at all.
inline constexpr std::int64_t kMaxWindowPastMs = 600'000;
inline constexpr std::int64_t kMaxWindowFutureMs = 60'000;

/// One `--security-time-window` value, `PSID=PAST_MS` or `PSID=PAST_MS:FUTURE_MS`: the window
/// of ITS-AID PSID; the future side (when not given) and replay detection keep the PSID's
/// defaults. The error names the value and the part that is wrong.
Expected<std::pair<Psid, TimePolicy>, std::string> parse_time_window(std::string_view spec);

/// What verify() found. The decoded packet is there whatever the result (unless malformed), so
/// that a permissive station can pass the payload up with the reason.
struct Verification {
  VerifyResult result = VerifyResult::kMalformed;
  Ieee1609Dot2Data data;
  asn1::CodecError decode_error{};
  std::optional<HashedId8> signer;  ///< the AT's HashedId8 (digest or certificate signer)
  bool signer_certificate_included = false;
  bool signer_learned = false;  ///< the included AT was new to the verifier (and now is known)
  std::optional<TimeBase> time_base;  ///< the base the generation time matched
  /// kUnknownIssuer: the HashedId8 of the AA the included AT names, to be asked for (P2PCD).
  std::optional<HashedId8> missing_issuer;
  /// The signer AT's SSP octets for the packet's psid (empty when it has none): what the
  /// service checks the content against (TS 103 900 / TS 103 831 "permissions").
  Bytes ssp;

  /// The signed payload (empty when there is none).
  std::span<const std::uint8_t> payload() const;
};

class Verifier {
 public:
  /// Throws CryptoError when a root is not self-signed or its signature fails.
  Verifier(std::vector<Certificate> trusted_roots, VerifierConfig config = {});

  /// Adds an AA certificate after checking it against the trusted roots at @p now. An AA that
  /// fails is remembered with the reason (a bounded set), so that the ATs it issued are refused
  /// with that reason (an AT of another PKI's AA: untrusted_root) rather than unknown_issuer.
  VerifyResult add_authority(const Certificate& aa, Time64 now);
  /// Why the AA @p id was refused, if it was.
  std::optional<VerifyResult> refused_authority(const HashedId8& id) const;

  /// Verifies one Ieee1609Dot2Data for the service @p psid at TAI time @p now.
  Verification verify(std::span<const std::uint8_t> secured, Psid psid, Time64 now) {
    return verify_for(secured, psid, now);
  }
  /// Verifies for whichever psid the header names (the layer above checks that it fits the
  /// BTP port the payload goes to).
  Verification verify(std::span<const std::uint8_t> secured, Time64 now) {
    return verify_for(secured, std::nullopt, now);
  }

  /// The steps of verify(), for a caller that decides after the header whether to check the
  /// signature (SecurityEntity's verification on demand). decode(): result kMalformed (counted)
  /// when @p secured does not decode, else kNotVerified until verify_decoded() or
  /// accept_unverified() sets it.
  Verification decode(std::span<const std::uint8_t> secured);
  /// Every check of verify() on a decoded packet.
  void verify_decoded(Verification& v, Time64 now);
  /// The checks of the header only (signed data, sha256, payload, generationTime in its window,
  /// DENM generationLocation) and who signed it, without the packet's signature, permissions or
  /// replay detection: kNotVerified when they pass, and `ssp` stays empty. An AT that comes in
  /// the packet and is not known yet is verified against its AA and cached, as verify() does
  /// (once per AT: a later DENM signed with its digest verifies without waiting for it); one
  /// that fails is refused with its reason. A digest that names no known AT is kNotVerified
  /// with `signer` set, so that the caller can ask for the AT.
  void accept_unverified(Verification& v, Time64 now);

  /// A known certificate (root, AA or verified AT) by its HashedId3 (P2PCD requests).
  const Certificate* find(const HashedId3& id) const;
  bool knows(const HashedId8& id) const { return entries_.contains(id); }

  std::uint64_t count(VerifyResult r) const { return counts_[static_cast<std::size_t>(r)]; }
  const std::array<std::uint64_t, static_cast<std::size_t>(VerifyResult::kCount)>& counts() const {
    return counts_;
  }
  std::size_t known_certificates() const { return entries_.size(); }
  /// ECDSA verifications done so far (packets' and certificates' signatures; the trusted roots'
  /// self-signatures not included): the cost verification on demand saves.
  std::uint64_t ecdsa_verifications() const { return ecdsa_verifications_; }
  /// (signer, generationTime) pairs remembered for replay detection.
  std::size_t replay_entries() const { return replay_.size(); }
  const VerifierConfig& config() const { return config_; }

 private:
  struct Id8Hash {
    std::size_t operator()(const HashedId8& id) const;
  };
  struct Entry {
    Certificate cert;
    Octets32 hash{};  ///< SHA-256 of the canonical certificate
    EcKey key;
    const Entry* issuer = nullptr;  ///< null for a root
  };

  /// A packet for replay detection: its signer, its ITS-AID (a beacon and a CAM may be signed
  /// in one microsecond) and its generationTime (as sent).
  struct ReplayKey {
    HashedId8 signer{};
    Psid psid = 0;
    Time64 generation_time = 0;
    bool operator==(const ReplayKey&) const = default;
  };
  struct ReplayKeyHash {
    std::size_t operator()(const ReplayKey& k) const;
  };
  /// Whether @p key was accepted before; remembers it until @p forget_at (TAI) when not.
  /// Forgets what expired by @p now first.
  bool seen_before(const ReplayKey& key, Time64 forget_at, Time64 now);

  VerifyResult check_issued(const Certificate& c, const Entry& issuer, Time64 at) const;
  /// The entry of the AT @p c (verified against its AA and cached when new).
  VerifyResult ticket_entry(const Certificate& c, Psid psid, Time64 at, const Entry** out);
  /// The checks of the header, common to verify() and accept_unverified(): sets v.time_base
  /// and @p at (the generation time on TAI) when they pass.
  VerifyResult check_header(Verification& v, std::optional<Psid> psid, Time64 now, Time64& at);
  /// The AT of a certificate signer, verified and cached when new (v.signer, v.missing_issuer,
  /// v.signer_learned set).
  VerifyResult included_ticket(Verification& v, Psid psid, Time64 at, const Entry** out);
  VerifyResult check(Verification& v, std::optional<Psid> psid, Time64 now);
  Verification verify_for(std::span<const std::uint8_t> secured, std::optional<Psid> psid,
                          Time64 now);

  VerifierConfig config_;
  std::unordered_map<HashedId8, Entry, Id8Hash> entries_;
  std::unordered_map<HashedId8, VerifyResult, Id8Hash> refused_;
  std::unordered_map<ReplayKey, Time64, ReplayKeyHash> replay_;  ///< key -> forget at (TAI)
  std::multimap<Time64, ReplayKey> replay_expiry_;               ///< forget at -> key
  std::array<std::uint64_t, static_cast<std::size_t>(VerifyResult::kCount)> counts_{};
  mutable std::uint64_t ecdsa_verifications_ = 0;
};

}  // namespace tb::its::security
