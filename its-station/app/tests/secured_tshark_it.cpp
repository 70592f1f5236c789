// Interoperability with Wireshark for signed packets: CAMs (certificate, then digest signer)
// and a DENM as the stack sends them with security `signed` (router + security entity + BTP),
// written to a pcap and decoded by Debian's tshark 4.0 down to the CAM/DENM fields, with no
// malformed packet and no expert information but the note tshark gives every secured SHB.

#include <gtest/gtest.h>
#include <stdlib.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "its-station/btp/dispatcher.hpp"
#include "its-station/geonet/router.hpp"
#include "its-station/geonet/tests/router_fixture.hpp"
#include "its-station/link/test_link.hpp"
#include "its-station/messages/cam.hpp"
#include "its-station/messages/denm.hpp"
#include "its-station/messages/tests/run_command.hpp"
#include "its-station/messages/tests/samples.hpp"
#include "its-station/security/tests/test_pki.hpp"

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
  sec::testing::TestPki pki{rt.wall_now()};
  auto entity = pki.entity(sec::SecurityMode::kSigned);
  link::TestLink link(geonet::testing::mac(1));
  geonet::StaticPositionProvider position;
  position.set({rt.wall_now(), 41.0255, 28.9742, 13.89, 90.0, true});
  // A beacon 2 s after the last CAM (each SHB puts it off), signed for GN-MGMT.
  geonet::RouterConfig cfg;
  cfg.beacon_interval = std::chrono::seconds(2);
  cfg.beacon_max_jitter = std::chrono::milliseconds(0);
  geonet::Router router(rt, link, position, cfg);
  router.set_security(entity.get());
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
  rt.advance(std::chrono::milliseconds(2000));

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
  ASSERT_EQ(frames.size(), 4u);
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
  std::string l1, l2, l3, l4;
  std::getline(lines, l1);
  std::getline(lines, l2);
  std::getline(lines, l3);
  std::getline(lines, l4);
  // Signer: 1 = certificate, 0 = digest (the second CAM within the second).
  EXPECT_EQ(l1, "2|36|1|2001|2|" + id + "|" + std::to_string(rp.latitude));
  EXPECT_EQ(l2, "2|36|0|2001|2|" + id + "|" + std::to_string(rp.latitude));
  EXPECT_EQ(l3.substr(0, 12), "2|37|1|2002|");
  EXPECT_NE(l3.find("|1|" + std::to_string(denm.header.stationID)), std::string::npos) << l3;
  EXPECT_EQ(l4, "2|141|1||||");  // the beacon: no CAM carried the AT in the last second

  // Expert information, packet by packet: tshark notes a secured packet whose remaining hop
  // limit is below 5 (packet-geonw.c, ei_geonw_rhl_too_low, severity note), which every signed
  // SHB and beacon has (RHL 1, clause 10.3.10.2); nothing else may show, in any packet: no
  // other note, no warning, no error, no malformed packet. The DENM (a GBC, RHL 10) has none.
  const std::string expert =
      run("tshark -r '" + pcap.string() +
          "' -T fields -E separator='|' -e frame.number -e _ws.expert.severity"
          " -e _ws.expert.message -e _ws.malformed 2>/dev/null");
  std::istringstream per_packet(expert);
  std::vector<std::string> got_expert;
  for (std::string line; std::getline(per_packet, line);)
    got_expert.push_back(line);
  const std::string note = std::to_string(0x00400000);  // PI_NOTE
  EXPECT_EQ(got_expert,
            (std::vector<std::string>{"1|" + note + "|\"Remain Hop Limit\" only 1|",
                                      "2|" + note + "|\"Remain Hop Limit\" only 1|", "3|||",
                                      "4|" + note + "|\"Remain Hop Limit\" only 1|"}))
      << expert;
  const std::string summary = run("tshark -r '" + pcap.string() + "' -q -z expert 2>/dev/null");
  for (const char* word : {"Error", "Warn", "Chat", "Malformed"})
    EXPECT_EQ(summary.find(word), std::string::npos) << word << " in:\n" << summary;
  const std::string full = run("tshark -r '" + pcap.string() + "' -V 2>/dev/null");
  EXPECT_NE(full.find("CoopAwareness"), std::string::npos);
  EXPECT_NE(full.find("DecentralizedEnvironmentalNotificationMessage"), std::string::npos);
  EXPECT_EQ(full.find("Malformed"), std::string::npos);
  std::filesystem::remove_all(tmpl);
}

}  // namespace
}  // namespace tb::its
