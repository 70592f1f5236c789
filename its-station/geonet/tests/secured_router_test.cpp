// The router with a security entity: secured packets out (basic header next header 2) and in,
// the modes' handling of what fails verification and of unsecured packets.

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "its-station/geonet/router.hpp"
#include "its-station/geonet/tests/router_fixture.hpp"
#include "its-station/link/test_link.hpp"
#include "its-station/security/pki.hpp"
#include "its-station/security/tests/test_pki.hpp"
#include "its-station/security/time.hpp"

namespace tb::its::geonet {
namespace {

using namespace std::chrono_literals;
using namespace testing;
namespace sec = security;

using Authority = sec::testing::TestPki;

RouterConfig no_beacons() {
  RouterConfig cfg;
  cfg.beacon_interval = 1h;  // no beacons in the way
  return cfg;
}

struct Station {
  Station(clock::ManualRuntime& rt, std::uint8_t id, std::unique_ptr<sec::SecurityEntity> e,
          RouterConfig cfg = no_beacons(), GeoPoint where = {kOriginLat, kOriginLon})
      : link(mac(id)), entity(std::move(e)) {
    position.set({rt.wall_now(), where.latitude_deg, where.longitude_deg, 10.0, 90.0, true});
    router = std::make_unique<Router>(rt, link, position, cfg);
    router->set_security(entity.get());
    router->set_indication_handler([this](const DataIndication& ind, auto payload) {
      delivered.push_back({ind, Bytes(payload.begin(), payload.end())});
    });
    router->set_drop_hook([this](const DropEvent& e) { drops.push_back(e.reason); });
  }
  /// Sends a CAM-like SHB and returns its frame.
  Bytes send(const Bytes& payload, std::uint64_t its_aid = sec::kPsidCam) {
    auto req = DataRequest::single_hop();
    req.its_aid = its_aid;
    return send(req, payload);
  }
  /// Sends @p payload by @p req and returns its frame.
  Bytes send(DataRequest req, const Bytes& payload) {
    EXPECT_EQ(router->request(req, payload), DataConfirm::kAccepted);
    return link.sent().back().payload;
  }
  void receive(clock::ManualRuntime& rt, const Bytes& frame, std::uint8_t from) {
    link.inject(mac(from), link::kBroadcastMac, link::kEtherTypeGeoNetworking, frame,
                rt.wall_now());
  }

  link::TestLink link;
  StaticPositionProvider position;
  std::unique_ptr<sec::SecurityEntity> entity;
  std::unique_ptr<Router> router;
  std::vector<std::pair<DataIndication, Bytes>> delivered;
  std::vector<DropReason> drops;
};

const Bytes kBtpCam{0x07, 0xd1, 0x00, 0x00, 0x02, 0x02, 0x00, 0x00, 0x03, 0xe9};
const Bytes kBtpDenm{0x07, 0xd2, 0x00, 0x00, 0x02, 0x01, 0x00, 0x00, 0x03, 0xe9};

/// A DENM's GBC around the point 300 m east of the origin, 1 km in radius.
DataRequest denm_gbc() {
  auto req = DataRequest::geo_broadcast(circle_at(at(300, 0), 1000));
  req.its_aid = sec::kPsidDenm;
  return req;
}

/// The frame forwarded from @p received: the same octets but for the remaining hop limit.
void expect_forwarded_as_received(const Bytes& received, const Bytes& forwarded) {
  ASSERT_EQ(forwarded.size(), received.size());
  EXPECT_EQ(forwarded[0] & 0x0f, 2);  // still a secured packet
  EXPECT_EQ(forwarded[3], received[3] - 1);
  EXPECT_TRUE(std::equal(received.begin() + 4, received.end(), forwarded.begin() + 4))
      << "the signed part changed";
  EXPECT_TRUE(std::equal(received.begin(), received.begin() + 3, forwarded.begin()));
}

TEST(SecuredRouter, SignedShbGoesOutAsSecuredPacketAndIsDeliveredVerified) {
  clock::ManualRuntime rt;
  Authority pki{rt.wall_now()};
  Station a(rt, 1, pki.entity(sec::SecurityMode::kSigned));
  Station b(rt, 2, pki.entity(sec::SecurityMode::kSigned));
  const Bytes frame = a.send(kBtpCam);
  EXPECT_EQ(frame[0] & 0x0f, 2);  // basic header next header: secured packet
  auto d = sec::decode_data(std::span(frame).subspan(4));
  ASSERT_TRUE(d);
  EXPECT_EQ(d->signed_data.tbs.header.psid, sec::kPsidCam);
  // The signed payload is common header + SHB + the BTP payload: with the basic header (next
  // header common header) it is the unsecured packet.
  Bytes unwrapped(frame.begin(), frame.begin() + 4);
  unwrapped[0] = static_cast<std::uint8_t>((unwrapped[0] & 0xf0) | 1);
  unwrapped.insert(unwrapped.end(), d->signed_data.tbs.payload.data->begin(),
                   d->signed_data.tbs.payload.data->end());
  auto plain = parse_packet(unwrapped);
  ASSERT_TRUE(plain);
  EXPECT_EQ(Bytes(plain->payload.begin(), plain->payload.end()), kBtpCam);
  b.receive(rt, frame, 1);
  ASSERT_EQ(b.delivered.size(), 1u);
  EXPECT_EQ(b.delivered[0].second, kBtpCam);
  EXPECT_EQ(b.delivered[0].first.security_report, sec::VerifyResult::kOk);
  EXPECT_EQ(b.delivered[0].first.its_aid, sec::kPsidCam);
  EXPECT_EQ(b.router->stats().received, 1u);
  EXPECT_EQ(b.router->location_table().size(), 1u);
}

TEST(SecuredRouter, SignedStationDropsUnsecuredAndForeignPacketsPermissivePassesThem) {
  clock::ManualRuntime rt;
  Authority pki{rt.wall_now()};
  Authority foreign{rt.wall_now()};
  Station plain(rt, 1, nullptr);
  Station stranger(rt, 3, foreign.entity(sec::SecurityMode::kSigned));
  Station strict(rt, 2, pki.entity(sec::SecurityMode::kSigned));
  Station lax(rt, 4, pki.entity(sec::SecurityMode::kSignedPermissive));
  const Bytes unsecured = plain.send(kBtpCam);
  EXPECT_EQ(unsecured[0] & 0x0f, 1);
  const Bytes alien = stranger.send(kBtpCam);
  for (Station* s : {&strict, &lax}) {
    s->receive(rt, unsecured, 1);
    s->receive(rt, alien, 3);
  }
  EXPECT_TRUE(strict.delivered.empty());
  EXPECT_EQ(strict.drops, (std::vector{DropReason::kUnsecured, DropReason::kSecurity}));
  EXPECT_EQ(strict.entity->verifier().count(sec::VerifyResult::kUnknownIssuer), 1u);
  ASSERT_EQ(lax.delivered.size(), 2u);
  EXPECT_FALSE(lax.delivered[0].first.security_report);  // unsecured
  EXPECT_EQ(lax.delivered[1].first.security_report, sec::VerifyResult::kUnknownIssuer);
  EXPECT_EQ(lax.delivered[1].second, kBtpCam);
}

TEST(SecuredRouter, ModeNoneKeepsTodaysBehaviour) {
  clock::ManualRuntime rt;
  Authority pki{rt.wall_now()};
  Station none(rt, 1, pki.entity(sec::SecurityMode::kNone));
  Station signer(rt, 2, pki.entity(sec::SecurityMode::kSigned));
  EXPECT_EQ(none.send(kBtpCam)[0] & 0x0f, 1);
  none.receive(rt, signer.send(kBtpCam), 2);
  EXPECT_TRUE(none.delivered.empty());
  EXPECT_EQ(none.drops, std::vector{DropReason::kParseError});
}

TEST(SecuredRouter, SignedGbcIsForwardedAsReceivedAndVerifiesAtTheNextHop) {
  // Clause 9.3 / 10.3.11.3: the forwarder changes the basic header (RHL) only; a station two
  // hops from the source verifies the source's signature in the forwarded copy.
  clock::ManualRuntime rt;
  Authority pki{rt.wall_now()};
  RouterConfig simple = no_beacons();
  simple.area_forwarding = RouterConfig::AreaForwarding::kSimple;
  Station source(rt, 1, pki.entity(sec::SecurityMode::kSigned), simple);
  Station relay(rt, 2, pki.entity(sec::SecurityMode::kSigned), simple, at(300, 0));
  Station far(rt, 3, pki.entity(sec::SecurityMode::kSigned), simple, at(600, 0));
  const Bytes sent = source.send(denm_gbc(), kBtpDenm);
  ASSERT_EQ(sent[0] & 0x0f, 2);

  relay.receive(rt, sent, 1);
  ASSERT_EQ(relay.delivered.size(), 1u);
  EXPECT_EQ(relay.delivered[0].first.security_report, sec::VerifyResult::kOk);
  EXPECT_EQ(relay.delivered[0].first.its_aid, sec::kPsidDenm);
  EXPECT_EQ(relay.router->stats().forwarded, 1u);
  ASSERT_EQ(relay.link.sent().size(), 1u);
  const Bytes forwarded = relay.link.sent().back().payload;
  expect_forwarded_as_received(sent, forwarded);

  far.receive(rt, forwarded, 2);
  ASSERT_EQ(far.delivered.size(), 1u);
  EXPECT_EQ(far.delivered[0].first.security_report, sec::VerifyResult::kOk);
  EXPECT_EQ(far.delivered[0].second, kBtpDenm);
  EXPECT_EQ(far.delivered[0].first.sender, mac(2));  // the last forwarder
  EXPECT_EQ(far.delivered[0].first.source.mid, mac(1));
  EXPECT_EQ(far.delivered[0].first.remaining_hop_limit, sent[3] - 1);
  // The source hears its packet back, the relay the far station's copy: neither goes on.
  relay.receive(rt, far.link.sent().back().payload, 3);
  EXPECT_EQ(relay.router->stats().forwarded, 1u);
  EXPECT_EQ(relay.router->stats().dropped(DropReason::kDuplicate), 1u);
}

TEST(SecuredRouter, SignedGbcContendsAndGoesOutAsReceived) {
  clock::ManualRuntime rt;
  Authority pki{rt.wall_now()};
  Station source(rt, 1, pki.entity(sec::SecurityMode::kSigned));
  Station relay(rt, 2, pki.entity(sec::SecurityMode::kSigned), no_beacons(), at(300, 0));
  const Bytes sent = source.send(denm_gbc(), kBtpDenm);
  relay.receive(rt, sent, 1);
  EXPECT_EQ(relay.router->stats().cbf_buffered, 1u);
  EXPECT_TRUE(relay.link.sent().empty());
  rt.advance(RouterConfig{}.cbf_max_time);  // the contention timeout is at most this
  ASSERT_EQ(relay.link.sent().size(), 1u);
  expect_forwarded_as_received(sent, relay.link.sent().back().payload);
}

TEST(SecuredRouter, SignedTsbIsForwardedAsReceived) {
  clock::ManualRuntime rt;
  Authority pki{rt.wall_now()};
  Station source(rt, 1, pki.entity(sec::SecurityMode::kSigned));
  Station relay(rt, 2, pki.entity(sec::SecurityMode::kSigned));
  auto req = DataRequest::topologically_scoped(3);
  req.its_aid = sec::kPsidDenm;
  const Bytes sent = source.send(req, kBtpDenm);
  relay.receive(rt, sent, 1);
  ASSERT_EQ(relay.delivered.size(), 1u);
  ASSERT_EQ(relay.link.sent().size(), 1u);
  expect_forwarded_as_received(sent, relay.link.sent().back().payload);
}

TEST(SecuredRouter, AHeldPacketGoesOnWithItsOwnFrame) {
  // A CAM signed by a digest we do not know waits for the AT; when a later packet brings it,
  // the held CAM goes up with its own sender and receive time, not the later packet's.
  clock::ManualRuntime rt;
  Authority pki{rt.wall_now()};
  Station a(rt, 1, pki.entity(sec::SecurityMode::kSigned));
  Station b(rt, 2, pki.entity(sec::SecurityMode::kSigned));
  const Bytes with_at = a.send(Bytes{0x07, 0xd1, 0x00, 0x00, 0x01});
  rt.advance(100ms);
  const Bytes with_digest = a.send(Bytes{0x07, 0xd1, 0x00, 0x00, 0x02});
  const auto held_at = rt.wall_now();
  b.receive(rt, with_digest, 1);
  EXPECT_TRUE(b.delivered.empty());
  EXPECT_EQ(b.entity->held(), 1u);
  rt.advance(200ms);
  b.receive(rt, with_at, 9);  // the AT, from elsewhere (a forwarder, a replay)
  ASSERT_EQ(b.delivered.size(), 2u);
  EXPECT_EQ(b.delivered[0].second.back(), 0x01);
  EXPECT_EQ(b.delivered[0].first.sender, mac(9));
  EXPECT_EQ(b.delivered[1].second.back(), 0x02);
  EXPECT_EQ(b.delivered[1].first.sender, mac(1));
  EXPECT_EQ(b.delivered[1].first.rx_time, held_at);
  EXPECT_EQ(b.delivered[1].first.security_report, sec::VerifyResult::kOk);
  EXPECT_EQ(b.entity->held(), 0u);
}

TEST(SecuredRouter, BeaconsAreSignedForGnMgmtAndAStrictStationTakesNoOther) {
  clock::ManualRuntime rt;
  Authority pki{rt.wall_now()};
  RouterConfig beacons;
  beacons.beacon_max_jitter = 0ms;
  Station a(rt, 1, pki.entity(sec::SecurityMode::kSigned), beacons);
  Station old(rt, 5, pki.entity(sec::SecurityMode::kSigned, true), beacons);
  Station plain(rt, 3, nullptr, beacons);
  Station strict(rt, 2, pki.entity(sec::SecurityMode::kSigned));
  Station lax(rt, 4, pki.entity(sec::SecurityMode::kSignedPermissive));
  rt.advance(1ms);  // the first beacons go out after a jitter of 0
  ASSERT_EQ(a.link.sent().size(), 1u);
  const Bytes beacon = a.link.sent().back().payload;
  EXPECT_EQ(beacon[0] & 0x0f, 2);
  auto d = sec::decode_data(std::span(beacon).subspan(4));
  ASSERT_TRUE(d);
  EXPECT_EQ(d->signed_data.tbs.header.psid, sec::kPsidGnMgmt);
  EXPECT_TRUE(d->signed_data.tbs.header.generation_time);
  EXPECT_EQ(a.router->stats().beacons_unsigned, 0u);
  // An AT without GN-MGMT (an older its-pki's): the beacon goes out unsigned, counted.
  ASSERT_EQ(old.link.sent().size(), 1u);
  EXPECT_EQ(old.link.sent().back().payload[0] & 0x0f, 1);
  EXPECT_EQ(old.router->stats().beacons_unsigned, 1u);
  ASSERT_EQ(plain.link.sent().size(), 1u);
  const Bytes unsigned_beacon = plain.link.sent().back().payload;

  strict.receive(rt, beacon, 1);
  EXPECT_EQ(strict.entity->verifier().count(sec::VerifyResult::kOk), 1u);
  EXPECT_NE(strict.router->location_table().find(
                GnAddress{false, StationType::kUnknown, mac(1)}.mid_key(), rt.steady_now()),
            nullptr);
  strict.receive(rt, unsigned_beacon, 3);
  EXPECT_EQ(strict.drops, std::vector{DropReason::kUnsecured});
  EXPECT_EQ(strict.router->location_table().size(), 1u);
  lax.receive(rt, unsigned_beacon, 3);
  lax.receive(rt, beacon, 1);
  EXPECT_EQ(lax.router->location_table().size(), 2u);
  EXPECT_TRUE(lax.delivered.empty());  // beacons update the table, nothing goes up
}

TEST(SecuredRouter, ReplayedCamIsDroppedForwardedDenmCopyIsAGnDuplicate) {
  clock::ManualRuntime rt;
  Authority pki{rt.wall_now()};
  RouterConfig simple = no_beacons();
  simple.area_forwarding = RouterConfig::AreaForwarding::kSimple;
  Station a(rt, 1, pki.entity(sec::SecurityMode::kSigned), simple);
  Station b(rt, 2, pki.entity(sec::SecurityMode::kSigned), simple, at(300, 0));
  // A CAM recorded and played back 0.5 s later: within the window, so only replay detection
  // (the same signer and generationTime) stops it.
  const Bytes cam = a.send(kBtpCam);
  b.receive(rt, cam, 1);
  rt.advance(500ms);
  b.receive(rt, cam, 1);
  ASSERT_EQ(b.delivered.size(), 1u);
  EXPECT_EQ(b.drops, std::vector{DropReason::kSecurity});
  EXPECT_EQ(b.entity->verifier().count(sec::VerifyResult::kReplay), 1u);
  // 2.5 s after it was sent the CAM is out of the window (and forgotten by the replay table).
  rt.advance(2s);
  b.receive(rt, cam, 1);
  EXPECT_EQ(b.entity->verifier().count(sec::VerifyResult::kGenerationTimeOutOfWindow), 1u);

  // A DENM's copy forwarded back by a neighbour is the same signed packet: it still reaches
  // GeoNetworking, whose duplicate detection drops it (not a security drop).
  const Bytes denm = a.send(denm_gbc(), kBtpDenm);
  b.receive(rt, denm, 1);
  ASSERT_EQ(b.delivered.size(), 2u);
  Bytes copy = denm;
  copy[3] = static_cast<std::uint8_t>(copy[3] - 1);  // as a forwarder sends it (RHL)
  b.drops.clear();
  b.receive(rt, copy, 3);
  EXPECT_EQ(b.delivered.size(), 2u);
  EXPECT_EQ(b.drops, std::vector{DropReason::kDuplicate});
  EXPECT_EQ(b.entity->verifier().count(sec::VerifyResult::kReplay), 1u);
}

}  // namespace
}  // namespace tb::its::geonet
