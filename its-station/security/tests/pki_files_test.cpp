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
