#include "its-station/security/ieee1609dot2.hpp"

#include <gtest/gtest.h>

#include <string>

#include "its-station/security/tests/socktap_capture.hpp"

namespace tb::its::security {
namespace {

Bytes hex(const std::string& s) {
  Bytes out;
  std::string digits;
  for (char c : s)
    if (std::isxdigit(static_cast<unsigned char>(c)))
      digits += c;
  for (std::size_t i = 0; i + 1 < digits.size(); i += 2)
    out.push_back(static_cast<std::uint8_t>(std::stoi(digits.substr(i, 2), nullptr, 16)));
  return out;
}

Octets32 filled(std::uint8_t v) {
  Octets32 o;
  o.fill(v);
  return o;
}

/// An authorization ticket as TS 103 097 7.2.1 has it: issuer digest, id none, CAM and DENM
/// permissions, a compressed P-256 key, an x-only r.
Certificate sample_at() {
  Certificate c;
  c.issuer.kind = IssuerIdentifier::Kind::kSha256AndDigest;
  c.issuer.digest = {1, 2, 3, 4, 5, 6, 7, 8};
  c.tbs.id.kind = CertificateId::Kind::kNone;
  c.tbs.validity = {600000000, DurationUnit::kHours, 168};
  c.tbs.app_permissions = std::vector<PsidSsp>{
      PsidSsp{kPsidCam, Ssp{Ssp::Kind::kBitmap, {0x01, 0xff, 0xfc}}}, PsidSsp{kPsidDenm, {}}};
  c.tbs.verify_key.curve = EccCurve::kNistP256;
  c.tbs.verify_key.point = {EccP256CurvePoint::Form::kCompressedY0, filled(0x11), {}};
  c.signature = Signature{
      EccCurve::kNistP256, {EccP256CurvePoint::Form::kXOnly, filled(0x22), {}}, filled(0x33)};
  return c;
}

// Worked out by hand from the ASN.1 of 1609.2 and X.696.
const std::string kSampleAtHex =
    "80"                        // CertificateBase preamble: signature present
    "03 00"                     // version 3, type explicit
    "80 0102030405060708"       // issuer sha256AndDigest
    "10"                        // ToBeSignedCertificate: no extension, only appPermissions
    "83"                        // id none
    "000000 0000"               // cracaId, crlSeries
    "23c34600 84 00a8"          // validityPeriod: start 600000000, hours 168
    "01 02"                     // appPermissions: 2 entries
    "80 01 24 81 04 03 01fffc"  // psid 36, ssp bitmapSsp (extension alternative: open type)
    "00 01 25"                  // psid 37, no ssp
    "80 80 82"                  // verificationKey ecdsaNistP256 compressed-y-0
    "1111111111111111111111111111111111111111111111111111111111111111"
    "80 80"  // signature ecdsaNistP256Signature, rSig x-only
    "2222222222222222222222222222222222222222222222222222222222222222"
    "3333333333333333333333333333333333333333333333333333333333333333";

TEST(Certificate, EncodesToTheValueWorkedOutByHand) {
  EXPECT_EQ(encode(sample_at()), hex(kSampleAtHex));
}

TEST(Certificate, DecodesTheHandWorkedValueAndKeepsItsOctets) {
  const Bytes b = hex(kSampleAtHex);
  auto c = decode_certificate(b);
  ASSERT_TRUE(c) << asn1::to_string(c.error());
  EXPECT_EQ(*c, sample_at());
  EXPECT_EQ(c->encoding, b);
}

TEST(Certificate, RoundTripsEveryOptionalComponent) {
  Certificate c = sample_at();
  c.issuer = {IssuerIdentifier::Kind::kSelf, {}, HashAlgorithm::kSha256};
  c.tbs.id = {CertificateId::Kind::kName, {'r', 'o', 'o', 't'}};
  c.tbs.craca_id = {0xa, 0xb, 0xc};
  c.tbs.crl_series = 7;
  // identifiedRegion { countryOnly 276, countryAndRegions { 40, {1, 2} } }
  c.tbs.region = hex("83 0102 80 0114 81 0028 0102 0102");
  c.tbs.assurance_level = 0xe0;
  PsidGroupPermissions all;
  all.all_psids = true;
  all.min_chain_length = 2;
  all.chain_length_range = -1;
  all.ee_type = 0xc0;
  PsidGroupPermissions some;
  some.psids = {PsidSspRange{kPsidCam, SspRange{SspRange::Kind::kBitmap, {}, {1, 0xff}, {0, 0}}},
                PsidSspRange{kPsidDenm, SspRange{SspRange::Kind::kOpaque, {{1}, {2, 3}}, {}, {}}},
                PsidSspRange{0x8007, SspRange{}}, PsidSspRange{1, std::nullopt}};
  c.tbs.cert_issue_permissions = std::vector{all, some};
  c.tbs.cert_request_permissions = std::vector{some};
  c.tbs.can_request_rollover = true;
  c.tbs.encryption_key = hex("00 80 83");
  c.tbs.encryption_key->insert(c.tbs.encryption_key->end(), 32, 0x44);
  c.tbs.verify_key = {EccCurve::kBrainpoolP256r1,
                      {EccP256CurvePoint::Form::kUncompressed, filled(5), filled(6)}};
  c.signature.reset();
  const Bytes b = encode(c);
  auto back = decode_certificate(b);
  ASSERT_TRUE(back) << asn1::to_string(back.error());
  EXPECT_EQ(*back, c);
  EXPECT_EQ(encode(*back), b);
}

TEST(Certificate, RejectsWhatTs103097DoesNotUseNamingTheField) {
  Bytes b = hex(kSampleAtHex);
  b[2] = 0x01;  // type implicit
  auto c = decode_certificate(b);
  ASSERT_FALSE(c);
  EXPECT_EQ(c.error().code, asn1::Error::kUnsupported);
  b = hex(kSampleAtHex);
  b[1] = 0x02;  // version 2
  c = decode_certificate(b);
  ASSERT_FALSE(c);
  EXPECT_EQ(c.error().code, asn1::Error::kUnsupportedVersion);
  b = hex(kSampleAtHex);
  b.pop_back();
  c = decode_certificate(b);
  ASSERT_FALSE(c);
  EXPECT_EQ(c.error().code, asn1::Error::kTruncated);
  EXPECT_STREQ(c.error().field, "sSig");
}

Ieee1609Dot2Data signed_cam(Bytes payload) {
  Ieee1609Dot2Data d;
  d.content = Ieee1609Dot2Data::Content::kSignedData;
  auto& s = d.signed_data;
  s.tbs.payload.data = std::move(payload);
  s.tbs.header.psid = kPsidCam;
  s.tbs.header.generation_time = 722539108207911ull;
  s.signer.kind = SignerIdentifier::Kind::kDigest;
  s.signer.digest = {0xa1, 0xa2, 0xa3, 0xa4, 0xa5, 0xa6, 0xa7, 0xa8};
  s.signature = {
      EccCurve::kNistP256, {EccP256CurvePoint::Form::kXOnly, filled(0x22), {}}, filled(0x33)};
  return d;
}

const std::string kSignedCamHex =
    "03 81 00"             // protocolVersion 3, signedData, hashId sha256
    "40 03 80 03 aabbcc"   // payload: data { version 3, unsecuredData, 3 octets }
    "40 01 24"             // headerInfo: generationTime only; psid 36
    "00 0291253ee18d27"    // generationTime 722539108207911 µs
    "80 a1a2a3a4a5a6a7a8"  // signer digest
    "80 80"                // ecdsaNistP256Signature, rSig x-only
    "2222222222222222222222222222222222222222222222222222222222222222"
    "3333333333333333333333333333333333333333333333333333333333333333";

TEST(SignedData, DigestSignedCamEncodesToTheValueWorkedOutByHand) {
  EXPECT_EQ(encode(signed_cam({0xaa, 0xbb, 0xcc})), hex(kSignedCamHex));
  auto d = decode_data(hex(kSignedCamHex));
  ASSERT_TRUE(d) << asn1::to_string(d.error());
  EXPECT_EQ(*d, signed_cam({0xaa, 0xbb, 0xcc}));
  // The tbsData octets are kept for the signature: from the payload preamble to the signer.
  EXPECT_EQ(d->signed_data.tbs_encoding, hex("40 03 80 03 aabbcc 40 01 24 00 0291253ee18d27"));
  EXPECT_EQ(d->signed_data.tbs_encoding, encode(d->signed_data.tbs));
}

TEST(SignedData, DenmWithCertificateLocationAndPeerRequestsRoundTrips) {
  auto d = signed_cam(Bytes(300, 0x5a));  // long-form payload length
  auto& h = d.signed_data.tbs.header;
  h.psid = kPsidDenm;
  h.generation_location = ThreeDLocation{481351000, -115830000, 4096 + 5200};
  h.expiry_time = 1;
  h.p2pcd_learning_request = HashedId3{1, 2, 3};
  h.missing_crl_identifier = MissingCrlIdentifier{{4, 5, 6}, 7};
  h.inline_p2pcd_request = std::vector<HashedId3>{{9, 9, 9}, {8, 8, 8}};
  h.requested_certificate = sample_at();
  d.signed_data.signer.kind = SignerIdentifier::Kind::kCertificate;
  d.signed_data.signer.certificates = {sample_at()};
  d.signed_data.signature.curve = EccCurve::kBrainpoolP256r1;
  d.signed_data.signature.r.form = EccP256CurvePoint::Form::kCompressedY1;
  const Bytes b = encode(d);
  auto back = decode_data(b);
  ASSERT_TRUE(back) << asn1::to_string(back.error());
  EXPECT_EQ(*back, d);
  EXPECT_EQ(encode(*back), b);
  EXPECT_EQ(back->signed_data.signer.certificates.at(0).encoding, hex(kSampleAtHex));
}

TEST(SignedData, SkipsUnknownHeaderExtensionsButKeepsTheirOctetsInTheSignedPart) {
  // HeaderInfo with the extension bit, a 4-bit bitmap (two of 1609.2-2022's later additions
  // present: pduFunctionalType = 1 and an unknown one), each an open type.
  const Bytes b =
      hex("03 81 00 40 03 80 01 ff"
          "c0 01 24 0000000000000001"  // extension bit, generationTime
          "02 04 30 01 01 02 abcd"     // bitmap 0011: two unknown additions, open types
          "82 80 80" +
          std::string(128, '0'));
  auto d = decode_data(b);
  ASSERT_TRUE(d) << asn1::to_string(d.error());
  EXPECT_EQ(d->signed_data.tbs.header.generation_time, 1u);
  EXPECT_FALSE(d->signed_data.tbs.header.inline_p2pcd_request);
  EXPECT_EQ(d->signed_data.tbs_encoding.size(), 5u + 12u + 7u);
}

TEST(SignedData, RejectsBadInputNamingTheField) {
  Bytes b = hex(kSignedCamHex);
  b[0] = 2;
  auto d = decode_data(b);
  ASSERT_FALSE(d);
  EXPECT_EQ(d.error().code, asn1::Error::kUnsupportedVersion);
  b = hex(kSignedCamHex);
  b.push_back(0);
  d = decode_data(b);
  ASSERT_FALSE(d);
  EXPECT_EQ(d.error().code, asn1::Error::kTrailingData);
  b = hex(kSignedCamHex);
  b[1] = 0x82;  // encryptedData
  d = decode_data(b);
  ASSERT_FALSE(d);
  EXPECT_STREQ(d.error().field, "Ieee1609Dot2Content");
  b = hex(kSignedCamHex);
  b[3] = 0x00;  // empty SignedDataPayload
  d = decode_data(b);
  ASSERT_FALSE(d);
  EXPECT_STREQ(d.error().field, "SignedDataPayload (empty)");
  b = hex(kSignedCamHex);
  b[6] = 0x7f;  // unsecuredData longer than the packet
  d = decode_data(b);
  ASSERT_FALSE(d);
  EXPECT_EQ(d.error().code, asn1::Error::kTruncated);
  EXPECT_STREQ(d.error().field, "payload.data.unsecuredData");
  // Every prefix of a valid packet is an error, never a crash or a read past the end.
  b = hex(kSignedCamHex);
  for (std::size_t n = 0; n < b.size(); ++n)
    EXPECT_FALSE(decode_data(std::span(b).first(n))) << n;
}

// Vanetza's socktap with its default security (`dummy`): TS 103 097 v1.3.1 signedData over
// common header + SHB + BTP-B + CAM, signer self, an all-zero signature.
TEST(SocktapCapture, EveryFrameDecodesAndReencodesToTheSameOctets) {
  const auto frames = test::socktap_secured_packets();
  ASSERT_EQ(frames.size(), 108u);
  std::optional<Time64> previous;
  for (const auto& f : frames) {
    const std::span<const std::uint8_t> secured(f);
    auto d = decode_data(secured);
    ASSERT_TRUE(d) << asn1::to_string(d.error());
    ASSERT_EQ(d->content, Ieee1609Dot2Data::Content::kSignedData);
    const auto& s = d->signed_data;
    EXPECT_EQ(s.hash_id, HashAlgorithm::kSha256);
    EXPECT_EQ(s.tbs.header.psid, kPsidCam);
    ASSERT_TRUE(s.tbs.header.generation_time);
    EXPECT_FALSE(s.tbs.header.generation_location);
    EXPECT_EQ(s.signer.kind, SignerIdentifier::Kind::kSelf);
    EXPECT_EQ(s.signature.curve, EccCurve::kNistP256);
    EXPECT_EQ(s.signature.r.form, EccP256CurvePoint::Form::kXOnly);
    EXPECT_EQ(s.signature.s, Octets32{});
    ASSERT_TRUE(s.tbs.payload.data);
    // Common header: next header BTP-B (2) in the high nibble, header type SHB (0x50).
    const Bytes& inner = *s.tbs.payload.data;
    ASSERT_GE(inner.size(), 8u);
    EXPECT_EQ(inner[0] >> 4, 2);
    EXPECT_EQ(inner[1], 0x50);
    if (previous) {
      EXPECT_GT(*s.tbs.header.generation_time, *previous);
    }
    previous = s.tbs.header.generation_time;
    EXPECT_EQ(encode(*d), Bytes(secured.begin(), secured.end()));
  }
  // First frame, as tshark 4.0 shows it: generationTime 722539108207911 (2026-11-23
  // 17:18:23.207911 counted without leap seconds, 5 s behind the capture's 17:18:28).
  auto first = decode_data(frames[0]);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->signed_data.tbs.header.generation_time, 722539108207911ull);
  EXPECT_EQ(first->signed_data.tbs.payload.data->size(), 81u);
}

}  // namespace
}  // namespace tb::its::security
