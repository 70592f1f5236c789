#include <gtest/gtest.h>

#include <vector>

#include "its-station/btp/dispatcher.hpp"
#include "its-station/geonet/tests/router_fixture.hpp"
#include "its-station/link/test_link.hpp"
#include "its-station/security/tests/test_pki.hpp"

namespace tb::its::btp {
namespace {

using namespace std::chrono_literals;
using geonet::testing::at;
using geonet::testing::mac;
using Bytes = std::vector<std::uint8_t>;

TEST(BtpHeader, BtpBIsDestinationPortThenPortInfoBigEndian) {
  // 07 d1 = 2001 (CAM), 12 34 = destination port info.
  const Bytes golden = {0x07, 0xd1, 0x12, 0x34, 0xaa};
  auto h = parse_header_b(golden);
  ASSERT_TRUE(h);
  EXPECT_EQ(*h, (HeaderB{kPortCam, 0x1234}));
  Bytes out(4);
  ByteWriter w{out};
  write_header(w, HeaderB{kPortCam, 0x1234});
  EXPECT_EQ(out, Bytes(golden.begin(), golden.begin() + 4));
}

TEST(BtpHeader, BtpAIsDestinationPortThenSourcePort) {
  const Bytes golden = {0x07, 0xd2, 0xc3, 0x50};  // 2002, 50000
  auto h = parse_header_a(golden);
  ASSERT_TRUE(h);
  EXPECT_EQ(*h, (HeaderA{kPortDenm, 50000}));
  Bytes out(4);
  ByteWriter w{out};
  write_header(w, *h);
  EXPECT_EQ(out, golden);
}

TEST(BtpHeader, TruncatedHeadersAreErrors) {
  for (std::size_t n = 0; n < 4; ++n) {
    const Bytes b(n, 0x07);
    EXPECT_EQ(parse_header_a(b).error(), ParseError::kTruncatedHeader);
    EXPECT_EQ(parse_header_b(b).error(), ParseError::kTruncatedHeader);
  }
  EXPECT_EQ(to_string(ParseError::kTruncatedHeader), "BTP header shorter than 4 bytes");
}

// Two stations whose links are wired together by hand: what A sends, the test hands to B.
class BtpPair : public ::testing::Test {
 protected:
  BtpPair() {
    pos_a.set({rt.wall_now(), at(0, 0).latitude_deg, at(0, 0).longitude_deg, 10.0, 0.0, true});
    pos_b.set({rt.wall_now(), at(50, 0).latitude_deg, at(50, 0).longitude_deg, 0.0, 0.0, true});
    btp_b.set_drop_hook([this](DropReason r) { drops.push_back(r); });
  }
  void carry_last_frame() {
    ASSERT_FALSE(link_a.sent().empty());
    const auto& f = link_a.sent().back();
    link_b.inject(mac(1), f.destination, f.ethertype, f.payload, rt.wall_now());
  }

  clock::ManualRuntime rt;
  link::TestLink link_a{mac(1)}, link_b{mac(2)};
  geonet::StaticPositionProvider pos_a, pos_b;
  geonet::Router router_a{rt, link_a, pos_a}, router_b{rt, link_b, pos_b};
  Dispatcher btp_a{router_a}, btp_b{router_b};
  std::vector<DropReason> drops;
};

TEST_F(BtpPair, CamOverShbReachesThePort2001Handler) {
  std::vector<Bytes> got;
  std::optional<Indication> ind;
  geonet::DataIndication gn_copy;
  ASSERT_TRUE(btp_b.register_port(kPortCam, [&](const Indication& i, auto payload) {
    got.emplace_back(payload.begin(), payload.end());
    ind = i;
    gn_copy = *i.gn;
  }));
  EXPECT_FALSE(btp_b.register_port(kPortCam, [](const Indication&, auto) {}));

  const Bytes cam = {0x02, 0x02, 0x00, 0x00, 0x00, 0x01};
  ASSERT_EQ(btp_a.send_b(geonet::DataRequest::single_hop(), kPortCam, 0, cam),
            geonet::DataConfirm::kAccepted);
  auto p = geonet::parse_packet(link_a.sent().back().payload);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->common.next_header, geonet::UpperProtocol::kBtpB);
  EXPECT_EQ(Bytes(p->payload.begin(), p->payload.begin() + 4), (Bytes{0x07, 0xd1, 0x00, 0x00}));

  carry_last_frame();
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0], cam);
  EXPECT_EQ(ind->type, geonet::UpperProtocol::kBtpB);
  EXPECT_EQ(ind->destination_port, kPortCam);
  EXPECT_EQ(ind->destination_port_info, 0);
  EXPECT_FALSE(ind->source_port);
  EXPECT_EQ(gn_copy.packet_type, geonet::PacketType::kSingleHopBroadcast);
  EXPECT_EQ(gn_copy.source.mid, mac(1));
  EXPECT_EQ(gn_copy.source_position.speed, 1000);
  EXPECT_EQ(btp_b.stats().delivered, 1u);
}

TEST_F(BtpPair, DenmOverGeoBroadcastWithBtpAReachesPort2002WithItsSourcePort) {
  std::optional<Indication> ind;
  std::optional<geonet::GeoArea> area;
  btp_b.register_port(kPortDenm, [&](const Indication& i, auto) {
    ind = i;
    area = i.gn->destination_area;
  });
  const auto target = geonet::testing::circle_at(at(0, 0), 500);
  ASSERT_EQ(btp_a.send_a(geonet::DataRequest::geo_broadcast(target), kPortDenm, 40001, Bytes{1}),
            geonet::DataConfirm::kAccepted);
  carry_last_frame();
  ASSERT_TRUE(ind);
  EXPECT_EQ(ind->type, geonet::UpperProtocol::kBtpA);
  EXPECT_EQ(ind->source_port, 40001);
  EXPECT_FALSE(ind->destination_port_info);
  EXPECT_EQ(area, target);
}

TEST_F(BtpPair, UnknownPortsShortHeadersAndNonBtpPayloadsAreDropped) {
  int calls = 0;
  btp_b.register_port(kPortCam, [&](const Indication&, auto) { ++calls; });
  btp_a.send_b(geonet::DataRequest::single_hop(), 2003, 0, Bytes{1});
  carry_last_frame();
  rt.advance(1ms);
  pos_a.set({rt.wall_now(), at(0, 0).latitude_deg, at(0, 0).longitude_deg, 10.0, 0.0, true});
  auto req = geonet::DataRequest::single_hop();
  req.upper_protocol = geonet::UpperProtocol::kBtpB;
  router_a.request(req, Bytes{0x07, 0xd1});  // a BTP-B header cut short
  carry_last_frame();
  rt.advance(1ms);
  pos_a.set({rt.wall_now(), at(0, 0).latitude_deg, at(0, 0).longitude_deg, 10.0, 0.0, true});
  req.upper_protocol = geonet::UpperProtocol::kIpv6;
  router_a.request(req, Bytes{0x07, 0xd1, 0, 0});
  carry_last_frame();
  EXPECT_EQ(calls, 0);
  EXPECT_EQ(drops, (std::vector{DropReason::kNoPortHandler, DropReason::kTruncatedHeader,
                                DropReason::kNotBtp}));
  btp_b.unregister_port(kPortCam);
  EXPECT_TRUE(btp_b.register_port(kPortCam, [](const Indication&, auto) {}));
}

TEST_F(BtpPair, OversizedPayloadIsRefusedBeforeTheRouter) {
  EXPECT_EQ(btp_a.send_b(geonet::DataRequest::single_hop(), kPortCam, 0, Bytes(1497)),
            geonet::DataConfirm::kMaxSduSizeExceeded);
  EXPECT_EQ(btp_a.send_b(geonet::DataRequest::single_hop(), kPortCam, 0, Bytes(1395)),
            geonet::DataConfirm::kMaxSduSizeExceeded);  // 1399 > itsGnMaxSduSize
  EXPECT_EQ(btp_a.send_b(geonet::DataRequest::single_hop(), kPortCam, 0, Bytes(1394)),
            geonet::DataConfirm::kAccepted);
}

TEST_F(BtpPair, ASecuredPacketMustBeSignedForItsPortsService) {
  // A payload for the CAM port signed for DENM (or the other way round) would pass verification
  // under permissions that are not the CAM's: dropped.
  security::testing::TestPki pki{rt.wall_now()};
  auto entity_a = pki.entity(security::SecurityMode::kSigned);
  auto entity_b = pki.entity(security::SecurityMode::kSigned);
  router_a.set_security(entity_a.get());
  router_b.set_security(entity_b.get());
  std::vector<std::uint64_t> cams;
  btp_b.register_port(kPortCam, [&](const Indication& i, auto) { cams.push_back(i.gn->its_aid); });
  ASSERT_EQ(btp_a.send_b(geonet::DataRequest::single_hop(), kPortCam, 0, Bytes{2, 2, 0}),
            geonet::DataConfirm::kAccepted);
  carry_last_frame();
  auto as_denm = geonet::DataRequest::single_hop();
  as_denm.its_aid = 37;
  rt.advance(1ms);
  ASSERT_EQ(btp_a.send_b(as_denm, kPortCam, 0, Bytes{2, 2, 1}), geonet::DataConfirm::kAccepted);
  carry_last_frame();
  EXPECT_EQ(cams, std::vector<std::uint64_t>{36});
  EXPECT_EQ(drops, std::vector{DropReason::kItsAidMismatch});
  EXPECT_EQ(its_aid_of(kPortDenm), 37u);
  EXPECT_EQ(its_aid_of(kPortMapem), 138u);   // TS 102 965 RLT
  EXPECT_EQ(its_aid_of(kPortSpatem), 137u);  // TLM
  EXPECT_EQ(its_aid_of(2005), 0u);
  router_a.set_security(nullptr);
  router_b.set_security(nullptr);
}

}  // namespace
}  // namespace tb::its::btp
