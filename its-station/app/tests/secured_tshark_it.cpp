// Interoperability with Wireshark for signed packets: CAMs (certificate, then digest signer)
// and a DENM as the stack sends them with security `signed` (router + security entity + BTP),
// written to a pcap and decoded by Debian's tshark 4.0 down to the CAM/DENM fields, with no
// malformed packet and no expert information.

#include <gtest/gtest.h>
#include <stdlib.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "its-station/btp/dispatcher.hpp"
#include "its-station/geonet/router.hpp"
#include "its-station/geonet/tests/router_fixture.hpp"
#include "its-station/link/test_link.hpp"
#include "its-station/messages/cam.hpp"
#include "its-station/messages/denm.hpp"
#include "its-station/messages/tests/run_command.hpp"
#include "its-station/messages/tests/samples.hpp"
#include "its-station/security/pki.hpp"
#include "its-station/security/time.hpp"

namespace tb::its {
namespace {

using Bytes = std::vector<std::uint8_t>;
namespace sec = security;

void write_pcap(const std::filesystem::path& path, const std::vector<Bytes>& frames) {
  std::ofstream out(path, std::ios::binary);
  auto le = [&](std::uint32_t v, int n) {
    for (int i = 0; i < n; ++i)
      out.put(static_cast<char>(v >> (8 * i)));
  };
  le(0xA1B2C3D4, 4);
  le(2, 2);
  le(4, 2);
  le(0, 4);
  le(0, 4);
  le(65535, 4);
  le(1, 4);  // LINKTYPE_ETHERNET
  std::uint32_t t = 1700000000;
  for (const Bytes& f : frames) {
    le(t++, 4);
    le(0, 4);
    le(static_cast<std::uint32_t>(f.size()), 4);
    le(static_cast<std::uint32_t>(f.size()), 4);
    out.write(reinterpret_cast<const char*>(f.data()), static_cast<std::streamsize>(f.size()));
  }
}

std::string run(const std::string& cmd) {
  return test::run_command(cmd);
}

TEST(SecuredTshark, SignedCamsAndDenmDecodeDownToTheirFields) {
  if (std::system("command -v tshark >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "tshark not installed (scripts/install-deps installs it)";
  clock::ManualRuntime rt;
  const sec::Time32 start = sec::to_time32(rt.wall_now()) - 3600;
  sec::EcKey root_key = sec::EcKey::generate(sec::EccCurve::kNistP256);
  sec::EcKey aa_key = sec::EcKey::generate(sec::EccCurve::kNistP256);
  const auto root = sec::make_root(root_key, "root", {start, sec::DurationUnit::kHours, 100});
  const auto aa =
      sec::make_authority(aa_key, "aa", {start, sec::DurationUnit::kHours, 100}, root, root_key);
  sec::EcKey at_key = sec::EcKey::generate(sec::EccCurve::kNistP256);
  auto at = sec::make_ticket(at_key, {start, sec::DurationUnit::kHours, 10}, aa, aa_key);
  sec::Verifier verifier({root});
  sec::SecurityEntity entity(sec::SecurityMode::kSigned, sec::Signer(at, std::move(at_key), aa),
                             std::move(verifier));

  link::TestLink link(geonet::testing::mac(1));
  geonet::StaticPositionProvider position;
  position.set({rt.wall_now(), 41.0255, 28.9742, 13.89, 90.0, true});
  geonet::RouterConfig cfg;
  cfg.beacon_interval = std::chrono::hours(1);
  geonet::Router router(rt, link, position, cfg);
  router.set_security(&entity);
  btp::Dispatcher btp(router);

  const messages::Cam cam = messages::samples::cam_hf();
  const auto cam_bytes = messages::encode(cam);
  ASSERT_TRUE(cam_bytes);
  ASSERT_EQ(btp.send_b(geonet::DataRequest::single_hop(), btp::kPortCam, 0, *cam_bytes),
            geonet::DataConfirm::kAccepted);
  rt.advance(std::chrono::milliseconds(100));
  ASSERT_EQ(btp.send_b(geonet::DataRequest::single_hop(), btp::kPortCam, 0, *cam_bytes),
            geonet::DataConfirm::kAccepted);
  const messages::Denm denm = messages::samples::denm_collision_risk();
  const auto denm_bytes = messages::encode(denm);
  ASSERT_TRUE(denm_bytes);
  ASSERT_EQ(btp.send_b(geonet::DataRequest::geo_broadcast(
                           geonet::testing::circle_at({41.0255, 28.9742}, 500)),
                       btp::kPortDenm, 0, *denm_bytes),
            geonet::DataConfirm::kAccepted);

  std::vector<Bytes> frames;
  for (const auto& s : link.sent()) {
    Bytes f(6, 0xff);
    const auto src = link.address();
    f.insert(f.end(), src.begin(), src.end());
    f.push_back(0x89);
    f.push_back(0x47);
    f.insert(f.end(), s.payload.begin(), s.payload.end());
    frames.push_back(std::move(f));
  }
  ASSERT_EQ(frames.size(), 3u);
  std::string tmpl = (std::filesystem::temp_directory_path() / "sec-tshark-XXXXXX").string();
  ASSERT_NE(mkdtemp(tmpl.data()), nullptr);
  const std::filesystem::path pcap = std::filesystem::path(tmpl) / "signed.pcap";
  write_pcap(pcap, frames);

  const std::string got =
      run("tshark -r '" + pcap.string() +
          "' -T fields -E occurrence=f -E separator='|' -e geonw.bh.nh -e ieee1609dot2.psid"
          " -e ieee1609dot2.signer -e btpb.dstport -e its.messageID"
          " -e its.stationID -e its.latitude 2>/dev/null");
  const auto& rp = cam.cam.camParameters.basicContainer.referencePosition;
  const std::string id = std::to_string(cam.header.stationID);
  std::istringstream lines(got);
  std::string l1, l2, l3;
  std::getline(lines, l1);
  std::getline(lines, l2);
  std::getline(lines, l3);
  // Signer: 1 = certificate, 0 = digest (the second CAM within the second).
  EXPECT_EQ(l1, "2|36|1|2001|2|" + id + "|" + std::to_string(rp.latitude));
  EXPECT_EQ(l2, "2|36|0|2001|2|" + id + "|" + std::to_string(rp.latitude));
  EXPECT_EQ(l3.substr(0, 12), "2|37|1|2002|");
  EXPECT_NE(l3.find("|1|" + std::to_string(denm.header.stationID)), std::string::npos) << l3;

  const std::string expert = run("tshark -r '" + pcap.string() + "' -q -z expert 2>/dev/null");
  // tshark notes every packet with remaining hop limit 1 when it is secured (an SHB always
  // has it); nothing else may show: no warning, error or malformed packet.
  for (const char* word : {"Error", "Warn", "Chat", "Malformed"})
    EXPECT_EQ(expert.find(word), std::string::npos) << word << " in:\n" << expert;
  std::istringstream notes(expert);
  for (std::string line; std::getline(notes, line);) {
    if (line.find("GNW") != std::string::npos || line.find("IEEE") != std::string::npos) {
      EXPECT_NE(line.find("\"Remain Hop Limit\" only 1"), std::string::npos) << line;
    }
  }
  const std::string full = run("tshark -r '" + pcap.string() + "' -V 2>/dev/null");
  EXPECT_NE(full.find("CoopAwareness"), std::string::npos);
  EXPECT_NE(full.find("DecentralizedEnvironmentalNotificationMessage"), std::string::npos);
  EXPECT_EQ(full.find("Malformed"), std::string::npos);
  std::filesystem::remove_all(tmpl);
}

}  // namespace
}  // namespace tb::its
