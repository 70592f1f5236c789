#pragma once
/// @file A test PKI after TS 103 097 v1.3.1 clause 7.2 and TS 102 940: a self-signed root CA,
/// an authorization authority (AA) it certifies, and authorization tickets (AT) the AA issues,
/// all explicit certificates with P-256 keys. its-pki writes them to files; tests make them in
/// memory.

#include <string>

#include "its-station/security/crypto.hpp"
#include "its-station/security/ieee1609dot2.hpp"

namespace tb::its::security {

/// SHA-256 of the certificate's canonical COER: the signer hash of 1609.2 5.3.1 and, in its
/// last 8 octets, the HashedId8.
Octets32 certificate_hash(const Certificate& c);
inline HashedId8 certificate_id(const Certificate& c) {
  return hashed_id8(certificate_hash(c));
}

/// Signs @p c with @p issuer_key: by its issuer @p issuer (AA, AT), or self-signed when
/// @p issuer is null (root): 1609.2 5.3.1 hashes the empty string in the signer's place.
/// Sets issuer and signature; the encoding is refreshed.
void sign_certificate(Certificate& c, const Certificate* issuer, const EcKey& issuer_key);

/// CAM and DENM service-specific permissions of an AT: SSP version 1 and no special-vehicle
/// or cause-code restriction bits the testbed uses (TS 103 900 / TS 103 831 layouts).
inline const Bytes kCamSsp{0x01, 0x00, 0x00};
inline const Bytes kDenmSsp{0x01, 0xff, 0xff, 0xff};

/// What an AA may issue: CAM, DENM (any SSP), GN-MGMT, and a road-side unit's SPATEM and MAPEM.
std::vector<PsidSspRange> authority_issue_permissions();
/// An AT's appPermissions: CAM (kCamSsp), DENM (kDenmSsp), GN-MGMT (no SSP, the beacons); a
/// road-side unit's (@p road_side_unit) also SPATEM (137) and MAPEM (138), without an SSP: the
/// layout of TS 103 301's SSPs for them was not at hand (its-station/security/README.md).
std::vector<PsidSsp> ticket_permissions(bool road_side_unit = false);

/// The root CA: names itself, may issue everything through one more level (minChainLength 2).
Certificate make_root(const EcKey& key, const std::string& name, ValidityPeriod validity);
/// An AA under @p root that may issue CAM, DENM and GN-MGMT ATs.
Certificate make_authority(const EcKey& key, const std::string& name, ValidityPeriod validity,
                           const Certificate& root, const EcKey& root_key);
/// An AT (id none, TS 103 097 7.2.1) with CAM and DENM permissions (kCamSsp, kDenmSsp) and
/// GN-MGMT (no SSP) for the router's beacons.
/// A road-side unit's AT (@p road_side_unit) adds SPATEM and MAPEM (ticket_permissions()).
Certificate make_ticket(const EcKey& key, ValidityPeriod validity, const Certificate& aa,
                        const EcKey& aa_key, bool road_side_unit = false);

}  // namespace tb::its::security
