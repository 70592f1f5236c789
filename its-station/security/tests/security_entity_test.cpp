#include "its-station/security/security_entity.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/trace/tracer.hpp"

#include "its-station/security/pki.hpp"
#include "its-station/security/tests/socktap_capture.hpp"
#include "its-station/security/time.hpp"

namespace tb::its::security {
namespace {

const Time64 kNow = to_time64(clock::WallTime{std::chrono::seconds(1795454308)});
const Time32 kNowS = static_cast<Time32>(kNow / 1000000);
const Bytes kPayload{0x20, 0x50, 0x00, 0x80, 0x00, 0x2d, 0x01, 0x00};

struct Fixture {
  EcKey root_key = EcKey::generate(EccCurve::kNistP256);
  EcKey aa_key = EcKey::generate(EccCurve::kNistP256);
  Certificate root = make_root(root_key, "root", {kNowS - 3600, DurationUnit::kHours, 100});
  Certificate aa =
      make_authority(aa_key, "aa", {kNowS - 3600, DurationUnit::kHours, 100}, root, root_key);

  SecurityEntity station(SecurityMode mode) {
    EcKey k = EcKey::generate(EccCurve::kNistP256);
    Certificate at = make_ticket(k, {kNowS - 60, DurationUnit::kHours, 10}, aa, aa_key);
    Verifier v({root});
    EXPECT_EQ(v.add_authority(aa, kNow), VerifyResult::kOk);
    return SecurityEntity(mode, Signer(std::move(at), std::move(k), aa), std::move(v));
  }
};

TEST(SecurityMode, ParsesTheScenarioNames) {
  EXPECT_EQ(parse_security_mode("none"), SecurityMode::kNone);
  EXPECT_EQ(parse_security_mode("signed"), SecurityMode::kSigned);
  EXPECT_EQ(parse_security_mode("signed-permissive"), SecurityMode::kSignedPermissive);
  EXPECT_FALSE(parse_security_mode("Signed"));
}

TEST(SecurityEntity, SignedStationsExchangeCams) {
  Fixture f;
  auto a = f.station(SecurityMode::kSigned);
  auto b = f.station(SecurityMode::kSigned);
  auto out = b.decapsulate(a.encapsulate(kPsidCam, kPayload, kNow), kNow);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0].pass_up);
  EXPECT_EQ(out[0].reason, VerifyResult::kOk);
  EXPECT_EQ(out[0].psid, kPsidCam);
  EXPECT_EQ(out[0].payload, kPayload);
  // b heard a new station: its next CAM carries its AT; the one after is a digest until a
  // second has passed.
  auto first = decode_data(b.encapsulate(kPsidCam, kPayload, kNow));
  auto second = decode_data(b.encapsulate(kPsidCam, kPayload, kNow + 100'000));
  ASSERT_TRUE(first && second);
  EXPECT_EQ(first->signed_data.signer.kind, SignerIdentifier::Kind::kCertificate);
  EXPECT_EQ(second->signed_data.signer.kind, SignerIdentifier::Kind::kDigest);
}

// A pooled station writes no its.verify for the CAMs it hears (300 in range: 240 000 a second,
// issue 33); those of DENMs, rare, stay.
TEST(SecurityEntity, CamVerificationsAreTracedUnlessTurnedOff) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("security-verify-trace-" + std::to_string(::getpid()) + ".jsonl");
  std::filesystem::remove(path);
  // The entity writes to the process's tracer, as in its-station; it stays on for this test
  // binary's later tests (their records go to the file removed below).
  trace::configure(path.string(), "its-station");
  Fixture f;
  auto a = f.station(SecurityMode::kSigned);
  auto full = f.station(SecurityMode::kSigned);
  auto pooled = f.station(SecurityMode::kSigned);
  full.set_trace_station(1001);
  pooled.set_trace_station(2002);
  pooled.set_trace_cam_receptions(false);
  const Bytes cam = a.encapsulate(kPsidCam, kPayload, kNow);
  const Bytes denm = a.encapsulate(kPsidDenm, kPayload, kNow, ThreeDLocation{481'500'000, 0, 0});
  for (auto* s : {&full, &pooled}) {
    ASSERT_EQ(s->decapsulate(cam, kNow).size(), 1u);
    ASSERT_EQ(s->decapsulate(denm, kNow).size(), 1u);
  }
  trace::global().flush();
  std::vector<std::string> verified;  // "station/psid"
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (line.find("\"ev\":\"its.verify\"") == std::string::npos)
      continue;
    auto field = [&](const std::string& name) {
      const auto at = line.find("\"" + name + "\":") + name.size() + 3;
      return line.substr(at, line.find_first_of(",}", at) - at);
    };
    verified.push_back(field("station") + "/" + field("psid"));
  }
  std::filesystem::remove(path);
  EXPECT_EQ(verified, (std::vector<std::string>{"1001/36", "1001/37", "2002/37"}));
}

TEST(SecurityEntity, UnknownDigestIsHeldRequestedAndReleasedByTheCertificate) {
  Fixture f;
  auto a = f.station(SecurityMode::kSigned);
  auto b = f.station(SecurityMode::kSigned);
  b.encapsulate(kPsidCam, kPayload, kNow);  // b's first CAM (its AT) goes out
  a.encapsulate(kPsidCam, kPayload, kNow);  // lost
  const Bytes digest = a.encapsulate(kPsidCam, kPayload, kNow + 100'000);
  auto out = b.decapsulate(digest, kNow + 100'000);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(b.held(), 1u);
  // b's next CAM asks for a's AT and carries b's own (a new station was heard).
  auto ask = b.encapsulate(kPsidCam, kPayload, kNow + 150'000);
  auto ask_d = decode_data(ask);
  ASSERT_TRUE(ask_d);
  ASSERT_TRUE(ask_d->signed_data.tbs.header.inline_p2pcd_request);
  EXPECT_EQ(ask_d->signed_data.tbs.header.inline_p2pcd_request->front(),
            hashed_id3(a.signer().id()));
  EXPECT_EQ(ask_d->signed_data.signer.kind, SignerIdentifier::Kind::kCertificate);
  // a learns b and is asked for its AT: its next CAM carries it; b releases the held one.
  auto at_a = a.decapsulate(ask, kNow + 150'000);
  ASSERT_EQ(at_a.size(), 1u);
  EXPECT_TRUE(at_a[0].pass_up);
  auto released = b.decapsulate(a.encapsulate(kPsidCam, kPayload, kNow + 200'000), kNow + 200'000);
  ASSERT_EQ(released.size(), 2u);
  EXPECT_TRUE(released[0].pass_up);
  EXPECT_TRUE(released[1].pass_up);
  EXPECT_EQ(released[1].reason, VerifyResult::kOk);
  EXPECT_EQ(b.held(), 0u);
}

TEST(SecurityEntity, HeldPacketsTimeOutAsUnknownSigner) {
  Fixture f;
  auto a = f.station(SecurityMode::kSigned);
  auto b = f.station(SecurityMode::kSigned);
  a.encapsulate(kPsidCam, kPayload, kNow);
  b.decapsulate(a.encapsulate(kPsidCam, kPayload, kNow + 100'000), kNow + 100'000);
  EXPECT_TRUE(b.expire(kNow + 100'000 + SecurityEntity::kHoldUs - 1).empty());
  auto out = b.expire(kNow + 100'000 + SecurityEntity::kHoldUs);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].pass_up);
  EXPECT_EQ(out[0].reason, VerifyResult::kUnknownSigner);
}

TEST(SecurityEntity, SocktapSelfSignerDroppedWhenSignedPassedUpWhenPermissive) {
  Fixture f;
  auto strict = f.station(SecurityMode::kSigned);
  auto permissive = f.station(SecurityMode::kSignedPermissive);
  const auto frames = test::socktap_secured_packets();
  ASSERT_FALSE(frames.empty());
  const std::span<const std::uint8_t> secured(frames[0]);
  const Time64 now = 722539108207911ull + 5'000'000;  // on our TAI base
  auto s = strict.decapsulate(secured, now);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_FALSE(s[0].pass_up);
  EXPECT_EQ(s[0].reason, VerifyResult::kSelfSigned);
  auto p = permissive.decapsulate(secured, now);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_TRUE(p[0].pass_up);
  EXPECT_EQ(p[0].reason, VerifyResult::kSelfSigned);
  EXPECT_EQ(p[0].psid, kPsidCam);
  EXPECT_EQ(p[0].payload.size(), 81u);
  EXPECT_EQ(p[0].time_base, TimeBase::kUtcNoLeapSeconds);
  EXPECT_EQ(permissive.passed_unverified(), 1u);
  EXPECT_EQ(strict.verifier().count(VerifyResult::kSelfSigned), 1u);
}

TEST(SecurityEntity, ForeignRootStationIsIgnoredAndNamedUntrustedRoot) {
  Fixture ours;
  Fixture foreign;
  auto a = ours.station(SecurityMode::kSigned);
  auto stranger = foreign.station(SecurityMode::kSigned);
  // Its first CAM carries its AT, whose AA we do not know: unknown_issuer, and we ask for the AA
  // in our next CAM (1609.2 P2PCD).
  auto out = a.decapsulate(stranger.encapsulate(kPsidCam, kPayload, kNow), kNow);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].pass_up);
  EXPECT_EQ(out[0].reason, VerifyResult::kUnknownIssuer);
  const Bytes asking = a.encapsulate(kPsidCam, kPayload, kNow + 1000);
  const auto asked = decode_data(asking);
  ASSERT_TRUE(asked);
  ASSERT_TRUE(asked->signed_data.tbs.header.inline_p2pcd_request);
  EXPECT_EQ(asked->signed_data.tbs.header.inline_p2pcd_request->front(),
            hashed_id3(certificate_id(foreign.aa)));
  // The stranger (which cannot verify us either) answers with its AA...
  out = stranger.decapsulate(asking, kNow + 1000);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].reason, VerifyResult::kUnknownIssuer);
  const Bytes answer = stranger.encapsulate(kPsidCam, kPayload, kNow + 2000);
  const auto answered = decode_data(answer);
  ASSERT_TRUE(answered);
  ASSERT_TRUE(answered->signed_data.tbs.header.requested_certificate);
  EXPECT_EQ(certificate_id(*answered->signed_data.tbs.header.requested_certificate),
            certificate_id(foreign.aa));
  // ... which is not under our root: refused and remembered, so that the stations of that PKI
  // are dropped as untrusted_root from then on.
  a.decapsulate(answer, kNow + 2000);
  EXPECT_EQ(a.verifier().refused_authority(certificate_id(foreign.aa)),
            VerifyResult::kUntrustedRoot);
  auto other = foreign.station(SecurityMode::kSigned);
  out = a.decapsulate(other.encapsulate(kPsidCam, kPayload, kNow + 3000), kNow + 3000);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].pass_up);
  EXPECT_EQ(out[0].reason, VerifyResult::kUntrustedRoot);
  EXPECT_EQ(a.verifier().count(VerifyResult::kUntrustedRoot), 1u);
}

// Verification on demand (issue 33, README "Verification on demand").
const ThreeDLocation kWhere{487000000, 110000000, 5000};

Bytes tamper(Bytes packet) {
  packet.back() ^= 0x01;  // the signature's s ends the packet: it still decodes
  return packet;
}

TEST(VerifyOnDemand, PassesCamsUpUnverifiedAndCachesTheirCertificate) {
  Fixture f;
  auto a = f.station(SecurityMode::kSigned);
  auto b = f.station(SecurityMode::kSigned);
  const auto base = b.verifier().ecdsa_verifications();  // the AA, checked at the start
  b.set_verify_policy(VerifyPolicy::kOnDemand);
  EXPECT_FALSE(b.verifies(kPsidCam));
  EXPECT_FALSE(b.verifies(kPsidGnMgmt));
  EXPECT_TRUE(b.verifies(kPsidDenm));
  // a's first CAM carries its AT: checked once against the AA (one ECDSA verification) and
  // cached; the CAM's own signature is not.
  auto out = b.decapsulate(a.encapsulate(kPsidCam, kPayload, kNow), kNow);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0].pass_up);
  EXPECT_EQ(out[0].reason, VerifyResult::kNotVerified);
  EXPECT_EQ(out[0].psid, kPsidCam);
  EXPECT_EQ(out[0].payload, kPayload);
  EXPECT_TRUE(out[0].ssp.empty());  // SSP only from a verified packet
  EXPECT_EQ(b.verifier().ecdsa_verifications() - base, 1u);
  EXPECT_TRUE(b.verifier().knows(a.signer().id()));
  // Digest-signed CAMs, a forged signature too: passed up, no ECDSA verification.
  out = b.decapsulate(a.encapsulate(kPsidCam, kPayload, kNow + 100'000), kNow + 100'000);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].reason, VerifyResult::kNotVerified);
  out = b.decapsulate(tamper(a.encapsulate(kPsidCam, kPayload, kNow + 200'000)), kNow + 200'000);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0].pass_up);
  EXPECT_EQ(out[0].reason, VerifyResult::kNotVerified);
  EXPECT_EQ(b.verifier().ecdsa_verifications() - base, 1u);
  EXPECT_EQ(b.verifier().count(VerifyResult::kNotVerified), 3u);
  EXPECT_EQ(b.passed_unverified(), 0u);  // not a failure passed up by a permissive station
  // What can be told without the signature still counts: a CAM out of its time window.
  out = b.decapsulate(a.encapsulate(kPsidCam, kPayload, kNow), kNow + 3'000'000);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].pass_up);
  EXPECT_EQ(out[0].reason, VerifyResult::kGenerationTimeOutOfWindow);
}

TEST(VerifyOnDemand, VerifiesDenmsAndDropsATamperedOne) {
  Fixture f;
  auto a = f.station(SecurityMode::kSigned);
  auto b = f.station(SecurityMode::kSigned);
  const auto base = b.verifier().ecdsa_verifications();  // the AA, checked at the start
  b.set_verify_policy(VerifyPolicy::kOnDemand);
  b.decapsulate(a.encapsulate(kPsidCam, kPayload, kNow), kNow);  // a's AT, cached
  const auto before = b.verifier().ecdsa_verifications() - base;
  auto out = b.decapsulate(a.encapsulate(kPsidDenm, kPayload, kNow + 1000, kWhere), kNow + 1000);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0].pass_up);
  EXPECT_EQ(out[0].reason, VerifyResult::kOk);
  EXPECT_FALSE(out[0].ssp.empty());  // the DEN service checks the cause code against it
  EXPECT_EQ(b.verifier().ecdsa_verifications() - base, before + 1);
  out = b.decapsulate(tamper(a.encapsulate(kPsidDenm, kPayload, kNow + 2000, kWhere)), kNow + 2000);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].pass_up);
  EXPECT_EQ(out[0].reason, VerifyResult::kSignatureInvalid);
}

TEST(VerifyOnDemand, DenmOfAnUnknownDigestIsHeldUntilACamBringsTheCertificate) {
  Fixture f;
  // Another stack's signer, which may sign a DENM with its AT's digest.
  EcKey k = EcKey::generate(EccCurve::kNistP256);
  Certificate at = make_ticket(k, {kNowS - 60, DurationUnit::kHours, 10}, f.aa, f.aa_key);
  Signer a(std::move(at), std::move(k), f.aa);
  auto b = f.station(SecurityMode::kSigned);
  b.set_verify_policy(VerifyPolicy::kOnDemand);
  a.sign_cam(kPayload, kNow);  // a's AT, lost
  // A digest-signed CAM of an unknown AT goes up unverified, and b asks for the AT.
  auto out = b.decapsulate(a.sign_cam(kPayload, kNow + 1000), kNow + 1000);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].reason, VerifyResult::kNotVerified);
  EXPECT_TRUE(out[0].pass_up);
  const auto ask = decode_data(b.encapsulate(kPsidCam, kPayload, kNow + 2000));
  ASSERT_TRUE(ask && ask->signed_data.tbs.header.inline_p2pcd_request);
  EXPECT_EQ(ask->signed_data.tbs.header.inline_p2pcd_request->front(), hashed_id3(a.id()));
  // A DENM signed with the digest waits; a's next CAM, which carries the AT, releases it.
  out = b.decapsulate(a.sign(kPsidDenm, kPayload, kNow + 3000, kWhere, false), kNow + 3000, 7);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(b.held(), 1u);
  a.on_unknown_station();
  out = b.decapsulate(a.sign_cam(kPayload, kNow + 4000), kNow + 4000, 8);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].reason, VerifyResult::kNotVerified);
  EXPECT_EQ(out[1].ticket, 7u);
  EXPECT_TRUE(out[1].pass_up);
  EXPECT_EQ(out[1].reason, VerifyResult::kOk);
  // From then on a digest-signed DENM verifies at once.
  out = b.decapsulate(a.sign(kPsidDenm, kPayload, kNow + 5000, kWhere, false), kNow + 5000);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].reason, VerifyResult::kOk);
}

// Issue 34: a pooled station without the signal application leaves SPATEM and MAPEM unverified
// (it does not even take them in); one that runs it verifies them.
TEST(VerifyOnDemand, VerifiesSpatemAndMapemOnlyForTheSignalApplication) {
  Fixture f;
  auto a = f.station(SecurityMode::kSigned);
  auto b = f.station(SecurityMode::kSigned);
  b.set_verify_policy(VerifyPolicy::kOnDemand);
  // a's AT first, so that the messages below are signed with its digest.
  b.decapsulate(a.encapsulate(kPsidCam, kPayload, kNow), kNow);
  const auto base = b.verifier().ecdsa_verifications();
  EXPECT_FALSE(b.verifies(kPsidSpatem));
  EXPECT_FALSE(b.verifies(kPsidMapem));
  auto out = b.decapsulate(tamper(a.encapsulate(kPsidSpatem, kPayload, kNow + 1000)), kNow + 1000);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].reason, VerifyResult::kNotVerified);
  EXPECT_EQ(b.verifier().ecdsa_verifications(), base);
  b.set_signal_consumer(true);
  EXPECT_TRUE(b.verifies(kPsidSpatem));
  EXPECT_TRUE(b.verifies(kPsidMapem));
  EXPECT_FALSE(b.verifies(kPsidCam));  // the CAM consumer is another switch
  out = b.decapsulate(tamper(a.encapsulate(kPsidMapem, kPayload, kNow + 2000)), kNow + 2000);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].pass_up);
  // Checked now: the test's AT carries no ITS-AID 138, which only verification looks at.
  EXPECT_EQ(out[0].reason, VerifyResult::kPsidNotPermitted) << to_string(out[0].reason);
  // A full station verifies them whatever runs.
  auto c = f.station(SecurityMode::kSigned);
  EXPECT_TRUE(c.verifies(kPsidSpatem));
  EXPECT_TRUE(c.verifies(kPsidMapem));
}

TEST(VerifyOnDemand, VerifiesCamsWhenAConsumerRuns) {
  Fixture f;
  auto a = f.station(SecurityMode::kSigned);
  auto b = f.station(SecurityMode::kSigned);
  const auto base = b.verifier().ecdsa_verifications();  // the AA, checked at the start
  b.set_verify_policy(VerifyPolicy::kOnDemand);
  b.set_cam_consumer(true);
  EXPECT_TRUE(b.verifies(kPsidCam));
  EXPECT_FALSE(b.verifies(kPsidGnMgmt));
  auto out = b.decapsulate(a.encapsulate(kPsidCam, kPayload, kNow), kNow);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].reason, VerifyResult::kOk);
  EXPECT_EQ(b.verifier().ecdsa_verifications() - base, 2u);  // the AT, then the CAM
  out = b.decapsulate(tamper(a.encapsulate(kPsidCam, kPayload, kNow + 1000)), kNow + 1000);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].pass_up);
  EXPECT_EQ(out[0].reason, VerifyResult::kSignatureInvalid);
}

TEST(VerifyOnDemand, EveryIsTheDefaultAndVerifiesEachPacket) {
  Fixture f;
  auto a = f.station(SecurityMode::kSigned);
  auto b = f.station(SecurityMode::kSigned);
  const auto base = b.verifier().ecdsa_verifications();  // the AA, checked at the start
  EXPECT_EQ(b.verify_policy(), VerifyPolicy::kEvery);
  EXPECT_TRUE(b.verifies(kPsidCam) && b.verifies(kPsidGnMgmt));
  b.decapsulate(a.encapsulate(kPsidCam, kPayload, kNow), kNow);
  b.decapsulate(a.encapsulate(kPsidCam, kPayload, kNow + 1000), kNow + 1000);
  EXPECT_EQ(b.verifier().ecdsa_verifications() - base, 3u);
  EXPECT_EQ(b.verifier().count(VerifyResult::kOk), 2u);
}

}  // namespace
}  // namespace tb::its::security
