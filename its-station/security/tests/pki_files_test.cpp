#include "its-station/security/pki_files.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>

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
  groups.front().psids.pop_back();
  ASSERT_EQ(groups.front().psids.back().psid, kPsidDenm);
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

}  // namespace
}  // namespace tb::its::security
