// The router with a security entity: secured packets out (basic header next header 2) and in,
// the modes' handling of what fails verification and of unsecured packets.

#include <gtest/gtest.h>

#include <memory>

#include "its-station/geonet/router.hpp"
#include "its-station/geonet/tests/router_fixture.hpp"
#include "its-station/link/test_link.hpp"
#include "its-station/security/pki.hpp"
#include "its-station/security/time.hpp"

namespace tb::its::geonet {
namespace {

using namespace std::chrono_literals;
using namespace testing;
namespace sec = security;

struct Authority {
  clock::WallTime now;
  sec::Time32 start = sec::to_time32(now) - 3600;
  sec::EcKey root_key = sec::EcKey::generate(sec::EccCurve::kNistP256);
  sec::EcKey aa_key = sec::EcKey::generate(sec::EccCurve::kNistP256);
  sec::Certificate root = sec::make_root(root_key, "root", {start, sec::DurationUnit::kHours, 100});
  sec::Certificate aa =
      sec::make_authority(aa_key, "aa", {start, sec::DurationUnit::kHours, 100}, root, root_key);
  std::unique_ptr<sec::SecurityEntity> entity(sec::SecurityMode mode) {
    sec::EcKey k = sec::EcKey::generate(sec::EccCurve::kNistP256);
    sec::Certificate at = sec::make_ticket(k, {start, sec::DurationUnit::kHours, 10}, aa, aa_key);
    sec::Verifier v({root});
    EXPECT_EQ(v.add_authority(aa, sec::to_time64(now)), sec::VerifyResult::kOk);
    return std::make_unique<sec::SecurityEntity>(mode, sec::Signer(std::move(at), std::move(k), aa),
                                                 std::move(v));
  }
};

struct Station {
  Station(clock::ManualRuntime& rt, std::uint8_t id, std::unique_ptr<sec::SecurityEntity> e)
      : link(mac(id)), entity(std::move(e)) {
    position.set({rt.wall_now(), kOriginLat, kOriginLon, 10.0, 90.0, true});
    RouterConfig cfg;
    cfg.beacon_interval = 1h;  // no beacons in the way
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
  EXPECT_EQ(strict.drops, (std::vector{DropReason::kSecurity, DropReason::kSecurity}));
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

}  // namespace
}  // namespace tb::its::geonet
