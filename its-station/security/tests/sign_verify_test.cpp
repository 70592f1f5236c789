#include <gtest/gtest.h>
#include <openssl/ec.h>
#include <openssl/obj_mac.h>
#include <openssl/sha.h>

#include <algorithm>
#include <chrono>

#include "its-station/asn1/coer.hpp"

#include "its-station/security/pki.hpp"
#include "its-station/security/signer.hpp"
#include "its-station/security/tests/socktap_capture.hpp"
#include "its-station/security/time.hpp"
#include "its-station/security/verifier.hpp"

namespace tb::its::security {
namespace {

using namespace std::chrono_literals;

// 2026-11-23 17:18:28 UTC, the instant of the socktap capture.
const clock::WallTime kWall{std::chrono::seconds(1795454308)};
const Time64 kNow = to_time64(kWall);
const Time32 kNowS = static_cast<Time32>(kNow / 1000000);

ValidityPeriod week_from(Time32 start) {
  return {start, DurationUnit::kHours, 168};
}

/// A root, an AA and two ATs, as its-pki makes them.
struct Pki {
  EcKey root_key = EcKey::generate(EccCurve::kNistP256);
  EcKey aa_key = EcKey::generate(EccCurve::kNistP256);
  Certificate root = make_root(root_key, "testbed root", week_from(kNowS - 3600));
  Certificate aa = make_authority(aa_key, "testbed aa", week_from(kNowS - 3600), root, root_key);

  std::pair<Certificate, EcKey> ticket(ValidityPeriod v = week_from(kNowS - 60)) {
    EcKey k = EcKey::generate(EccCurve::kNistP256);
    Certificate c = make_ticket(k, v, aa, aa_key);
    return {std::move(c), std::move(k)};
  }
  Signer signer(ValidityPeriod v = week_from(kNowS - 60)) {
    auto [c, k] = ticket(v);
    return Signer(std::move(c), std::move(k), aa);
  }
  Verifier verifier(VerifierConfig cfg = {}) {
    Verifier v({root}, cfg);
    EXPECT_EQ(v.add_authority(aa, kNow), VerifyResult::kOk);
    return v;
  }
};

const Bytes kPayload{0x20, 0x50, 0x00, 0x80, 0x00, 0x2d, 0x01, 0x00, 0xaa, 0xbb};

TEST(Pki, CertificatesAreCanonicalAndVerifyUpTheChain) {
  Pki pki;
  EXPECT_EQ(pki.root.issuer.kind, IssuerIdentifier::Kind::kSelf);
  EXPECT_EQ(pki.aa.issuer.digest, certificate_id(pki.root));
  auto [at, key] = pki.ticket();
  EXPECT_EQ(at.issuer.digest, certificate_id(pki.aa));
  EXPECT_EQ(at.tbs.verify_key.point, key.public_point());
  // Decoding the octets gives the certificate back, and its hash is that of those octets.
  auto back = decode_certificate(at.encoding);
  ASSERT_TRUE(back) << asn1::to_string(back.error());
  EXPECT_EQ(*back, at);
  EXPECT_EQ(certificate_hash(*back), sha256(at.encoding));
  // An AT of TS 103 097 7.2.1: explicit, id none, x-only r, compressed key, CAM + DENM with
  // their SSPs and GN-MGMT (the beacons) without one.
  EXPECT_EQ(at.tbs.id.kind, CertificateId::Kind::kNone);
  EXPECT_EQ(at.signature->r.form, EccP256CurvePoint::Form::kXOnly);
  ASSERT_TRUE(at.tbs.app_permissions);
  EXPECT_EQ(*at.tbs.app_permissions, ticket_permissions());
  ASSERT_EQ(at.tbs.app_permissions->size(), 3u);
  EXPECT_EQ(at.tbs.app_permissions->at(2).psid, kPsidGnMgmt);
  EXPECT_FALSE(at.tbs.app_permissions->at(2).ssp);
}

TEST(Pki, KeysSurviveAPemFile) {
  const std::string path = ::testing::TempDir() + "/i20-key.pem";
  EcKey k = EcKey::generate(EccCurve::kNistP256);
  k.save_private_pem(path);
  EcKey again = EcKey::load_private_pem(path);
  EXPECT_EQ(again.public_point(), k.public_point());
  const Octets32 digest = sha256(kPayload);
  EXPECT_TRUE(k.verify(digest, again.sign(digest)));
  EXPECT_THROW(EcKey::load_private_pem(path + ".missing"), CryptoError);
}

TEST(SignVerify, CamWithCertificateThenDigestVerifies) {
  Pki pki;
  Signer signer = pki.signer();
  Verifier verifier = pki.verifier();
  const Bytes first = signer.sign_cam(kPayload, kNow);
  auto v = verifier.verify(first, kPsidCam, kNow);
  ASSERT_EQ(v.result, VerifyResult::kOk) << to_string(v.result);
  EXPECT_TRUE(v.signer_certificate_included);
  EXPECT_EQ(v.signer, signer.id());
  EXPECT_EQ(v.time_base, TimeBase::kTai);
  EXPECT_EQ(Bytes(v.payload().begin(), v.payload().end()), kPayload);
  // Within the second: the digest, which the verifier knows from the first CAM.
  const Bytes second = signer.sign_cam(kPayload, kNow + 100'000);
  v = verifier.verify(second, kPsidCam, kNow + 100'000);
  ASSERT_EQ(v.result, VerifyResult::kOk) << to_string(v.result);
  EXPECT_FALSE(v.signer_certificate_included);
  EXPECT_LT(second.size(), first.size());
  // A second later the AT again.
  const Bytes third = signer.sign_cam(kPayload, kNow + 1'000'000);
  v = verifier.verify(third, kPsidCam, kNow + 1'000'000);
  EXPECT_EQ(v.result, VerifyResult::kOk);
  EXPECT_TRUE(v.signer_certificate_included);
  EXPECT_EQ(verifier.count(VerifyResult::kOk), 3u);
}

TEST(SignVerify, UnknownDigestIsNamedAndResolvedByTheCertificate) {
  Pki pki;
  Signer signer = pki.signer();
  Verifier verifier = pki.verifier();
  signer.sign_cam(kPayload, kNow);  // lost on the air
  const Bytes digest = signer.sign_cam(kPayload, kNow + 100'000);
  auto v = verifier.verify(digest, kPsidCam, kNow + 100'000);
  EXPECT_EQ(v.result, VerifyResult::kUnknownSigner);
  ASSERT_TRUE(v.signer);
  // The receiver asks for it by HashedId3; the sender's next CAM carries its AT.
  Signer receiver = pki.signer();
  receiver.request_certificate(*v.signer);
  auto request = decode_data(receiver.sign_cam(kPayload, kNow + 150'000));
  ASSERT_TRUE(request);
  const auto& asked = request->signed_data.tbs.header.inline_p2pcd_request;
  ASSERT_TRUE(asked);
  ASSERT_EQ(asked->size(), 1u);
  signer.on_certificate_request(asked->front());
  auto answer =
      verifier.verify(signer.sign_cam(kPayload, kNow + 200'000), kPsidCam, kNow + 200'000);
  EXPECT_EQ(answer.result, VerifyResult::kOk);
  EXPECT_TRUE(answer.signer_certificate_included);
  EXPECT_EQ(verifier.verify(digest, kPsidCam, kNow + 200'000).result, VerifyResult::kOk);
  EXPECT_EQ(verifier.count(VerifyResult::kUnknownSigner), 1u);
}

TEST(SignVerify, PeerAskingForOurAaGetsItAsRequestedCertificate) {
  Pki pki;
  Signer signer = pki.signer();
  signer.sign_cam(kPayload, kNow);
  signer.on_certificate_request(hashed_id3(certificate_id(pki.aa)));
  auto d = decode_data(signer.sign_cam(kPayload, kNow + 100'000));
  ASSERT_TRUE(d);
  ASSERT_TRUE(d->signed_data.tbs.header.requested_certificate);
  EXPECT_EQ(*d->signed_data.tbs.header.requested_certificate, pki.aa);
  EXPECT_EQ(d->signed_data.signer.kind, SignerIdentifier::Kind::kDigest);
}

/// Flips every bit of octets [from, to) of @p packet and expects each to be rejected.
void expect_every_flip_rejected(Verifier& verifier, const Bytes& packet, std::size_t from,
                                std::size_t to, Psid psid, Time64 now) {
  for (std::size_t i = from; i < to; ++i) {
    for (int bit = 0; bit < 8; ++bit) {
      Bytes b = packet;
      b[i] ^= static_cast<std::uint8_t>(1u << bit);
      const auto r = verifier.verify(b, psid, now).result;
      EXPECT_NE(r, VerifyResult::kOk) << "octet " << i << " bit " << bit;
    }
  }
}

TEST(SignVerify, EverySingleBitFlipInTheSignedPartIsRejected) {
  Pki pki;
  Signer signer = pki.signer();
  Verifier verifier = pki.verifier();
  const Bytes with_cert = signer.sign_cam(kPayload, kNow);
  const Bytes digest = signer.sign_cam(kPayload, kNow + 100'000);
  auto d = decode_data(digest);
  ASSERT_TRUE(d);
  // protocolVersion, content tag, hashId, tbsData, signer digest: every octet before the
  // signature's own tags.
  const std::size_t signed_end = 3 + d->signed_data.tbs_encoding.size() + 1 + 8;
  ASSERT_EQ(verifier.verify(with_cert, kPsidCam, kNow).result, VerifyResult::kOk);
  expect_every_flip_rejected(verifier, digest, 0, signed_end, kPsidCam, kNow + 100'000);
  // The signature values themselves (after the Signature and rSig tags).
  expect_every_flip_rejected(verifier, digest, signed_end + 2, digest.size(), kPsidCam,
                             kNow + 100'000);
  // A fresh verifier sees the certificate form: the tbsData and the AT in it.
  Verifier fresh = pki.verifier();
  auto dc = decode_data(with_cert);
  ASSERT_TRUE(dc);
  const std::size_t cert_end = with_cert.size() - 66;  // signature: tags + r + s
  // The AT's own rSig tag is outside what anything signs: 1609.2 6.4.3 hashes a certificate
  // with r made x-only, so x-only -> compressed-y-0 (one bit) names the same certificate.
  const std::size_t at_r_tag = cert_end - 65;
  ASSERT_EQ(with_cert[at_r_tag], 0x80);
  expect_every_flip_rejected(fresh, with_cert, 0, at_r_tag, kPsidCam, kNow);
  expect_every_flip_rejected(fresh, with_cert, at_r_tag + 1, cert_end, kPsidCam, kNow);
  EXPECT_EQ(fresh.count(VerifyResult::kOk), 0u);
  EXPECT_GT(fresh.count(VerifyResult::kSignatureInvalid), 0u);
  EXPECT_GT(fresh.count(VerifyResult::kCertificateSignature), 0u);
}

TEST(SignVerify, WrongPsidAndMissingPermissionAreRejected) {
  Pki pki;
  Signer signer = pki.signer();
  Verifier verifier = pki.verifier();
  const Bytes cam = signer.sign_cam(kPayload, kNow);
  EXPECT_EQ(verifier.verify(cam, kPsidDenm, kNow).result, VerifyResult::kWrongPsid);
  // An AT whose permissions lack the psid it signs with.
  const Bytes other = signer.sign(0x8007, kPayload, kNow, std::nullopt, true);
  EXPECT_EQ(verifier.verify(other, 0x8007, kNow).result, VerifyResult::kIssuerNotPermitted);
  EcKey k = EcKey::generate(EccCurve::kNistP256);
  Certificate cam_only = make_ticket(k, week_from(kNowS - 60), pki.aa, pki.aa_key);
  cam_only.tbs.app_permissions->erase(cam_only.tbs.app_permissions->begin() + 1);  // no DENM
  sign_certificate(cam_only, &pki.aa, pki.aa_key);
  Signer s2(cam_only, std::move(k), pki.aa);
  const Bytes denm = s2.sign_denm(kPayload, kNow, ThreeDLocation{481351000, 115830000, 4096});
  EXPECT_EQ(verifier.verify(denm, kPsidDenm, kNow).result, VerifyResult::kPsidNotPermitted);
  EXPECT_EQ(verifier.count(VerifyResult::kPsidNotPermitted), 1u);
}

TEST(SignVerify, DenmCarriesLocationAndCertificate) {
  Pki pki;
  Signer signer = pki.signer();
  Verifier verifier = pki.verifier();
  const ThreeDLocation where{481351000, 115830000, 4096 + 5000};
  signer.sign_cam(kPayload, kNow);
  const Bytes denm = signer.sign_denm(kPayload, kNow + 10'000, where);
  auto v = verifier.verify(denm, kPsidDenm, kNow + 10'000);
  ASSERT_EQ(v.result, VerifyResult::kOk) << to_string(v.result);
  EXPECT_TRUE(v.signer_certificate_included);
  EXPECT_EQ(v.data.signed_data.tbs.header.generation_location, where);
  // A DENM without the location is not one TS 103 097 7.1.2 allows.
  const Bytes bare = signer.sign(kPsidDenm, kPayload, kNow, std::nullopt, true);
  EXPECT_EQ(verifier.verify(bare, kPsidDenm, kNow).result,
            VerifyResult::kGenerationLocationMissing);
}

TEST(SignVerify, ExpiredAndNotYetValidTicketsAreRejected) {
  Pki pki;
  Verifier verifier = pki.verifier();
  Signer expired = pki.signer({kNowS - 7200, DurationUnit::kHours, 1});
  EXPECT_EQ(verifier.verify(expired.sign_cam(kPayload, kNow), kPsidCam, kNow).result,
            VerifyResult::kCertificateNotValid);
  Signer future = pki.signer({kNowS + 3600, DurationUnit::kHours, 1});
  EXPECT_EQ(verifier.verify(future.sign_cam(kPayload, kNow), kPsidCam, kNow).result,
            VerifyResult::kCertificateNotValid);
  // A known AT expires too: digest CAMs after its end are rejected.
  Signer short_lived = pki.signer({kNowS - 60, DurationUnit::kSeconds, 120});
  EXPECT_EQ(verifier.verify(short_lived.sign_cam(kPayload, kNow), kPsidCam, kNow).result,
            VerifyResult::kOk);
  const Time64 later = kNow + 61'000'000;
  EXPECT_EQ(
      verifier
          .verify(short_lived.sign(kPsidCam, kPayload, later, std::nullopt, false), kPsidCam, later)
          .result,
      VerifyResult::kCertificateNotValid);
}

TEST(SignVerify, TicketFromAForeignRootIsRejected) {
  Pki ours;
  Pki foreign;
  Verifier verifier = ours.verifier();
  Signer stranger = foreign.signer();
  // Its AA is unknown: named, and which AA it is, to be asked for.
  auto first = verifier.verify(stranger.sign_cam(kPayload, kNow), kPsidCam, kNow);
  EXPECT_EQ(first.result, VerifyResult::kUnknownIssuer);
  EXPECT_EQ(first.missing_issuer, certificate_id(foreign.aa));
  // Once its AA came and was refused (not under our root), its ATs are refused by that reason.
  EXPECT_EQ(verifier.add_authority(foreign.aa, kNow), VerifyResult::kUntrustedRoot);
  EXPECT_EQ(verifier.refused_authority(certificate_id(foreign.aa)), VerifyResult::kUntrustedRoot);
  EXPECT_EQ(
      verifier.verify(stranger.sign(kPsidCam, kPayload, kNow, std::nullopt, true), kPsidCam, kNow)
          .result,
      VerifyResult::kUntrustedRoot);
  EXPECT_FALSE(verifier.refused_authority(certificate_id(ours.aa)));
  // An AA that claims our root but was signed by another key.
  Certificate forged = make_authority(foreign.aa_key, "forged", week_from(kNowS - 3600), ours.root,
                                      foreign.root_key);
  EXPECT_EQ(verifier.add_authority(forged, kNow), VerifyResult::kCertificateSignature);
  // A root that does not verify cannot be trusted at all.
  Certificate bad_root = ours.root;
  bad_root.signature->s[0] ^= 1;
  EXPECT_THROW(Verifier({bad_root}), CryptoError);
}

TEST(SignVerify, BrainpoolP256r1SignaturesAreAccepted) {
  // TS 103 097 5.3: a receiver verifies brainpoolP256r1 as well as P-256 (we sign with P-256).
  Pki pki;
  EcKey k = EcKey::generate(EccCurve::kBrainpoolP256r1);
  Certificate at = make_ticket(k, week_from(kNowS - 60), pki.aa, pki.aa_key);
  ASSERT_EQ(at.tbs.verify_key.curve, EccCurve::kBrainpoolP256r1);
  Signer signer(std::move(at), std::move(k), pki.aa);
  Verifier verifier = pki.verifier();
  const ThreeDLocation where{481351000, 115830000, 4096};
  const Bytes denm = signer.sign_denm(kPayload, kNow, where);
  const auto d = decode_data(denm);
  ASSERT_TRUE(d);
  EXPECT_EQ(d->signed_data.signature.curve, EccCurve::kBrainpoolP256r1);
  EXPECT_EQ(verifier.verify(denm, kPsidDenm, kNow).result, VerifyResult::kOk);
  Bytes flipped = denm;
  flipped.back() ^= 0x01;  // the signature's s
  EXPECT_EQ(verifier.verify(flipped, kPsidDenm, kNow).result, VerifyResult::kSignatureInvalid);
  // A chain on brainpoolP256r1 below our P-256 root: AA and AT, then a CAM by digest.
  EcKey aa_key = EcKey::generate(EccCurve::kBrainpoolP256r1);
  const Certificate aa =
      make_authority(aa_key, "bp aa", week_from(kNowS - 3600), pki.root, pki.root_key);
  ASSERT_EQ(verifier.add_authority(aa, kNow), VerifyResult::kOk);
  EcKey k2 = EcKey::generate(EccCurve::kBrainpoolP256r1);
  Certificate at2 = make_ticket(k2, week_from(kNowS - 60), aa, aa_key);
  Signer bp(std::move(at2), std::move(k2), aa);
  EXPECT_EQ(verifier.verify(bp.sign_cam(kPayload, kNow), kPsidCam, kNow).result, VerifyResult::kOk);
  EXPECT_EQ(verifier.verify(bp.sign_cam(kPayload, kNow + 1000), kPsidCam, kNow + 1000).result,
            VerifyResult::kOk);
}

/// SHA-256 by OpenSSL itself, not by the code under test.
Octets32 openssl_sha256(std::span<const std::uint8_t> b) {
  Octets32 out{};
  SHA256(b.data(), b.size(), out.data());
  return out;
}

TEST(SignVerify, CertificateSignatureCoversToBeSignedAsReceived) {
  Pki pki;
  auto [at, key] = pki.ticket();
  // toBeSigned with its extension bit set and one extension addition the decoder skips
  // (1609.2-2022's `flags`, a BIT STRING of 8 bits, as an open type).
  Bytes tbs(at.tbs_octets().begin(), at.tbs_octets().end());
  ASSERT_FALSE(tbs.empty());
  ASSERT_EQ(tbs[0] & 0x80, 0);
  tbs[0] |= 0x80;
  {
    asn1::CoerWriter w(tbs);
    w.extension_bitmap(1, 1);
    w.open_type(Bytes{0x80});
  }
  // The certificate with toBeSigned @p sent, signed by the AA over @p signed_tbs: 1609.2 5.3.1
  // SHA-256(SHA-256(toBeSigned) || SHA-256(AA certificate)), the hashes taken with OpenSSL.
  const auto build = [&](const Bytes& signed_tbs, const Bytes& sent) {
    const Octets32 t = openssl_sha256(signed_tbs);
    const Octets32 a = openssl_sha256(pki.aa.encoding);
    Bytes both(t.begin(), t.end());
    both.insert(both.end(), a.begin(), a.end());
    Bytes cert(at.encoding.begin(),
               at.encoding.begin() + static_cast<std::ptrdiff_t>(at.tbs_offset));
    cert.insert(cert.end(), sent.begin(), sent.end());
    asn1::CoerWriter w(cert);
    coer::put(w, pki.aa_key.sign(openssl_sha256(both)));
    return cert;
  };
  const Bytes good = build(tbs, tbs);
  auto c = decode_certificate(good);
  ASSERT_TRUE(c) << asn1::to_string(c.error());
  EXPECT_EQ(c->tbs, at.tbs);  // the addition is skipped...
  EXPECT_EQ(Bytes(c->tbs_octets().begin(), c->tbs_octets().end()), tbs);  // ...but kept
  EXPECT_NE(encode(c->tbs), tbs);
  EXPECT_EQ(encode(*c), good);  // and sent on as it came

  Signer signer(*c, std::move(key), pki.aa);
  const Bytes cam = signer.sign_cam(kPayload, kNow);
  const auto where = std::search(cam.begin(), cam.end(), good.begin(), good.end());
  ASSERT_NE(where, cam.end());
  Verifier verifier = pki.verifier();
  auto v = verifier.verify(cam, kPsidCam, kNow);
  EXPECT_EQ(v.result, VerifyResult::kOk) << to_string(v.result);
  EXPECT_EQ(v.signer, hashed_id8(openssl_sha256(good)));

  // The same certificate with the skipped octet altered (0x80 -> 0x40): it still decodes to the
  // same fields, but the AA did not sign it.
  Bytes altered_tbs = tbs;
  altered_tbs.back() = 0x40;
  const Bytes bad = build(tbs, altered_tbs);
  auto cb = decode_certificate(bad);
  ASSERT_TRUE(cb) << asn1::to_string(cb.error());
  EXPECT_EQ(cb->tbs, c->tbs);
  Bytes forged = cam;
  std::copy(bad.begin(), bad.end(), forged.begin() + (where - cam.begin()));
  Verifier fresh = pki.verifier();
  EXPECT_EQ(fresh.verify(forged, kPsidCam, kNow).result, VerifyResult::kCertificateSignature);
  EXPECT_EQ(fresh.count(VerifyResult::kCertificateSignature), 1u);
}

/// The uncompressed form of the compressed P-256 point @p p, by OpenSSL.
EccP256CurvePoint openssl_uncompressed(const EccP256CurvePoint& p) {
  EC_GROUP* g = EC_GROUP_new_by_curve_name(NID_X9_62_prime256v1);
  EC_POINT* pt = EC_POINT_new(g);
  std::array<std::uint8_t, 33> in{};
  in[0] = p.form == EccP256CurvePoint::Form::kCompressedY1 ? 0x03 : 0x02;
  std::copy(p.x.begin(), p.x.end(), in.begin() + 1);
  std::array<std::uint8_t, 65> out{};
  const bool ok = EC_POINT_oct2point(g, pt, in.data(), in.size(), nullptr) == 1 &&
                  EC_POINT_point2oct(g, pt, POINT_CONVERSION_UNCOMPRESSED, out.data(), out.size(),
                                     nullptr) == out.size();
  EC_POINT_free(pt);
  EC_GROUP_free(g);
  EXPECT_TRUE(ok);
  EccP256CurvePoint u{EccP256CurvePoint::Form::kUncompressed, {}, {}};
  std::copy(out.begin() + 1, out.begin() + 33, u.x.begin());
  std::copy(out.begin() + 33, out.end(), u.y.begin());
  return u;
}

TEST(SignVerify, UncompressedKeyIsCanonicalisedForTheIssuerSignature) {
  Pki pki;
  auto [at, key] = pki.ticket();
  Signer signer(at, std::move(key), pki.aa);
  const Bytes cam = signer.sign_cam(kPayload, kNow);
  // The AA signed toBeSigned with the key compressed, its canonical form (1609.2 6.4.3); the
  // same certificate travels with the key uncompressed (the signature unchanged).
  Certificate loose = at;
  loose.encoding.clear();
  loose.tbs_offset = loose.tbs_length = loose.key_offset = loose.key_length = 0;
  loose.tbs.verify_key.point = openssl_uncompressed(at.tbs.verify_key.point);
  auto c = decode_certificate(encode(loose));
  ASSERT_TRUE(c) << asn1::to_string(c.error());
  EXPECT_EQ(c->key_length, 65u);
  EXPECT_EQ(canonical_tbs(*c), Bytes(at.tbs_octets().begin(), at.tbs_octets().end()));
  EXPECT_EQ(canonical_encoding(*c), at.encoding);
  EXPECT_EQ(certificate_id(*c), certificate_id(at));
  // A CAM that carries it in place of the compressed one verifies.
  const auto where = std::search(cam.begin(), cam.end(), at.encoding.begin(), at.encoding.end());
  ASSERT_NE(where, cam.end());
  Bytes sent(cam.begin(), where);
  sent.insert(sent.end(), c->encoding.begin(), c->encoding.end());
  sent.insert(sent.end(), where + static_cast<std::ptrdiff_t>(at.encoding.size()), cam.end());
  Verifier verifier = pki.verifier();
  const auto v = verifier.verify(sent, kPsidCam, kNow);
  EXPECT_EQ(v.result, VerifyResult::kOk) << to_string(v.result);
  // And one whose uncompressed key is another point fails the issuer's signature.
  Certificate other = loose;
  other.tbs.verify_key.point.y[31] ^= 0x01;  // off the curve and off the signed octets
  auto o = decode_certificate(encode(other));
  ASSERT_TRUE(o);
  EXPECT_NE(canonical_tbs(*o), canonical_tbs(*c));
}

TEST(SignVerify, GenerationTimeWindowOnTaiOrUtc) {
  Pki pki;
  Signer signer = pki.signer();
  Verifier verifier = pki.verifier();
  auto at = [&](std::int64_t offset_us) {
    const Time64 gen = static_cast<Time64>(static_cast<std::int64_t>(kNow) + offset_us);
    return verifier.verify(signer.sign(kPsidCam, kPayload, gen, std::nullopt, true), kPsidCam,
                           kNow);
  };
  EXPECT_EQ(at(0).time_base, TimeBase::kTai);
  EXPECT_EQ(at(-1'999'000).result, VerifyResult::kOk);
  EXPECT_EQ(at(39'000).result, VerifyResult::kOk);
  EXPECT_EQ(at(-2'100'000).result, VerifyResult::kGenerationTimeOutOfWindow);
  EXPECT_EQ(at(50'000).result, VerifyResult::kGenerationTimeOutOfWindow);
  // Vanetza stamps UTC without leap seconds: 5 s behind TAI, and still within the window.
  auto utc = at(-5'000'000 - 300'000);
  EXPECT_EQ(utc.result, VerifyResult::kOk);
  EXPECT_EQ(utc.time_base, TimeBase::kUtcNoLeapSeconds);
  EXPECT_EQ(at(-7'100'000).result, VerifyResult::kGenerationTimeOutOfWindow);
  EXPECT_EQ(at(-3'500'000).result, VerifyResult::kGenerationTimeOutOfWindow);
  // Without the UTC base only TAI counts.
  VerifierConfig tai_cfg;
  tai_cfg.accept_utc_time_base = false;
  Verifier tai_only = pki.verifier(tai_cfg);
  EXPECT_EQ(tai_only
                .verify(signer.sign(kPsidCam, kPayload, kNow - 5'300'000, std::nullopt, true),
                        kPsidCam, kNow)
                .result,
            VerifyResult::kGenerationTimeOutOfWindow);
}

TEST(SignVerify, TimeWindowIsSetPerItsAid) {
  Pki pki;
  Signer signer = pki.signer();
  VerifierConfig cfg;
  cfg.time_policy[kPsidDenm] = TimePolicy{10s, 40ms, false};
  Verifier verifier = pki.verifier(cfg);
  const ThreeDLocation here{488000000, 91000000, 4096};
  auto at = [&](Psid psid, std::chrono::microseconds offset) {
    const Time64 gen = static_cast<Time64>(static_cast<std::int64_t>(kNow) + offset.count());
    return verifier
        .verify(signer.sign(psid, kPayload, gen,
                            psid == kPsidDenm ? std::optional(here) : std::nullopt, true),
                psid, kNow)
        .result;
  };
  // DENM: -10 s .. +40 ms; CAM and GN-MGMT keep the default -2 s .. +40 ms.
  EXPECT_EQ(at(kPsidDenm, -3s), VerifyResult::kOk);
  EXPECT_EQ(at(kPsidDenm, -9'900ms), VerifyResult::kOk);
  EXPECT_EQ(at(kPsidCam, -3s), VerifyResult::kGenerationTimeOutOfWindow);
  EXPECT_EQ(at(kPsidGnMgmt, -3s), VerifyResult::kGenerationTimeOutOfWindow);
  EXPECT_EQ(at(kPsidDenm, 50ms), VerifyResult::kGenerationTimeOutOfWindow);
  // -11 s is in the window on the UTC base (5 s behind TAI: -6 s there); -16 s on neither.
  EXPECT_EQ(at(kPsidDenm, -11s), VerifyResult::kOk);
  EXPECT_EQ(at(kPsidDenm, -16s), VerifyResult::kGenerationTimeOutOfWindow);
  EXPECT_EQ(cfg.policy(kPsidDenm).past, 10s);
  EXPECT_EQ(cfg.policy(kPsidCam), default_time_policy(kPsidCam));
  EXPECT_EQ(cfg.policy(kPsidCam).past, 2s);
  EXPECT_EQ(cfg.policy(kPsidCam).future, 40ms);
}

TEST(SignVerify, TimeWindowOptionIsParsedOrRefusedByName) {
  auto w = parse_time_window("37=10000:40");
  ASSERT_TRUE(w) << w.error();
  EXPECT_EQ(w->first, kPsidDenm);
  EXPECT_EQ(w->second.past, 10s);
  EXPECT_EQ(w->second.future, 40ms);
  EXPECT_FALSE(w->second.replay_detection);  // DENM's default kept
  auto cam = parse_time_window("36=1500");
  ASSERT_TRUE(cam) << cam.error();
  EXPECT_EQ(cam->second.past, 1500ms);
  EXPECT_EQ(cam->second.future, default_time_policy(kPsidCam).future);
  EXPECT_TRUE(cam->second.replay_detection);
  for (const char* bad : {"36", "cam=2000", "36=", "36=-1", "36=600001", "36=2000:60001",
                          "36=2000:soon", "4294967296=10"}) {
    auto r = parse_time_window(bad);
    ASSERT_FALSE(r) << bad;
    EXPECT_NE(r.error().find(std::string("\"") + bad + "\""), std::string::npos) << r.error();
  }
  EXPECT_NE(parse_time_window("36=2000:soon").error().find("FUTURE_MS \"soon\""),
            std::string::npos);
  EXPECT_NE(parse_time_window("cam=2000").error().find("PSID \"cam\""), std::string::npos);
}

TEST(SignVerify, ReplayOfOneSignerAndGenerationTimeIsDropped) {
  Pki pki;
  Signer signer = pki.signer();
  Verifier verifier = pki.verifier();
  const Bytes cam = signer.sign_cam(kPayload, kNow);
  ASSERT_EQ(verifier.verify(cam, kPsidCam, kNow).result, VerifyResult::kOk);
  auto again = verifier.verify(cam, kPsidCam, kNow + 10'000);
  EXPECT_EQ(again.result, VerifyResult::kReplay);
  EXPECT_EQ(to_string(again.result), "replay");
  // The same instant signed again, with the digest this time: other octets, the same packet.
  EXPECT_EQ(verifier
                .verify(signer.sign(kPsidCam, kPayload, kNow, std::nullopt, false), kPsidCam,
                        kNow + 20'000)
                .result,
            VerifyResult::kReplay);
  // Another generation time of that signer, or the same time of another signer, is new.
  EXPECT_EQ(verifier.verify(signer.sign_cam(kPayload, kNow + 1), kPsidCam, kNow + 20'000).result,
            VerifyResult::kOk);
  Signer other = pki.signer();
  EXPECT_EQ(verifier.verify(other.sign_cam(kPayload, kNow), kPsidCam, kNow + 20'000).result,
            VerifyResult::kOk);
  // So is a beacon (GN-MGMT) of the first signer in the CAM's microsecond.
  EXPECT_EQ(verifier.verify(signer.sign_other(kPsidGnMgmt, kPayload, kNow), kNow + 20'000).result,
            VerifyResult::kOk);
  EXPECT_EQ(verifier.count(VerifyResult::kReplay), 2u);
  EXPECT_EQ(verifier.count(VerifyResult::kOk), 4u);
  EXPECT_EQ(verifier.replay_entries(), 4u);
  // Only what verified is remembered: a forgery of a new instant does not block the real one.
  const Bytes real = signer.sign_cam(kPayload, kNow + 2);
  Bytes forged = real;
  forged.back() ^= 0x01;  // the signature's s
  EXPECT_EQ(verifier.verify(forged, kPsidCam, kNow + 20'000).result,
            VerifyResult::kSignatureInvalid);
  EXPECT_EQ(verifier.verify(real, kPsidCam, kNow + 20'000).result, VerifyResult::kOk);
  EXPECT_EQ(verifier.replay_entries(), 5u);
}

TEST(SignVerify, ReplayTableForgetsWhatLeftTheWindowAndIsCapped) {
  Pki pki;
  Signer signer = pki.signer();
  VerifierConfig cfg;
  cfg.replay_capacity = 3;
  Verifier verifier = pki.verifier(cfg);
  std::vector<Bytes> sent;
  for (int i = 0; i < 3; ++i) {
    sent.push_back(signer.sign_cam(kPayload, kNow + i * 100'000));
    ASSERT_EQ(verifier.verify(sent.back(), kPsidCam, kNow + i * 100'000).result, VerifyResult::kOk);
  }
  EXPECT_EQ(verifier.replay_entries(), 3u);
  // Full: a fourth pushes out the one whose window ends first (the oldest), whose replay then
  // passes; the others are still caught.
  sent.push_back(signer.sign_cam(kPayload, kNow + 300'000));
  ASSERT_EQ(verifier.verify(sent.back(), kPsidCam, kNow + 300'000).result, VerifyResult::kOk);
  EXPECT_EQ(verifier.replay_entries(), 3u);
  EXPECT_EQ(verifier.verify(sent[3], kPsidCam, kNow + 310'000).result, VerifyResult::kReplay);
  EXPECT_EQ(verifier.verify(sent[2], kPsidCam, kNow + 310'000).result, VerifyResult::kReplay);
  // 2 s after the last one every entry has left its window and is forgotten; the old packets
  // are out of the window themselves.
  const Time64 later = kNow + 300'000 + 2'000'001;
  EXPECT_EQ(verifier.verify(signer.sign_cam(kPayload, later), kPsidCam, later).result,
            VerifyResult::kOk);
  EXPECT_EQ(verifier.replay_entries(), 1u);
  EXPECT_EQ(verifier.verify(sent[3], kPsidCam, later).result,
            VerifyResult::kGenerationTimeOutOfWindow);
}

TEST(SignVerify, DenmRepeatsAreLeftToGeoNetworkingUnlessSetOtherwise) {
  Pki pki;
  Signer signer = pki.signer();
  const ThreeDLocation here{488000000, 91000000, 4096};
  const Bytes denm = signer.sign_denm(kPayload, kNow, here);
  // By default a DENM's forwarded copies (the same octets) all verify: GN drops duplicates.
  Verifier by_default = pki.verifier();
  EXPECT_EQ(by_default.verify(denm, kPsidDenm, kNow).result, VerifyResult::kOk);
  EXPECT_EQ(by_default.verify(denm, kPsidDenm, kNow + 100'000).result, VerifyResult::kOk);
  EXPECT_EQ(by_default.replay_entries(), 0u);
  VerifierConfig cfg;
  cfg.time_policy[kPsidDenm] = TimePolicy{2s, 40ms, true};
  Verifier strict = pki.verifier(cfg);
  EXPECT_EQ(strict.verify(denm, kPsidDenm, kNow).result, VerifyResult::kOk);
  EXPECT_EQ(strict.verify(denm, kPsidDenm, kNow + 100'000).result, VerifyResult::kReplay);
}

TEST(SignVerify, SocktapSelfSignedCamsAreRejectedWithTheirReason) {
  Pki pki;
  Verifier verifier = pki.verifier();
  const auto frames = test::socktap_secured_packets();
  ASSERT_FALSE(frames.empty());
  for (const auto& f : frames) {
    const std::span<const std::uint8_t> secured(f);
    auto d = decode_data(secured);
    ASSERT_TRUE(d);
    // Verified at the instant it was stamped: socktap's UTC base is 5 s behind ours.
    const Time64 now = *d->signed_data.tbs.header.generation_time + 5'000'000 + 1'000;
    auto v = verifier.verify(secured, kPsidCam, now);
    EXPECT_EQ(v.result, VerifyResult::kSelfSigned);
    EXPECT_EQ(v.time_base, TimeBase::kUtcNoLeapSeconds);
    EXPECT_EQ(v.payload().size(), d->signed_data.tbs.payload.data->size());
  }
  EXPECT_EQ(verifier.count(VerifyResult::kSelfSigned), frames.size());
}

TEST(SignVerify, MalformedInputIsCountedNotThrown) {
  Pki pki;
  Verifier verifier = pki.verifier();
  const Bytes junk{0x03, 0x81, 0x00, 0x40};
  auto v = verifier.verify(junk, kPsidCam, kNow);
  EXPECT_EQ(v.result, VerifyResult::kMalformed);
  EXPECT_EQ(v.decode_error.code, asn1::Error::kTruncated);
  EXPECT_EQ(verifier.count(VerifyResult::kMalformed), 1u);
  EXPECT_EQ(to_string(VerifyResult::kGenerationTimeOutOfWindow), "generation_time_out_of_window");
}

}  // namespace
}  // namespace tb::its::security
