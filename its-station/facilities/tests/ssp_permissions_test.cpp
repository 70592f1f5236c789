// Signed CAMs and DENMs against their signer's SSP (TS 103 900 6.2.2.2, TS 103 831 6.2.2.2).

#include "its-station/facilities/ssp_permissions.hpp"

#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "its-station/messages/tests/samples.hpp"

namespace tb::its::facilities {
namespace {

using Bytes = std::vector<std::uint8_t>;
namespace m = messages;

TEST(CamPermissions, AnOrdinaryCamNeedsNoBitNotEvenAnSsp) {
  EXPECT_FALSE(cam_not_permitted(m::samples::cam_hf(), Bytes{}));
  EXPECT_FALSE(cam_not_permitted(m::samples::cam_lf(), Bytes{0x01, 0x00, 0x00}));
}

TEST(CamPermissions, EachContainerNeedsItsBitAndNoOther) {
  // samples::cams_special_vehicle(): one CAM per container, in CHOICE order; the bit of each
  // (its fields' bits aside, below).
  const std::vector<SspBit> bits{cam_ssp::kPublicTransport, cam_ssp::kSpecialTransport,
                                 cam_ssp::kDangerousGoods,  cam_ssp::kRoadwork,
                                 cam_ssp::kRescue,          cam_ssp::kEmergency,
                                 cam_ssp::kSafetyCar};
  const auto cams = m::samples::cams_special_vehicle();
  ASSERT_EQ(cams.size(), bits.size());
  for (std::size_t i = 0; i < cams.size(); ++i) {
    SCOPED_TRACE(bits[i].name);
    const auto none = cam_not_permitted(cams[i], Bytes{0x01, 0x00, 0x00});
    ASSERT_TRUE(none);
    EXPECT_EQ(none->name, bits[i].name);
    // Every bit but this container's: still refused, for this container.
    Bytes all_but{0x01, 0xff, 0xfc};
    all_but[bits[i].octet] &= static_cast<std::uint8_t>(~bits[i].mask);
    const auto other = cam_not_permitted(cams[i], all_but);
    ASSERT_TRUE(other);
    EXPECT_EQ(other->name, bits[i].name);
  }
  for (const auto& cam : cams)
    EXPECT_FALSE(cam_not_permitted(cam, Bytes{0x01, 0xff, 0xfc}));  // Vanetza's full CAM SSP
}

TEST(CamPermissions, FieldsNeedTheirOwnBits) {
  const auto cams = m::samples::cams_special_vehicle();
  // Roadworks with closedLanes: roadwork alone is not enough.
  auto r = cam_not_permitted(cams[3], Bytes{0x01, 0x08, 0x00});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->name, "closedLanes");
  EXPECT_FALSE(cam_not_permitted(cams[3], Bytes{0x01, 0x08, 0x80}));
  // Emergency with emergencyPriority requestForRightOfWay (0b01).
  r = cam_not_permitted(cams[5], Bytes{0x01, 0x02, 0x00});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->name, "requestForRightOfWay");
  EXPECT_FALSE(cam_not_permitted(cams[5], Bytes{0x01, 0x02, 0x40}));
  m::Cam crossing = cams[5];
  std::get<m::EmergencyContainer>(*crossing.cam.camParameters.specialVehicleContainer)
      .emergencyPriority = 0b10;
  r = cam_not_permitted(crossing, Bytes{0x01, 0x02, 0x40});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->name, "requestForFreeCrossingAtATrafficLight");
  // Safety car: passToLeft needs no traffic-rule bit, its speedLimit (80) does.
  r = cam_not_permitted(cams[6], Bytes{0x01, 0x01, 0x00});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->name, "speedLimit");
  m::Cam no_passing = cams[6];
  auto& sc = std::get<m::SafetyCarContainer>(*no_passing.cam.camParameters.specialVehicleContainer);
  sc.trafficRule = m::TrafficRule::noPassing;
  sc.speedLimit.reset();
  r = cam_not_permitted(no_passing, Bytes{0x01, 0x01, 0x08});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->name, "noPassing");
  sc.trafficRule = m::TrafficRule::noPassingForTrucks;
  r = cam_not_permitted(no_passing, Bytes{0x01, 0x01, 0x10});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->name, "noPassingForTrucks");
  EXPECT_FALSE(cam_not_permitted(no_passing, Bytes{0x01, 0x01, 0x08}));
}

TEST(CamPermissions, ATruncatedSspPermitsNothingBeyondIt) {
  const auto cams = m::samples::cams_special_vehicle();
  EXPECT_TRUE(cam_not_permitted(cams[5], Bytes{0x01}));
  EXPECT_TRUE(cam_not_permitted(cams[3], Bytes{0x01, 0x08}));  // closedLanes is in octet 2
}

TEST(DenmPermissions, TheCauseCodeNeedsItsBit) {
  m::Denm denm = m::samples::denm_collision_risk();
  ASSERT_TRUE(denm.denm.situation);
  ASSERT_EQ(denm.denm.situation->eventType.causeCode, 97);
  // its-pki's DENM SSP (every version-1 bit), and Vanetza's: permitted.
  EXPECT_FALSE(denm_not_permitted(denm, Bytes{0x01, 0xff, 0xff, 0xff}));
  // Everything but collisionRisk (octet 3, 0x04).
  const auto r = denm_not_permitted(denm, Bytes{0x01, 0xff, 0xff, 0xfb});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->name, "collisionRisk");
  EXPECT_TRUE(denm_not_permitted(denm, Bytes{0x01, 0xff}));  // too short: nothing in octet 3
  // Version 2's fourth octet: railwayLevelCrossing (100) has no version-1 bit.
  denm.denm.situation->eventType.causeCode = 100;
  EXPECT_TRUE(denm_not_permitted(denm, Bytes{0x01, 0xff, 0xff, 0xff}));
  EXPECT_FALSE(denm_not_permitted(denm, Bytes{0x02, 0x00, 0x00, 0x00, 0x10}));
  // A cause code no bit is for (0, reserved) is permitted by none; a cancellation (no
  // situation) needs none.
  denm.denm.situation->eventType.causeCode = 0;
  EXPECT_TRUE(denm_not_permitted(denm, Bytes{0x02, 0xff, 0xff, 0xff, 0xff}));
  denm.denm.situation.reset();
  EXPECT_FALSE(denm_not_permitted(denm, Bytes{}));
  // Every bit is one cause code's, and no two codes share one.
  std::set<std::pair<int, int>> seen;
  int codes = 0;
  for (int c = 0; c < 256; ++c) {
    if (const auto b = denm_ssp_bit(static_cast<m::CauseCodeType>(c))) {
      ++codes;
      EXPECT_TRUE(seen.insert({b->octet, b->mask}).second) << c;
    }
  }
  EXPECT_EQ(codes, 28);
}

}  // namespace
}  // namespace tb::its::facilities
