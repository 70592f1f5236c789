#pragma once
/// @file The security entity of the station (EN 302 636-4-1 clause 9.3 "security services",
/// TS 103 097): wraps outgoing GN payloads (common header onwards) in signed data, and
/// unwraps, verifies and passes up or drops incoming ones, after the scenario's mode.
///
/// Packets signed by a certificate digest we do not know yet are held for a short while and
/// their certificate requested (1609.2 P2PCD, TS 103 097 7.1.1): they are verified when a
/// packet carrying that certificate arrives, and dropped as unknown_signer when the hold ends.

#include <chrono>
#include <deque>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "its-station/security/signer.hpp"
#include "its-station/security/verifier.hpp"

namespace tb::its::security {

/// Scenario `security`: none (unsecured packets only, as before), signed (sign and verify,
/// drop what fails), signed-permissive (sign; pass up what fails verification, with the
/// reason).
enum class SecurityMode : std::uint8_t { kNone, kSigned, kSignedPermissive };

std::string_view to_string(SecurityMode m);
std::optional<SecurityMode> parse_security_mode(std::string_view s);

/// Which received packets get their signature verified (issue 33; the rule and its source in
/// security/README.md, "Verification on demand").
/// kEvery: all of them (a full station). kOnDemand: only those whose content the station uses
/// in a way that needs trust (a pooled station, as the C2C-CC Basic System Profile allows):
/// DENMs and any ITS-AID other than CAM, SPATEM, MAPEM and GN-MGMT, CAMs when an application
/// that consumes them runs (set_cam_consumer), SPATEM and MAPEM when the signal application runs
/// (set_signal_consumer). The others are parsed and passed up as kNotVerified, without
/// SSP.
enum class VerifyPolicy : std::uint8_t { kEvery, kOnDemand };

std::string_view to_string(VerifyPolicy p);

/// One incoming packet's outcome.
struct SecuredIndication {
  bool pass_up = false;
  VerifyResult reason = VerifyResult::kMalformed;
  Psid psid = 0;
  Bytes payload;  ///< the signed payload: GN common header onwards
  std::optional<TimeBase> time_base;
  /// The caller's ticket of the packet this outcome is about (decapsulate()): the packet just
  /// given, or one held earlier and released now.
  std::uint64_t ticket = 0;
  Bytes ssp;  ///< the signer AT's SSP for psid (Verification::ssp)
};

class SecurityEntity {
 public:
  /// How long a packet from an unknown digest waits for its certificate: within the CAM
  /// generation-time window, so that it can still verify when the certificate comes.
  static constexpr Time64 kHoldUs = 1'000'000;
  static constexpr std::size_t kMaxHeld = 32;

  SecurityEntity(SecurityMode mode, Signer signer, Verifier verifier);

  SecurityMode mode() const { return mode_; }
  void set_verify_policy(VerifyPolicy p) { policy_ = p; }
  VerifyPolicy verify_policy() const { return policy_; }
  /// Whether an application that consumes received CAMs runs (LCRW): then kOnDemand verifies
  /// CAMs too.
  void set_cam_consumer(bool consumer) { cam_consumer_ = consumer; }
  /// Whether an application that consumes received SPATEM and MAPEM runs (the signal
  /// application, issue 34): then kOnDemand verifies them too.
  void set_signal_consumer(bool consumer) { signal_consumer_ = consumer; }
  /// Whether a received packet of @p psid gets its signature verified under the policy.
  bool verifies(Psid psid) const;
  /// The station id its trace records (its.sign, its.verify) carry, for the latency report to
  /// join them to the station's CAMs.
  void set_trace_station(std::uint32_t id) { trace_station_ = id; }
  /// Whether received CAMs' its.verify records are written (the other services' are, rare as
  /// they are); off for a pooled station, as its CA service's reception records (issue 33).
  void set_trace_cam_receptions(bool on) { trace_cam_receptions_ = on; }

  /// The signed data for @p payload of service @p psid (CAM and DENM after their profiles;
  /// @p where is the DENM's generationLocation).
  Bytes encapsulate(Psid psid, std::span<const std::uint8_t> payload, Time64 now,
                    const std::optional<ThreeDLocation>& where = std::nullopt);

  /// Verifies @p secured; returns the outcomes of held packets whose hold ended, then its own
  /// (none while it is held), then those of held packets it released (verified now that their
  /// certificate came). Each outcome carries the @p ticket its packet was given with, so that
  /// the caller can tell which of its packets it is about.
  std::vector<SecuredIndication> decapsulate(std::span<const std::uint8_t> secured, Time64 now,
                                             std::uint64_t ticket = 0);

  /// Whether our AT lets us sign for @p psid.
  bool can_sign(Psid psid) const { return signer_.permits(psid); }

  /// Drops held packets whose hold ended; their outcomes (unknown_signer).
  std::vector<SecuredIndication> expire(Time64 now);

  const Verifier& verifier() const { return verifier_; }
  Verifier& verifier() { return verifier_; }
  const Signer& signer() const { return signer_; }
  std::size_t held() const { return held_.size(); }
  /// Packets passed up in permissive mode although they failed verification.
  std::uint64_t passed_unverified() const { return passed_unverified_; }

 private:
  struct Held {
    HashedId8 digest{};
    Time64 until = 0;
    Bytes packet;
    std::uint64_t ticket = 0;
  };
  SecuredIndication outcome(Verification& v, std::uint64_t ticket);
  /// Decodes @p secured and verifies it, or only parses it when the policy does not need it.
  Verification check(std::span<const std::uint8_t> secured, Time64 now);

  SecurityMode mode_;
  VerifyPolicy policy_ = VerifyPolicy::kEvery;
  bool cam_consumer_ = false;
  bool signal_consumer_ = false;
  Signer signer_;
  Verifier verifier_;
  std::deque<Held> held_;
  std::uint64_t passed_unverified_ = 0;
  std::uint32_t trace_station_ = 0;
  bool trace_cam_receptions_ = true;
};

}  // namespace tb::its::security
