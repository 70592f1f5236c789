#pragma once
/// @file The cryptography of IEEE 1609.2 through OpenSSL 3: SHA-256, HashedId8/HashedId3, ECDSA
/// on NIST P-256 and brainpoolP256r1 with the points and signatures in their 1609.2 forms.

#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

#include "its-station/security/ieee1609dot2.hpp"

struct evp_pkey_st;      // OpenSSL's EVP_PKEY
struct evp_pkey_ctx_st;  // OpenSSL's EVP_PKEY_CTX

namespace tb::its::security {

/// An error of the crypto library or of key material (a file, a point not on the curve).
class CryptoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

Octets32 sha256(std::span<const std::uint8_t> data);

/// 1609.2 6.4.3: the low-order 8 (3) octets of the SHA-256 of the certificate's canonical
/// COER (compressed or x-only points, 6.4.3 / TS 103 097 5.2).
HashedId8 hashed_id8(const Octets32& certificate_hash);
HashedId3 hashed_id3(const HashedId8& id);

/// The canonical COER octets of @p c: its received octets when they already are canonical,
/// else those octets with an uncompressed verification key compressed and signature r made
/// x-only (1609.2 6.4.3); a certificate built here is encoded.
Bytes canonical_encoding(const Certificate& c);

/// The canonical COER octets of @p c's toBeSigned, the data input of the issuer's signature
/// (1609.2 6.4.3, 5.3.1): the received octets, extension additions the decoder skips included,
/// with an uncompressed verification key compressed; encode(c.tbs) for one built here.
Bytes canonical_tbs(const Certificate& c);

/// SHA-256 over SHA-256(@p tbs) || SHA-256(@p signer): the digest 1609.2 5.3.1 signs; the
/// signer octets are empty for a self-signed (root) certificate.
Octets32 signed_digest(std::span<const std::uint8_t> tbs, const Octets32& signer_hash);

/// An EC key pair or public key (an EVP_PKEY) on one of the two 1609.2 P-256 curves.
class EcKey {
 public:
  EcKey() = default;
  EcKey(EcKey&&) noexcept;
  EcKey& operator=(EcKey&&) noexcept;
  ~EcKey();

  static EcKey generate(EccCurve curve);
  /// A private key from a PEM file (PKCS#8 or SEC1). Throws CryptoError naming the file.
  static EcKey load_private_pem(const std::string& path);
  /// A public key from a PEM file (SubjectPublicKeyInfo, "BEGIN PUBLIC KEY"), checked by
  /// OpenSSL (the point on its curve). Throws CryptoError naming the file when it is no such
  /// key or its curve is not one of the two.
  static EcKey load_public_pem(const std::string& path);
  /// The public key of a 1609.2 point (compressed or uncompressed; x-only and fill cannot be
  /// keys). Throws CryptoError when the point is not on the curve.
  static EcKey from_point(EccCurve curve, const EccP256CurvePoint& p);

  void save_private_pem(const std::string& path) const;
  /// The public key as SubjectPublicKeyInfo PEM.
  void save_public_pem(const std::string& path) const;
  /// The public key as compressed-y-0/1.
  EccP256CurvePoint public_point() const;
  EccCurve curve() const { return curve_; }
  bool valid() const { return key_ != nullptr; }

  /// ECDSA over the 32-octet @p digest; r as x-only (TS 103 097 5.2 allows it, it is the
  /// smaller form).
  Signature sign(const Octets32& digest) const;
  /// Verifies @p sig (r x-only or compressed: only its x is used) over @p digest.
  bool verify(const Octets32& digest, const Signature& sig) const;

 private:
  EcKey(evp_pkey_st* k, EccCurve c) : key_(k), curve_(c) {}
  // One context per operation, initialised on first use and reused: making one per call costs
  // as much as a third of a P-256 signature. An EcKey is therefore used by one thread at a time.
  evp_pkey_ctx_st* sign_context() const;
  evp_pkey_ctx_st* verify_context() const;
  evp_pkey_st* key_ = nullptr;
  mutable evp_pkey_ctx_st* sign_ctx_ = nullptr;
  mutable evp_pkey_ctx_st* verify_ctx_ = nullptr;
  EccCurve curve_ = EccCurve::kNistP256;
};

}  // namespace tb::its::security
