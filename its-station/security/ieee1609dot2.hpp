#pragma once
/// @file The IEEE 1609.2 structures that ETSI TS 103 097 v1.3.1 uses for signed CAMs and DENMs
/// and for explicit certificates, and their COER encoding (asn1/coer.hpp).
///
/// What TS 103 097 v1.3.1 allows is decoded: signedData whose payload is unsecuredData, every
/// HeaderInfo component but encryptionKey (which no CAM or DENM carries), signer digest,
/// certificate or self, explicit certificates with any region, permissions and keys, unknown
/// extension additions skipped. Components the testbed does not interpret (region, linkage
/// data, encryption keys) are kept as their COER octets, checked for structure on decode and
/// written back unchanged.
///
/// Decoding fills `encoding` fields with the received octets (the tbsData of a SignedData, the
/// whole of a Certificate): signatures and HashedId8s are computed over what was received. They
/// take no part in comparisons.

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "common/util/expected.hpp"
#include "its-station/asn1/error.hpp"

namespace tb::its::asn1 {
class CoerWriter;
class CoerReader;
}  // namespace tb::its::asn1

namespace tb::its::security {

using Bytes = std::vector<std::uint8_t>;
using HashedId3 = std::array<std::uint8_t, 3>;
using HashedId8 = std::array<std::uint8_t, 8>;
using Octets32 = std::array<std::uint8_t, 32>;
using Psid = std::uint64_t;
/// Microseconds since 2004-01-01 00:00:00 TAI (1609.2 6.4.12).
using Time64 = std::uint64_t;
/// Seconds since 2004-01-01 00:00:00 TAI (1609.2 6.4.13).
using Time32 = std::uint32_t;

/// ITS-AIDs of ETSI TS 102 965: CA basic service, DEN basic service, GeoNetworking management
/// (GN-MGMT: the beacons a secured router signs, EN 302 636-4-1 10.3.6.2 with TS 103 097 7.1.3).
inline constexpr Psid kPsidCam = 36;
inline constexpr Psid kPsidDenm = 37;
inline constexpr Psid kPsidGnMgmt = 141;
/// TS 102 965: TLM (traffic light manoeuvre, SPATEM) and RLT (road and lane topology, MAPEM).
inline constexpr Psid kPsidSpatem = 137;
inline constexpr Psid kPsidMapem = 138;

enum class HashAlgorithm : std::uint8_t { kSha256 = 0, kSha384 = 1 };

/// EccP256CurvePoint (1609.2 6.4.23): the alternative is the point's form.
struct EccP256CurvePoint {
  enum class Form : std::uint8_t {
    kXOnly = 0,
    kFill = 1,
    kCompressedY0 = 2,
    kCompressedY1 = 3,
    kUncompressed = 4
  };
  Form form = Form::kXOnly;
  Octets32 x{};
  Octets32 y{};  ///< only for kUncompressed
  bool operator==(const EccP256CurvePoint&) const = default;
};

/// The curve of a verification key or signature: the PublicVerificationKey / Signature
/// alternative (1609.2 6.4.36, 6.3.28).
enum class EccCurve : std::uint8_t { kNistP256 = 0, kBrainpoolP256r1 = 1 };

struct PublicVerificationKey {
  EccCurve curve = EccCurve::kNistP256;
  EccP256CurvePoint point;
  bool operator==(const PublicVerificationKey&) const = default;
};

/// EcdsaP256Signature in its Signature alternative.
struct Signature {
  EccCurve curve = EccCurve::kNistP256;
  EccP256CurvePoint r;
  Octets32 s{};
  bool operator==(const Signature&) const = default;
};

/// Duration (1609.2 6.4.15): one unit and a 16-bit count.
enum class DurationUnit : std::uint8_t {
  kMicroseconds = 0,
  kMilliseconds,
  kSeconds,
  kMinutes,
  kHours,
  kSixtyHours,
  kYears
};

struct ValidityPeriod {
  Time32 start = 0;
  DurationUnit unit = DurationUnit::kHours;
  std::uint16_t duration = 0;
  /// start + duration in seconds (1609.2 6.4.15: a year is 31556952 s), rounded down.
  std::uint64_t end_seconds() const;
  bool operator==(const ValidityPeriod&) const = default;
};

/// ServiceSpecificPermissions: opaque or (extension alternative 1) bitmapSsp.
struct Ssp {
  enum class Kind : std::uint8_t { kOpaque = 0, kBitmap = 1 };
  Kind kind = Kind::kBitmap;
  Bytes bytes;
  bool operator==(const Ssp&) const = default;
};

struct PsidSsp {
  Psid psid = 0;
  std::optional<Ssp> ssp;
  bool operator==(const PsidSsp&) const = default;
};

/// SspRange: opaque list, all, or (extension) bitmapSspRange.
struct SspRange {
  enum class Kind : std::uint8_t { kOpaque = 0, kAll = 1, kBitmap = 2 };
  Kind kind = Kind::kAll;
  std::vector<Bytes> opaque;
  Bytes value;  ///< bitmapSspRange.sspValue
  Bytes mask;   ///< bitmapSspRange.sspBitmask
  bool operator==(const SspRange&) const = default;
};

struct PsidSspRange {
  Psid psid = 0;
  std::optional<SspRange> range;
  bool operator==(const PsidSspRange&) const = default;
};

/// PsidGroupPermissions (1609.2 6.4.30). subjectPermissions `all` when all_psids.
struct PsidGroupPermissions {
  bool all_psids = false;
  std::vector<PsidSspRange> psids;  ///< subjectPermissions explicit
  std::int64_t min_chain_length = 1;
  std::int64_t chain_length_range = 0;
  std::uint8_t ee_type = 0x80;  ///< EndEntityType BIT STRING {app(0), enrol(1)}: app
  bool operator==(const PsidGroupPermissions&) const = default;
};

struct CertificateId {
  enum class Kind : std::uint8_t { kLinkageData = 0, kName = 1, kBinaryId = 2, kNone = 3 };
  Kind kind = Kind::kNone;
  Bytes value;  ///< name octets, binaryId octets, or the linkageData's COER octets
  bool operator==(const CertificateId&) const = default;
};

struct ToBeSignedCertificate {
  CertificateId id;
  HashedId3 craca_id{};
  std::uint16_t crl_series = 0;
  ValidityPeriod validity;
  std::optional<Bytes> region;  ///< GeographicRegion, COER octets
  std::optional<std::uint8_t> assurance_level;
  std::optional<std::vector<PsidSsp>> app_permissions;
  std::optional<std::vector<PsidGroupPermissions>> cert_issue_permissions;
  std::optional<std::vector<PsidGroupPermissions>> cert_request_permissions;
  bool can_request_rollover = false;
  std::optional<Bytes> encryption_key;  ///< PublicEncryptionKey, COER octets
  PublicVerificationKey verify_key;     ///< verifyKeyIndicator verificationKey
  bool operator==(const ToBeSignedCertificate&) const = default;
};

struct IssuerIdentifier {
  enum class Kind : std::uint8_t { kSha256AndDigest = 0, kSelf = 1, kSha384AndDigest = 2 };
  Kind kind = Kind::kSelf;
  HashedId8 digest{};                                ///< the issuer's HashedId8
  HashAlgorithm self_hash = HashAlgorithm::kSha256;  ///< for kSelf
  /// Compares what the alternative holds.
  bool operator==(const IssuerIdentifier& o) const {
    return kind == o.kind && (kind == Kind::kSelf ? self_hash == o.self_hash : digest == o.digest);
  }
};

/// EtsiTs103097Certificate: CertificateBase version 3, type explicit. A decoded certificate is
/// encoded as the octets it came in; change one through sign_certificate() (pki.hpp), which
/// encodes it anew.
struct Certificate {
  IssuerIdentifier issuer;
  ToBeSignedCertificate tbs;
  std::optional<Signature> signature;
  Bytes encoding;  ///< the octets it was decoded from (empty when built here)
  /// Where toBeSigned lies in `encoding` (offset, length; length 0 when built here): the octets
  /// the issuer signed (1609.2 6.4.3, 5.3.1), extension additions the decoder skips included.
  std::size_t tbs_offset = 0;
  std::size_t tbs_length = 0;
  /// Where toBeSigned.verifyKeyIndicator's EccP256CurvePoint lies in `encoding`: the one part
  /// of the received octets that canonicalisation (1609.2 6.4.3: compressed points) may change.
  std::size_t key_offset = 0;
  std::size_t key_length = 0;

  /// The received toBeSigned octets (empty when built here).
  std::span<const std::uint8_t> tbs_octets() const {
    if (tbs_length == 0 || tbs_offset + tbs_length > encoding.size())
      return {};
    return std::span(encoding).subspan(tbs_offset, tbs_length);
  }
  bool operator==(const Certificate& o) const {
    return issuer == o.issuer && tbs == o.tbs && signature == o.signature;
  }
};

struct SignerIdentifier {
  enum class Kind : std::uint8_t { kDigest = 0, kCertificate = 1, kSelf = 2 };
  Kind kind = Kind::kDigest;
  HashedId8 digest{};
  std::vector<Certificate> certificates;
  /// Compares what the alternative holds.
  bool operator==(const SignerIdentifier& o) const {
    return kind == o.kind && (kind != Kind::kDigest || digest == o.digest) &&
           (kind != Kind::kCertificate || certificates == o.certificates);
  }
};

/// ThreeDLocation (1609.2 6.4.24): 1/10 micro degree, elevation in decimetres offset by 4096.
struct ThreeDLocation {
  std::int32_t latitude = 0;
  std::int32_t longitude = 0;
  std::uint16_t elevation = 0;
  bool operator==(const ThreeDLocation&) const = default;
};

struct MissingCrlIdentifier {
  HashedId3 craca_id{};
  std::uint16_t crl_series = 0;
  bool operator==(const MissingCrlIdentifier&) const = default;
};

struct HeaderInfo {
  Psid psid = 0;
  std::optional<Time64> generation_time;
  std::optional<Time64> expiry_time;
  std::optional<ThreeDLocation> generation_location;
  std::optional<HashedId3> p2pcd_learning_request;
  std::optional<MissingCrlIdentifier> missing_crl_identifier;
  std::optional<std::vector<HashedId3>> inline_p2pcd_request;  ///< extension addition 1
  std::optional<Certificate> requested_certificate;            ///< extension addition 2
  bool operator==(const HeaderInfo&) const = default;
};

/// SignedDataPayload: data (an Ieee1609Dot2Data with unsecuredData, kept as those octets)
/// and/or extDataHash.
struct SignedDataPayload {
  std::optional<Bytes> data;
  std::optional<Octets32> ext_data_hash;
  bool operator==(const SignedDataPayload&) const = default;
};

struct ToBeSignedData {
  SignedDataPayload payload;
  HeaderInfo header;
  bool operator==(const ToBeSignedData&) const = default;
};

struct SignedData {
  HashAlgorithm hash_id = HashAlgorithm::kSha256;
  ToBeSignedData tbs;
  SignerIdentifier signer;
  Signature signature;
  Bytes tbs_encoding;  ///< the received tbsData octets (empty when built here)
  bool operator==(const SignedData& o) const {
    return hash_id == o.hash_id && tbs == o.tbs && signer == o.signer && signature == o.signature;
  }
};

/// Ieee1609Dot2Data protocolVersion 3 (TS 103 097 EtsiTs103097Data): unsecuredData or
/// signedData.
struct Ieee1609Dot2Data {
  enum class Content : std::uint8_t { kUnsecuredData = 0, kSignedData = 1 };
  Content content = Content::kSignedData;
  Bytes unsecured_data;
  SignedData signed_data;
  bool operator==(const Ieee1609Dot2Data&) const = default;
};

inline constexpr std::uint8_t kIeee1609Dot2ProtocolVersion = 3;

// Whole-buffer entry points: the octets must hold exactly one value.
Expected<Ieee1609Dot2Data, asn1::CodecError> decode_data(std::span<const std::uint8_t> bytes);
Expected<Certificate, asn1::CodecError> decode_certificate(std::span<const std::uint8_t> bytes);
Bytes encode(const Ieee1609Dot2Data& data);
Bytes encode(const Certificate& cert);
Bytes encode(const ToBeSignedData& tbs);
Bytes encode(const ToBeSignedCertificate& tbs);

/// Reads one Ieee1609Dot2Data from the front of @p bytes (a secured GN packet continues with
/// nothing after it, but the caller decides); *consumed gets its length.
Expected<Ieee1609Dot2Data, asn1::CodecError> decode_data_prefix(std::span<const std::uint8_t> bytes,
                                                                std::size_t* consumed);

namespace coer {
// Component codecs, for tests and for the signer's hash inputs.
void put(asn1::CoerWriter& w, const Certificate& c);
void put(asn1::CoerWriter& w, const ToBeSignedData& t);
void put(asn1::CoerWriter& w, const Signature& s);
void put(asn1::CoerWriter& w, const EccP256CurvePoint& p);
void get(asn1::CoerReader& r, Certificate& c);
}  // namespace coer

}  // namespace tb::its::security
