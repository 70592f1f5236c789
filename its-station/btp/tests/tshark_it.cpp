// Interoperability with Wireshark's GeoNetworking and BTP dissectors: frames made by our router
// and BTP entity are written to a pcap and read back with tshark, which must decode every field
// as sent and report no malformed packets or expert warnings.

#include <unistd.h>

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "its-station/btp/dispatcher.hpp"
#include "its-station/geonet/tests/router_fixture.hpp"
#include "its-station/link/pcap_writer.hpp"
#include "its-station/link/test_link.hpp"

namespace tb::its::btp {
namespace {

using namespace std::chrono_literals;
using geonet::testing::at;
using Bytes = std::vector<std::uint8_t>;

std::string capture(const std::string& cmd) {
  std::string out;
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(::popen(cmd.c_str(), "r"), ::pclose);
  if (!pipe)
    return out;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe.get())) > 0)
    out.append(buf.data(), n);
  return out;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);)
    out.push_back(l);
  return out;
}

class TsharkTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (capture("command -v tshark").empty())
      GTEST_FAIL() << "tshark not installed (scripts/install-deps installs it)";
    path = ::testing::TempDir() + "/gn_tshark_" + std::to_string(::getpid()) + ".pcap";
    auto w = link::PcapWriter::create(path);
    ASSERT_TRUE(w) << w.error();
    pcap = std::make_unique<link::PcapWriter>(std::move(*w));
    link.set_send_observer([this](const link::TestLink::SentFrame& f) {
      pcap->write(rt.wall_now(), f.destination, link.address(), f.ethertype, f.payload);
    });
  }
  void TearDown() override { std::remove(path.c_str()); }
  // A new fix (each packet gets a newer TST, as a 100 Hz receiver would give).
  void fix() {
    pos.set({rt.wall_now(), 48.15, -1.6, 13.89, 271.5, true});
    tst.push_back(geonet::to_timestamp(rt.wall_now()));
    rt.advance(10ms);
  }
  std::string tshark(const std::string& args, bool with_stderr = true) {
    pcap->flush();
    return capture("tshark -n -r '" + path + "' " + args +
                   (with_stderr ? " 2>&1" : " 2>/dev/null"));
  }
  static std::string fields_args() {
    std::string args = "-T fields -E separator=';'";
    for (const char* f : kFields)
      args += std::string(" -e ") + f;
    return args;
  }

  static constexpr const char* kFields[] = {"geonw.bh.version",
                                            "geonw.bh.nh",
                                            "geonw.bh.lt.mult",
                                            "geonw.bh.lt.base",
                                            "geonw.bh.rhl",
                                            "geonw.ch.nh",
                                            "geonw.ch.htype",
                                            "geonw.ch.tc.id",
                                            "geonw.ch.flags.mob",
                                            "geonw.ch.plength",
                                            "geonw.ch.mhl",
                                            "geonw.seq_num",
                                            "geonw.src_pos.addr.manual",
                                            "geonw.src_pos.addr.type",
                                            "geonw.src_pos.addr.mid",
                                            "geonw.src_pos.tst",
                                            "geonw.src_pos.lat",
                                            "geonw.src_pos.long",
                                            "geonw.src_pos.pai",
                                            "geonw.src_pos.speed",
                                            "geonw.src_pos.hdg",
                                            "geonw.gxc.latitude",
                                            "geonw.gxc.longitude",
                                            "geonw.gxc.radius",
                                            "geonw.gxc.distancea",
                                            "geonw.gxc.distanceb",
                                            "geonw.gxc.angle",
                                            "btpb.dstport",
                                            "btpb.dstportinf",
                                            "btpa.dstport",
                                            "btpa.srcport"};
  // Frames with any expert info (malformed, bad length, unknown value) and what it says.
  static constexpr const char* kProblemArgs =
      "-Y '_ws.expert || _ws.malformed' -T fields -e frame.number -e _ws.expert.message";

  std::vector<geonet::Timestamp> tst;

  std::string path;
  std::unique_ptr<link::PcapWriter> pcap;
  clock::ManualRuntime rt;
  link::TestLink link{{0x02, 0x11, 0x22, 0x33, 0x44, 0x55}};
  geonet::StaticPositionProvider pos;
  geonet::RouterConfig config = [] {
    geonet::RouterConfig c;
    c.beacon_max_jitter = 0ms;
    return c;
  }();
  geonet::Router router{rt, link, pos, config};
  Dispatcher btp{router};
};

TEST_F(TsharkTest, EveryPacketTypeDecodesAsSentWithoutWarnings) {
  fix();
  rt.run_due();  // beacon
  fix();
  const Bytes data = {0xde, 0xad, 0xbe, 0xef};
  ASSERT_EQ(btp.send_b(geonet::DataRequest::single_hop({false, false, 2}, 1s), 3000, 0x1234, data),
            geonet::DataConfirm::kAccepted);
  fix();
  ASSERT_EQ(btp.send_b(geonet::DataRequest::topologically_scoped(5), 3001, 0, data),
            geonet::DataConfirm::kAccepted);
  fix();
  const auto centre_lat = geonet::to_tenth_micro_degree(48.15);
  const auto centre_lon = geonet::to_tenth_micro_degree(-1.6);
  ASSERT_EQ(btp.send_b(geonet::DataRequest::geo_broadcast(
                           {geonet::AreaShape::kCircle, centre_lat, centre_lon, 300, 0, 0}),
                       3002, 7, data),
            geonet::DataConfirm::kAccepted);
  fix();
  ASSERT_EQ(btp.send_a(geonet::DataRequest::geo_broadcast(
                           {geonet::AreaShape::kRectangle, centre_lat, centre_lon, 400, 100, 30}),
                       3003, 40000, data),
            geonet::DataConfirm::kAccepted);
  fix();
  ASSERT_EQ(btp.send_b(geonet::DataRequest::geo_broadcast(
                           {geonet::AreaShape::kEllipse, centre_lat, centre_lon, 500, 250, 359}),
                       3004, 0, data),
            geonet::DataConfirm::kAccepted);
  ASSERT_EQ(link.sent().size(), 6u);

  // Field by field, in the order of kFields; empty where a packet type has no such field.
  const std::string mid = "02:11:22:33:44:55";
  auto pv = [&](int i) {
    return "0;5;" + mid + ";" + std::to_string(tst[i]) + ";481500000;-16000000;1;1389;2715;";
  };
  const std::vector<std::string> expected = {
      // beacon: LT 60 × 1 s, RHL 1, NH any, HT 1, PL 0, MHL 1
      "1;1;60;1;1;0;0x10;0;1;0;1;;" + pv(0) + ";;;;;;;;;",
      // SHB: LT 20 × 50 ms, BTP-B, HT 5/0, TC 2, PL 4 + 4
      "1;1;20;0;1;2;0x50;2;1;8;1;;" + pv(1) + ";;;;;;3000;0x1234;;",
      // TSB: RHL = MHL = 5, SN 0
      "1;1;60;1;5;2;0x51;0;1;8;5;0x0000;" + pv(2) + ";;;;;;3001;0x0000;;",
      // GBC circle: radius in distance a, SN 1
      "1;1;60;1;10;2;0x40;0;1;8;10;0x0001;" + pv(3) + "481500000;-16000000;300;;0;0;3002;0x0007;;",
      // GBC rectangle over BTP-A
      "1;1;60;1;10;1;0x41;0;1;8;10;0x0002;" + pv(4) +
          "481500000;-16000000;;400;100;30;;;3003;40000",
      // GBC ellipse
      "1;1;60;1;10;2;0x42;0;1;8;10;0x0003;" + pv(5) +
          "481500000;-16000000;;500;250;359;3004;0x0000;;",
  };
  EXPECT_EQ(lines(tshark(fields_args(), false)), expected);
  EXPECT_EQ(tshark(kProblemArgs, false), "") << "tshark reports malformed packets or expert info";
  // The expert summary (-z expert) agrees: no errors and no warnings.
  const std::string expert = tshark("-q -z expert", false);
  EXPECT_EQ(expert.find("Errors ("), std::string::npos) << expert;
  EXPECT_EQ(expert.find("Warns ("), std::string::npos) << expert;
}

TEST_F(TsharkTest, TheWarningCheckCatchesAMalformedFrame) {
  // Control for the test above: a GN packet whose payload length exceeds the frame.
  fix();
  ASSERT_EQ(btp.send_b(geonet::DataRequest::single_hop(), 3000, 0, Bytes{1, 2, 3, 4}),
            geonet::DataConfirm::kAccepted);
  Bytes bad = link.sent().back().payload;
  bad[9] = 40;  // PL
  pcap->write(rt.wall_now(), link::kBroadcastMac, link.address(), link::kEtherTypeGeoNetworking,
              bad);
  // The beacon and the SHB are fine; only the frame written by hand is reported.
  const std::string bad_frame = std::to_string(link.sent().size() + 1);
  EXPECT_EQ(tshark(kProblemArgs, false).substr(0, bad_frame.size() + 1), bad_frame + "\t");
  const std::string expert = tshark("-q -z expert", false);
  EXPECT_NE(expert.find("Errors ("), std::string::npos) << expert;
  EXPECT_NE(expert.find("Bogus GeoNetworking length"), std::string::npos) << expert;
}

}  // namespace
}  // namespace tb::its::btp
