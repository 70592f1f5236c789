#include "its-station/security/pki_files.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <functional>

#include "common/clock/utc.hpp"
#include "its-station/security/pki.hpp"
#include "its-station/security/signer.hpp"
#include "its-station/security/time.hpp"
#include "its-station/security/verifier.hpp"

namespace tb::its::security {
namespace {

namespace fs = std::filesystem;

const clock::WallTime kWall{std::chrono::seconds(1795454308)};

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::path(::testing::TempDir()) / name;
  fs::remove_all(d);
  return d;
}

TEST(PkiFiles, MakesWhatIsMissingAndStationsVerifyEachOther) {
  const PkiPaths paths{fresh_dir("i20-pki")};
  PkiOptions o;
  o.now = to_time32(kWall);
  auto written = make_pki(paths, {1001, 1002}, o);
  EXPECT_EQ(written.size(), 8u);
  EXPECT_EQ((fs::status(paths.at_key(1001)).permissions() & fs::perms::others_read),
            fs::perms::none);
  EXPECT_TRUE(make_pki(paths, {1001, 1002}, o).empty());   // nothing missing
  EXPECT_EQ(make_pki(paths, {1001, 1003}, o).size(), 2u);  // only the new station's AT
  auto a = load_station_credentials(paths, 1001);
  auto b = load_station_credentials(paths, 1003);
  EXPECT_EQ(a.root, b.root);
  Verifier v({b.root});
  ASSERT_EQ(v.add_authority(b.aa, to_time64(kWall)), VerifyResult::kOk);
  Signer s(a.at, std::move(a.at_key), a.aa);
  const Bytes cam = s.sign_cam(Bytes{1, 2, 3}, to_time64(kWall));
  EXPECT_EQ(v.verify(cam, kPsidCam, to_time64(kWall)).result, VerifyResult::kOk);
}

// Issue 34: a road-side unit's AT carries SPATEM (137) and MAPEM (138) too, a vehicle's does not;
// the RSU signs both, a vehicle's verifier accepts them, and a vehicle cannot sign them.
TEST(PkiFiles, ARoadSideUnitsAtSignsSpatemAndMapem) {
  const PkiPaths paths{fresh_dir("i34-pki-rsu")};
  PkiOptions o;
  o.now = to_time32(kWall);
  o.road_side_units = {5001};
  ASSERT_EQ(make_pki(paths, {1001, 5001}, o).size(), 8u);
  auto rsu = load_station_credentials(paths, 5001);
  auto car = load_station_credentials(paths, 1001);
  EXPECT_EQ(*rsu.at.tbs.app_permissions, ticket_permissions(true));
  EXPECT_EQ(*car.at.tbs.app_permissions, ticket_permissions(false));
  Verifier v({car.root});
  ASSERT_EQ(v.add_authority(car.aa, to_time64(kWall)), VerifyResult::kOk);
  Signer rsu_signer(rsu.at, std::move(rsu.at_key), rsu.aa);
  Signer car_signer(car.at, std::move(car.at_key), car.aa);
  EXPECT_TRUE(rsu_signer.permits(kPsidSpatem));
  EXPECT_TRUE(rsu_signer.permits(kPsidMapem));
  EXPECT_TRUE(rsu_signer.permits(kPsidCam));
  EXPECT_FALSE(car_signer.permits(kPsidSpatem));
  EXPECT_FALSE(car_signer.permits(kPsidMapem));
  for (const Psid psid : {kPsidSpatem, kPsidMapem}) {
    const Bytes signed_data = rsu_signer.sign_other(psid, Bytes{4, 5, 6}, to_time64(kWall));
    EXPECT_EQ(v.verify(signed_data, psid, to_time64(kWall)).result, VerifyResult::kOk) << psid;
    // A car's AT signing it anyway is refused by the receiver.
    const Bytes forged = car_signer.sign_other(psid, Bytes{4, 5, 6}, to_time64(kWall));
    EXPECT_EQ(v.verify(forged, psid, to_time64(kWall)).result, VerifyResult::kPsidNotPermitted)
        << psid;
  }
  // Nothing to do again; a station that stops being an RSU gets a vehicle's AT.
  EXPECT_TRUE(make_pki(paths, {1001, 5001}, o).empty());
  PkiOptions no_rsu = o;
  no_rsu.road_side_units.clear();
  EXPECT_EQ(make_pki(paths, {1001, 5001}, no_rsu),
            (std::vector{paths.at_key(5001), paths.at_cert(5001)}));
  EXPECT_EQ(*read_certificate(paths.at_cert(5001)).tbs.app_permissions, ticket_permissions());
}

TEST(PkiFiles, MakesAgainWhatWouldNoLongerWork) {
  const PkiPaths paths{fresh_dir("i20-pki-renew")};
  PkiOptions o;
  o.now = to_time32(kWall);
  ASSERT_EQ(make_pki(paths, {1, 2}, o).size(), 8u);
  const auto at1 = read_certificate(paths.at_cert(1));
  // ATs are valid a week (from an hour before): with less than an hour left they are renewed,
  // under the same root and AA.
  PkiOptions later = o;
  later.now = o.now + 7 * 24 * 3600 - 2 * 3600 - 60;
  EXPECT_TRUE(make_pki(paths, {1, 2}, later).empty());
  later.now += 120;
  const auto renewed = make_pki(paths, {1, 2}, later);
  EXPECT_EQ(renewed.size(), 4u);  // two ATs and their keys
  const auto at1_new = read_certificate(paths.at_cert(1));
  EXPECT_NE(at1_new, at1);
  EXPECT_EQ(at1_new.issuer.digest, certificate_id(read_certificate(paths.aa_cert())));

  // An AA of an older its-pki, without GN-MGMT among what it may issue: root, AA and every AT
  // are made anew (an AT it issued could not get the permission).
  Certificate aa = read_certificate(paths.aa_cert());
  const Certificate root = read_certificate(paths.root_cert());
  const EcKey root_key = EcKey::load_private_pem(paths.root_key().string());
  auto& groups = *aa.tbs.cert_issue_permissions;
  auto& psids = groups.front().psids;
  const auto gn_mgmt = std::find_if(psids.begin(), psids.end(),
                                    [](const PsidSspRange& p) { return p.psid == kPsidGnMgmt; });
  ASSERT_NE(gn_mgmt, psids.end());
  psids.erase(gn_mgmt);
  sign_certificate(aa, &root, root_key);
  write_certificate(paths.aa_cert(), aa);
  EXPECT_EQ(make_pki(paths, {1, 2}, later).size(), 8u);
  auto c = load_station_credentials(paths, 2);
  EXPECT_NE(c.root, root);
  EXPECT_TRUE(Signer(c.at, std::move(c.at_key), c.aa).permits(kPsidGnMgmt));

  // An AT without GN-MGMT (issued by this AA): that AT alone is made anew.
  const EcKey aa_key = EcKey::load_private_pem(paths.aa_key().string());
  Certificate at = read_certificate(paths.at_cert(2));
  at.tbs.app_permissions->pop_back();
  sign_certificate(at, &c.aa, aa_key);
  write_certificate(paths.at_cert(2), at);
  const auto again = make_pki(paths, {1, 2}, later);
  ASSERT_EQ(again.size(), 2u);
  EXPECT_EQ(again.back(), paths.at_cert(2));
}

TEST(PkiFiles, BadFilesAreNamed) {
  const PkiPaths paths{fresh_dir("i20-pki-bad")};
  PkiOptions o;
  o.now = to_time32(kWall);
  make_pki(paths, {7}, o);
  try {
    load_station_credentials(paths, 8);
    FAIL() << "no AT for station 8";
  } catch (const PkiFileError& e) {
    EXPECT_NE(std::string(e.what()).find("at-8.cert: cannot open"), std::string::npos) << e.what();
  }
  // A key that is not the AT's.
  const fs::path saved = paths.at_key(7).string() + ".saved";
  fs::copy_file(paths.at_key(7), saved);
  fs::copy_file(paths.root_key(), paths.at_key(7), fs::copy_options::overwrite_existing);
  EXPECT_THROW(load_station_credentials(paths, 7), PkiFileError);
  fs::copy_file(saved, paths.at_key(7), fs::copy_options::overwrite_existing);
  EXPECT_NO_THROW(load_station_credentials(paths, 7));
  // A corrupt certificate, when loading and when making the missing rest.
  std::ofstream(paths.aa_cert(), std::ios::trunc) << "garbage";
  for (auto f : {std::function<void()>([&] { load_station_credentials(paths, 7); }),
                 std::function<void()>([&] { make_pki(paths, {9}, o); })}) {
    try {
      f();
      FAIL() << "a corrupt AA certificate";
    } catch (const PkiFileError& e) {
      EXPECT_NE(std::string(e.what()).find("aa.cert: not a COER certificate"), std::string::npos)
          << e.what();
    }
  }
}

// its-pki make --at: a PKI made for one world epoch is made anew when asked for another a year
// away, in either direction, valid from an hour before that epoch.
TEST(PkiFiles, MadeForTheEpochItIsAskedFor) {
  // Time32 is TAI seconds since 2004-01-01 (1609.2 6.4.13), worked out by hand:
  // 2004-01-01 .. 2025-01-01: 21 years, 6 of them leap (2004 .. 2024): 7671 days; to June 2nd:
  // 31 + 28 + 31 + 30 + 31 + 1 = 152 days more; 7823 days = 675 907 200 s, + 9 h = 675 939 600,
  // + 5 leap seconds (TAI) = 675 939 605. 2026: one year of 365 days more, 707 475 605.
  const auto at_2025 = clock::parse_utc("2025-06-02T09:00:00Z");
  const auto at_2026 = clock::parse_utc("2026-06-02T09:00:00Z");
  ASSERT_TRUE(at_2025 && at_2026);
  PkiOptions o2025;
  o2025.now = to_time32(*at_2025);
  PkiOptions o2026;
  o2026.now = to_time32(*at_2026);
  ASSERT_EQ(o2025.now, 675'939'605u);
  ASSERT_EQ(o2026.now, 707'475'605u);

  const PkiPaths paths{fresh_dir("i31-pki-at")};
  auto expect_made_for = [&](Time32 start) {
    for (const auto& f : {paths.root_cert(), paths.aa_cert(), paths.at_cert(1)})
      EXPECT_EQ(read_certificate(f).tbs.validity.start, start) << f;
    EXPECT_EQ(read_certificate(paths.at_cert(1)).tbs.validity.end_seconds(),
              std::uint64_t{start} + 7 * 24 * 3600);
  };
  ASSERT_EQ(make_pki(paths, {1}, o2026).size(), 6u);
  expect_made_for(707'472'005);
  EXPECT_TRUE(make_pki(paths, {1}, o2026).empty());
  // Asked for 2025: not yet valid then, so root, AA and AT are made anew.
  EXPECT_EQ(make_pki(paths, {1}, o2025).size(), 6u);
  expect_made_for(675'936'005);
  EXPECT_TRUE(make_pki(paths, {1}, o2025).empty());
  // And back to 2026: long expired then.
  EXPECT_EQ(make_pki(paths, {1}, o2026).size(), 6u);
  expect_made_for(707'472'005);
}

TEST(PkiFiles, ParsesUtcTextOrRefusesIt) {
  const auto t = clock::parse_utc("2025-06-02T09:00:00.250Z");
  ASSERT_TRUE(t);
  EXPECT_EQ(clock::to_unix_ns(*t), 1'748'854'800'250'000'000);  // 20 241 days + 9 h, + 250 ms
  for (const char* bad : {"2025-06-02T09:00:00", "2025-06-02 09:00:00Z", "2025-02-30T09:00:00Z",
                          "2025-06-02T24:00:00Z", "2025-06-02T09:00:60Z", "2025-06-02T09:00:00.Z",
                          "2025-06-02T09:00:00+02:00", "tomorrow", ""})
    EXPECT_FALSE(clock::parse_utc(bad)) << bad;
}

// its-pki issue / export: an AT for another stack's key, under our AA with our stations'
// permissions; what is exported lets that stack sign packets our stations verify, and verify
// theirs.
TEST(PkiFiles, IssuesAnAtForAnOutsideKeyAndExportsIt) {
  const PkiPaths paths{fresh_dir("i31-pki-issue")};
  PkiOptions o;
  o.now = to_time32(kWall);
  ASSERT_EQ(make_pki(paths, {1001}, o).size(), 6u);
  const fs::path outside = paths.dir / "outside";
  fs::create_directories(outside);
  EcKey key = EcKey::generate(EccCurve::kNistP256);
  key.save_private_pem((outside / "key.pem").string());
  key.save_public_pem((outside / "pub.pem").string());

  const auto written = issue_ticket(paths, 9001, outside / "pub.pem", o);
  // Root and AA were there: the key kept for renewals, and the AT.
  ASSERT_EQ(written, (std::vector{paths.at_public_key(9001), paths.at_cert(9001)}));
  EXPECT_FALSE(fs::exists(paths.at_key(9001)));
  // make (the launcher, for every station) keeps it, and renews it for the same key when due.
  EXPECT_TRUE(make_pki(paths, {1001, 9001}, o).empty());
  PkiOptions week_later = o;
  week_later.now += 7 * 24 * 3600;
  EXPECT_EQ(make_pki(paths, {9001}, week_later), std::vector{paths.at_cert(9001)});
  EXPECT_EQ(read_certificate(paths.at_cert(9001)).tbs.verify_key.point, key.public_point());
  EXPECT_FALSE(fs::exists(paths.at_key(9001)));
  ASSERT_EQ(issue_ticket(paths, 9001, outside / "pub.pem", o).size(), 2u);  // back to o.now
  const Certificate at = read_certificate(paths.at_cert(9001));
  EXPECT_EQ(at.tbs.verify_key.point, key.public_point());
  EXPECT_EQ(*at.tbs.app_permissions, ticket_permissions());
  EXPECT_EQ(at.tbs.validity.start, o.now - 3600);

  // The export: COER certificates under PkiPaths' names, no key (the PKI does not have it).
  const fs::path out = paths.dir / "export-9001";
  const auto exported = export_station(paths, 9001, out);
  EXPECT_EQ(exported.size(), 3u);
  const PkiPaths x{out};
  EXPECT_FALSE(fs::exists(x.at_key(9001)));
  const Certificate root = read_certificate(x.root_cert());
  const Certificate aa = read_certificate(x.aa_cert());
  EXPECT_EQ(read_certificate(x.at_cert(9001)), at);

  // The AT verifies under the AA: a CAM signed with the outside key and that AT (the whole AT
  // as signer, then its digest) passes our verifier.
  const Time64 now = to_time64(kWall);
  Verifier ours({read_certificate(paths.root_cert())});
  ASSERT_EQ(ours.add_authority(read_certificate(paths.aa_cert()), now), VerifyResult::kOk);
  Signer theirs(read_certificate(x.at_cert(9001)),
                EcKey::load_private_pem((outside / "key.pem").string()), aa);
  const Bytes cam = theirs.sign_cam(Bytes{9, 0, 0, 1}, now);
  EXPECT_TRUE(theirs.last_with_certificate());
  const auto v = ours.verify(cam, kPsidCam, now);
  EXPECT_EQ(v.result, VerifyResult::kOk);
  EXPECT_EQ(v.ssp, kCamSsp);
  const Bytes digest_cam = theirs.sign_cam(Bytes{9, 0, 0, 2}, now + 100'000);
  EXPECT_FALSE(theirs.last_with_certificate());
  EXPECT_EQ(ours.verify(digest_cam, kPsidCam, now + 100'000).result, VerifyResult::kOk);
  // The Signer refuses the AT with any other key.
  EXPECT_THROW(Signer(at, EcKey::generate(EccCurve::kNistP256), aa), std::exception);

  // And the other way: with only the exported root and AA, the outside stack verifies ours.
  Verifier their_verifier({root});
  ASSERT_EQ(their_verifier.add_authority(aa, now), VerifyResult::kOk);
  auto red = load_station_credentials(paths, 1001);
  Signer our_signer(red.at, std::move(red.at_key), red.aa);
  EXPECT_EQ(
      their_verifier.verify(our_signer.sign_cam(Bytes{1, 0, 0, 1}, now), kPsidCam, now).result,
      VerifyResult::kOk);

  // A station whose key the PKI made: exported with its key, owner-only.
  const auto with_key = export_station(paths, 1001, out);
  ASSERT_EQ(with_key.size(), 4u);
  EXPECT_EQ(with_key.back(), x.at_key(1001));
  EXPECT_EQ(
      (fs::status(x.at_key(1001)).permissions() & (fs::perms::group_all | fs::perms::others_all)),
      fs::perms::none);
  EXPECT_NO_THROW(load_station_credentials(x, 1001));
}

TEST(PkiFiles, OutsideKeysThatAreNoP256PublicKeyAreRefusedByName) {
  const PkiPaths paths{fresh_dir("i31-pki-issue-bad")};
  PkiOptions o;
  o.now = to_time32(kWall);
  make_pki(paths, {}, o);
  auto refused = [&](const fs::path& file, const std::string& says) {
    try {
      issue_ticket(paths, 9001, file, o);
      ADD_FAILURE() << file << " was taken";
    } catch (const PkiFileError& e) {
      EXPECT_NE(std::string(e.what()).find(file.string() + ": " + says), std::string::npos)
          << e.what();
    }
    EXPECT_FALSE(fs::exists(paths.at_cert(9001)));
  };
  refused(paths.dir / "missing.pem", "cannot open");
  // A private key where the public one belongs, and a PEM whose base64 is cut short.
  refused(paths.aa_key(), "not a PEM public key");
  const fs::path pub = paths.dir / "pub.pem";
  EcKey::generate(EccCurve::kNistP256).save_public_pem(pub.string());
  std::string text;
  {
    std::ifstream in(pub);
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const fs::path cut = paths.dir / "cut.pem";
  std::ofstream(cut) << text.substr(0, 40) << "\n-----END PUBLIC KEY-----\n";
  refused(cut, "not a PEM public key");
  // brainpoolP256r1: a 1609.2 curve, but not one our ATs use.
  const fs::path bp = paths.dir / "brainpool.pem";
  EcKey::generate(EccCurve::kBrainpoolP256r1).save_public_pem(bp.string());
  refused(bp, "a brainpoolP256r1 key");
  EXPECT_FALSE(fs::exists(paths.at_public_key(9001)));
  EXPECT_NO_THROW(issue_ticket(paths, 9001, pub, o));
}

}  // namespace
}  // namespace tb::its::security
