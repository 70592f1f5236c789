#pragma once
/// @file Signing of CAMs and DENMs after the profiles of TS 103 097 v1.3.1 clause 7.1.
///
/// CAM (7.1.1): psid 36, generationTime; signer digest, but the whole AT when none went out in
/// the last second, after a CAM from an unknown station arrived, and when a peer asked for our
/// AT by its HashedId3 (inlineP2pcdRequest); our AA goes out as requestedCertificate when asked
/// for. HashedId3s of certificates we miss go out as inlineP2pcdRequest.
/// DENM (7.1.2): psid 37, generationTime, generationLocation, always the whole AT.
/// Other messages (7.1.3), here the router's beacons (GN-MGMT, psid 141): generationTime; signer
/// digest, or the whole AT when none went out in a CAM in the last second (a station that sends
/// no CAMs, the only one whose beacons go out at all, is then known by its beacons).

#include <optional>
#include <span>
#include <vector>

#include "its-station/security/crypto.hpp"
#include "its-station/security/ieee1609dot2.hpp"

namespace tb::its::security {

class Signer {
 public:
  /// @p aa is the AT's issuer, sent when a peer asks for it.
  Signer(Certificate at, EcKey key, std::optional<Certificate> aa = {});

  /// An Ieee1609Dot2Data (COER) for the CAM @p payload (GN common header onwards) at TAI @p now.
  Bytes sign_cam(std::span<const std::uint8_t> payload, Time64 now);
  Bytes sign_denm(std::span<const std::uint8_t> payload, Time64 now, const ThreeDLocation& where);

  /// The generic profile (7.1.3) for @p psid, signer as above.
  Bytes sign_other(Psid psid, std::span<const std::uint8_t> payload, Time64 now);

  /// Any psid with the signer form chosen by the caller (tests, other services).
  Bytes sign(Psid psid, std::span<const std::uint8_t> payload, Time64 now,
             const std::optional<ThreeDLocation>& where, bool with_certificate);

  /// A CAM from a station we did not know arrived: the next CAM carries the AT (7.1.1).
  void on_unknown_station() { certificate_due_ = true; }
  /// A peer's inlineP2pcdRequest named @p id: our AT (next CAM carries it) or our AA (next CAM
  /// carries it as requestedCertificate).
  void on_certificate_request(const HashedId3& id);
  /// We hold a packet signed by an unknown digest: ask for its certificate in the next CAM.
  void request_certificate(const HashedId8& unknown);

  /// Whether our AT's appPermissions hold @p psid (an AT of an older its-pki lacks GN-MGMT).
  bool permits(Psid psid) const;

  /// Whether the last packet signed carried the AT (else its digest).
  bool last_with_certificate() const { return last_with_certificate_; }

  const Certificate& certificate() const { return at_; }
  const HashedId8& id() const { return id_; }

 private:
  Certificate at_;
  EcKey key_;
  std::optional<Certificate> aa_;
  Octets32 hash_{};
  HashedId8 id_{};
  std::optional<HashedId3> aa_id3_;
  std::optional<Time64> last_certificate_;
  bool certificate_due_ = true;
  bool last_with_certificate_ = false;
  bool aa_requested_ = false;
  std::vector<HashedId3> requests_;
};

/// The 1-second rule of TS 103 097 7.1.1.
inline constexpr Time64 kCamCertificateInterval = 1'000'000;

}  // namespace tb::its::security
