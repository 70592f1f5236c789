#include "its-station/security/crypto.hpp"

#include <openssl/bio.h>
#include <openssl/bn.h>
#include <openssl/core_names.h>
#include <openssl/ec.h>
#include <openssl/err.h>
#include <openssl/evp.h>
#include <openssl/params.h>
#include <openssl/pem.h>
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <utility>

#include "its-station/asn1/coer.hpp"

namespace tb::its::security {
namespace {

const char* group_name(EccCurve c) {
  return c == EccCurve::kNistP256 ? "prime256v1" : "brainpoolP256r1";
}

std::string openssl_error() {
  const unsigned long e = ERR_get_error();
  if (e == 0)
    return "no OpenSSL error";
  char buf[256];
  ERR_error_string_n(e, buf, sizeof buf);
  ERR_clear_error();
  return buf;
}

struct CtxFree {
  void operator()(EVP_PKEY_CTX* c) const { EVP_PKEY_CTX_free(c); }
};
using CtxPtr = std::unique_ptr<EVP_PKEY_CTX, CtxFree>;
struct BioFree {
  void operator()(BIO* b) const { BIO_free(b); }
};
using BioPtr = std::unique_ptr<BIO, BioFree>;
struct SigFree {
  void operator()(ECDSA_SIG* s) const { ECDSA_SIG_free(s); }
};
using SigPtr = std::unique_ptr<ECDSA_SIG, SigFree>;

EccCurve curve_of(EVP_PKEY* k, const std::string& what) {
  char name[64] = {};
  size_t len = 0;
  if (EVP_PKEY_get_utf8_string_param(k, OSSL_PKEY_PARAM_GROUP_NAME, name, sizeof name, &len) != 1)
    throw CryptoError(what + ": not an EC key");
  const std::string n(name, len);
  if (n == "prime256v1" || n == "P-256")
    return EccCurve::kNistP256;
  if (n == "brainpoolP256r1")
    return EccCurve::kBrainpoolP256r1;
  throw CryptoError(what + ": curve " + n + " is neither P-256 nor brainpoolP256r1");
}

}  // namespace

Octets32 sha256(std::span<const std::uint8_t> data) {
  Octets32 out{};
  unsigned int len = 0;
  if (EVP_Digest(data.data(), data.size(), out.data(), &len, EVP_sha256(), nullptr) != 1)
    throw CryptoError("SHA-256: " + openssl_error());
  return out;
}

HashedId8 hashed_id8(const Octets32& h) {
  HashedId8 id{};
  std::copy(h.end() - 8, h.end(), id.begin());
  return id;
}

HashedId3 hashed_id3(const HashedId8& id) {
  return {id[5], id[6], id[7]};
}

namespace {

bool compressed(const EccP256CurvePoint& p) {
  return p.form == EccP256CurvePoint::Form::kCompressedY0 ||
         p.form == EccP256CurvePoint::Form::kCompressedY1;
}

/// 1609.2 6.4.3 canonicalisation of a verification key: compressed-y-0/1 from uncompressed.
EccP256CurvePoint canonical_key(EccP256CurvePoint p) {
  if (p.form == EccP256CurvePoint::Form::kUncompressed)
    p.form = (p.y[31] & 1) != 0 ? EccP256CurvePoint::Form::kCompressedY1
                                : EccP256CurvePoint::Form::kCompressedY0;
  return p;
}

/// Whether the received octets of @p c can be spliced (decoded here, offsets in range).
bool spliceable(const Certificate& c) {
  return !c.tbs_octets().empty() && c.key_length > 0 && c.key_offset >= c.tbs_offset &&
         c.key_offset + c.key_length <= c.tbs_offset + c.tbs_length;
}

/// The received toBeSigned octets of @p c with the verification key canonical.
Bytes spliced_tbs(const Certificate& c) {
  const auto tbs = c.tbs_octets();
  if (compressed(c.tbs.verify_key.point))
    return Bytes(tbs.begin(), tbs.end());
  Bytes out(tbs.begin(), tbs.begin() + static_cast<std::ptrdiff_t>(c.key_offset - c.tbs_offset));
  asn1::CoerWriter w(out);
  coer::put(w, canonical_key(c.tbs.verify_key.point));
  out.insert(out.end(),
             tbs.begin() + static_cast<std::ptrdiff_t>(c.key_offset + c.key_length - c.tbs_offset),
             tbs.end());
  return out;
}

}  // namespace

Bytes canonical_tbs(const Certificate& c) {
  if (spliceable(c))
    return spliced_tbs(c);
  ToBeSignedCertificate t = c.tbs;
  t.verify_key.point = canonical_key(t.verify_key.point);
  return encode(t);
}

Bytes canonical_encoding(const Certificate& c) {
  const bool key_ok = compressed(c.tbs.verify_key.point);
  const bool sig_ok = !c.signature || c.signature->r.form == EccP256CurvePoint::Form::kXOnly;
  if (key_ok && sig_ok && !c.encoding.empty())
    return c.encoding;
  if (spliceable(c)) {
    // The issuer, the canonical toBeSigned, the signature with r x-only: nothing the decoder
    // skipped is lost.
    Bytes out(c.encoding.begin(), c.encoding.begin() + static_cast<std::ptrdiff_t>(c.tbs_offset));
    const Bytes tbs = spliced_tbs(c);
    out.insert(out.end(), tbs.begin(), tbs.end());
    if (c.signature) {
      Signature s = *c.signature;
      s.r.form = EccP256CurvePoint::Form::kXOnly;
      asn1::CoerWriter w(out);
      coer::put(w, s);
    }
    return out;
  }
  Certificate canon = c;
  canon.tbs.verify_key.point = canonical_key(canon.tbs.verify_key.point);
  if (canon.signature)
    canon.signature->r.form = EccP256CurvePoint::Form::kXOnly;
  return encode(canon);
}

Octets32 signed_digest(std::span<const std::uint8_t> tbs, const Octets32& signer_hash) {
  std::array<std::uint8_t, 64> both{};
  const Octets32 t = sha256(tbs);
  std::copy(t.begin(), t.end(), both.begin());
  std::copy(signer_hash.begin(), signer_hash.end(), both.begin() + 32);
  return sha256(both);
}

EcKey::EcKey(EcKey&& o) noexcept
    : key_(std::exchange(o.key_, nullptr)),
      sign_ctx_(std::exchange(o.sign_ctx_, nullptr)),
      verify_ctx_(std::exchange(o.verify_ctx_, nullptr)),
      curve_(o.curve_) {}

EcKey& EcKey::operator=(EcKey&& o) noexcept {
  if (this != &o) {
    EVP_PKEY_CTX_free(sign_ctx_);
    EVP_PKEY_CTX_free(verify_ctx_);
    EVP_PKEY_free(key_);
    key_ = std::exchange(o.key_, nullptr);
    sign_ctx_ = std::exchange(o.sign_ctx_, nullptr);
    verify_ctx_ = std::exchange(o.verify_ctx_, nullptr);
    curve_ = o.curve_;
  }
  return *this;
}

EcKey::~EcKey() {
  EVP_PKEY_CTX_free(sign_ctx_);
  EVP_PKEY_CTX_free(verify_ctx_);
  EVP_PKEY_free(key_);
}

EVP_PKEY_CTX* EcKey::sign_context() const {
  if (sign_ctx_ == nullptr) {
    CtxPtr ctx(EVP_PKEY_CTX_new(key_, nullptr));
    if (!ctx || EVP_PKEY_sign_init(ctx.get()) != 1 ||
        EVP_PKEY_CTX_set_signature_md(ctx.get(), EVP_sha256()) != 1)
      throw CryptoError("ECDSA sign: " + openssl_error());
    sign_ctx_ = ctx.release();
  }
  return sign_ctx_;
}

EVP_PKEY_CTX* EcKey::verify_context() const {
  if (verify_ctx_ == nullptr) {
    CtxPtr ctx(EVP_PKEY_CTX_new(key_, nullptr));
    if (!ctx || EVP_PKEY_verify_init(ctx.get()) != 1 ||
        EVP_PKEY_CTX_set_signature_md(ctx.get(), EVP_sha256()) != 1)
      throw CryptoError("ECDSA verify: " + openssl_error());
    verify_ctx_ = ctx.release();
  }
  return verify_ctx_;
}

EcKey EcKey::generate(EccCurve curve) {
  EVP_PKEY* k = EVP_PKEY_Q_keygen(nullptr, nullptr, "EC", group_name(curve));
  if (k == nullptr)
    throw CryptoError(std::string("EC key generation on ") + group_name(curve) + ": " +
                      openssl_error());
  return EcKey(k, curve);
}

EcKey EcKey::load_private_pem(const std::string& path) {
  BioPtr bio(BIO_new_file(path.c_str(), "r"));
  if (!bio)
    throw CryptoError(path + ": cannot open (" + openssl_error() + ")");
  EVP_PKEY* k = PEM_read_bio_PrivateKey(bio.get(), nullptr, nullptr, nullptr);
  if (k == nullptr)
    throw CryptoError(path + ": not a PEM private key (" + openssl_error() + ")");
  try {
    const EccCurve c = curve_of(k, path);
    return EcKey(k, c);
  } catch (...) {
    EVP_PKEY_free(k);
    throw;
  }
}

EcKey EcKey::load_public_pem(const std::string& path) {
  BioPtr bio(BIO_new_file(path.c_str(), "r"));
  if (!bio)
    throw CryptoError(path + ": cannot open (" + openssl_error() + ")");
  EVP_PKEY* k = PEM_read_bio_PUBKEY(bio.get(), nullptr, nullptr, nullptr);
  if (k == nullptr)
    throw CryptoError(path + ": not a PEM public key (SubjectPublicKeyInfo) (" + openssl_error() +
                      ")");
  try {
    const EccCurve c = curve_of(k, path);
    // The point on its curve (OpenSSL's full public-key check, not only the parse).
    CtxPtr ctx(EVP_PKEY_CTX_new_from_pkey(nullptr, k, nullptr));
    if (!ctx || EVP_PKEY_public_check(ctx.get()) != 1)
      throw CryptoError(path + ": the public key fails OpenSSL's check (" + openssl_error() + ")");
    return EcKey(k, c);
  } catch (...) {
    EVP_PKEY_free(k);
    throw;
  }
}

EcKey EcKey::from_point(EccCurve curve, const EccP256CurvePoint& p) {
  std::array<std::uint8_t, 65> buf{};
  std::size_t len = 0;
  switch (p.form) {
    case EccP256CurvePoint::Form::kCompressedY0:
    case EccP256CurvePoint::Form::kCompressedY1:
      buf[0] = p.form == EccP256CurvePoint::Form::kCompressedY0 ? 0x02 : 0x03;
      std::copy(p.x.begin(), p.x.end(), buf.begin() + 1);
      len = 33;
      break;
    case EccP256CurvePoint::Form::kUncompressed:
      buf[0] = 0x04;
      std::copy(p.x.begin(), p.x.end(), buf.begin() + 1);
      std::copy(p.y.begin(), p.y.end(), buf.begin() + 33);
      len = 65;
      break;
    default:
      throw CryptoError("verification key: an x-only or fill point is not a public key");
  }
  CtxPtr ctx(EVP_PKEY_CTX_new_from_name(nullptr, "EC", nullptr));
  OSSL_PARAM params[] = {
      OSSL_PARAM_construct_utf8_string(OSSL_PKEY_PARAM_GROUP_NAME,
                                       const_cast<char*>(group_name(curve)), 0),
      OSSL_PARAM_construct_octet_string(OSSL_PKEY_PARAM_PUB_KEY, buf.data(), len),
      OSSL_PARAM_construct_end()};
  EVP_PKEY* k = nullptr;
  if (!ctx || EVP_PKEY_fromdata_init(ctx.get()) != 1 ||
      EVP_PKEY_fromdata(ctx.get(), &k, EVP_PKEY_PUBLIC_KEY, params) != 1 || k == nullptr)
    throw CryptoError(std::string("verification key: not a point on ") + group_name(curve) + " (" +
                      openssl_error() + ")");
  return EcKey(k, curve);
}

void EcKey::save_private_pem(const std::string& path) const {
  BioPtr bio(BIO_new_file(path.c_str(), "w"));
  if (!bio)
    throw CryptoError(path + ": cannot create (" + openssl_error() + ")");
  ::chmod(path.c_str(), 0600);  // a private key: owner only
  if (PEM_write_bio_PrivateKey(bio.get(), key_, nullptr, nullptr, 0, nullptr, nullptr) != 1)
    throw CryptoError(path + ": cannot write the key (" + openssl_error() + ")");
}

void EcKey::save_public_pem(const std::string& path) const {
  BioPtr bio(BIO_new_file(path.c_str(), "w"));
  if (!bio)
    throw CryptoError(path + ": cannot create (" + openssl_error() + ")");
  if (PEM_write_bio_PUBKEY(bio.get(), key_) != 1)
    throw CryptoError(path + ": cannot write the key (" + openssl_error() + ")");
}

EccP256CurvePoint EcKey::public_point() const {
  std::array<std::uint8_t, 65> buf{};
  std::size_t len = 0;
  if (EVP_PKEY_get_octet_string_param(key_, OSSL_PKEY_PARAM_ENCODED_PUBLIC_KEY, buf.data(),
                                      buf.size(), &len) != 1 ||
      len != 65 || buf[0] != 0x04)
    throw CryptoError("public key: " + openssl_error());
  EccP256CurvePoint p;
  p.form = (buf[64] & 1) != 0 ? EccP256CurvePoint::Form::kCompressedY1
                              : EccP256CurvePoint::Form::kCompressedY0;
  std::copy(buf.begin() + 1, buf.begin() + 33, p.x.begin());
  return p;
}

Signature EcKey::sign(const Octets32& digest) const {
  std::array<std::uint8_t, 80> der{};
  std::size_t der_len = der.size();
  if (key_ == nullptr ||
      EVP_PKEY_sign(sign_context(), der.data(), &der_len, digest.data(), digest.size()) != 1)
    throw CryptoError("ECDSA sign: " + openssl_error());
  const unsigned char* p = der.data();
  SigPtr sig(d2i_ECDSA_SIG(nullptr, &p, static_cast<long>(der_len)));
  if (!sig)
    throw CryptoError("ECDSA sign: " + openssl_error());
  const BIGNUM* r = nullptr;
  const BIGNUM* s = nullptr;
  ECDSA_SIG_get0(sig.get(), &r, &s);
  Signature out;
  out.curve = curve_;
  out.r.form = EccP256CurvePoint::Form::kXOnly;
  if (BN_bn2binpad(r, out.r.x.data(), 32) != 32 || BN_bn2binpad(s, out.s.data(), 32) != 32)
    throw CryptoError("ECDSA sign: r or s longer than 32 octets");
  return out;
}

bool EcKey::verify(const Octets32& digest, const Signature& sig) const {
  if (key_ == nullptr || sig.curve != curve_ || sig.r.form == EccP256CurvePoint::Form::kFill)
    return false;
  SigPtr s(ECDSA_SIG_new());
  BIGNUM* r = BN_bin2bn(sig.r.x.data(), 32, nullptr);
  BIGNUM* sv = BN_bin2bn(sig.s.data(), 32, nullptr);
  if (!s || r == nullptr || sv == nullptr || ECDSA_SIG_set0(s.get(), r, sv) != 1) {
    BN_free(r);
    BN_free(sv);
    throw CryptoError("ECDSA verify: " + openssl_error());
  }
  std::array<std::uint8_t, 80> der{};
  unsigned char* p = der.data();
  const int der_len = i2d_ECDSA_SIG(s.get(), nullptr);
  if (der_len <= 0 || static_cast<std::size_t>(der_len) > der.size() ||
      i2d_ECDSA_SIG(s.get(), &p) != der_len)
    return false;
  const int ok = EVP_PKEY_verify(verify_context(), der.data(), static_cast<std::size_t>(der_len),
                                 digest.data(), digest.size());
  ERR_clear_error();  // a failed verification leaves an error on the queue
  return ok == 1;
}

}  // namespace tb::its::security
