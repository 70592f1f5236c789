#include <gtest/gtest.h>

#include "its-station/facilities/cdd_convert.hpp"
#include "its-station/facilities/its_time.hpp"
#include "its-station/facilities/ldm.hpp"

namespace tb::its::facilities {
namespace {

using namespace std::chrono_literals;

messages::Cam cam_from(messages::StationID id, double lat, double lon, double speed) {
  messages::Cam c;
  c.header.stationID = id;
  auto& rp = c.cam.camParameters.basicContainer.referencePosition;
  rp.latitude = cdd::latitude(lat);
  rp.longitude = cdd::longitude(lon);
  c.cam.camParameters.highFrequencyContainer.speed.speedValue = cdd::speed_value(speed);
  c.cam.camParameters.highFrequencyContainer.heading.headingValue = 450;
  return c;
}

messages::Denm denm_from(clock::ManualRuntime& rt, messages::StationID origin, int seq,
                         std::int64_t reference_offset_ms) {
  messages::Denm d;
  d.header.stationID = origin;
  auto& mc = d.denm.management;
  mc.actionID = {origin, static_cast<messages::SequenceNumber>(seq)};
  const auto now = timestamp_its(rt.wall_now());
  mc.detectionTime = static_cast<messages::TimestampIts>(now);
  mc.referenceTime = static_cast<messages::TimestampIts>(now + reference_offset_ms);
  mc.validityDuration = 5;
  return d;
}

TEST(Ldm, NeighboursKeepHistoryAndExpire) {
  clock::ManualRuntime rt;
  Ldm ldm(rt, LdmConfig{3000ms, 3, 50ms});
  std::vector<messages::StationID> gone;
  ldm.on_neighbour_gone([&](messages::StationID id) { gone.push_back(id); });
  for (int i = 0; i < 5; ++i) {
    ldm.add_cam(cam_from(7, 48.0 + i * 1e-5, 11.0, 10.0 + i), rt.wall_now());
    rt.advance(100ms);
  }
  ldm.add_cam(cam_from(8, 48.1, 11.1, 0.0), rt.wall_now());
  const auto* n = ldm.neighbour(7);
  ASSERT_NE(n, nullptr);
  EXPECT_EQ(n->history.size(), 3u);
  EXPECT_NEAR(*n->latest().speed_mps, 14.0, 1e-9);
  EXPECT_NEAR(n->latest().latitude_deg, 48.00004, 1e-9);
  EXPECT_NEAR(*n->latest().heading_deg, 45.0, 1e-9);
  EXPECT_EQ(ldm.neighbours().size(), 2u);
  // 7 was last heard at 400 ms, 8 at 500 ms; sweeps every 50 ms forget each 3 s later.
  rt.advance(2950ms);  // 3450 ms
  EXPECT_EQ(ldm.neighbour(7), nullptr);
  EXPECT_NE(ldm.neighbour(8), nullptr);
  rt.advance(100ms);
  EXPECT_TRUE(ldm.neighbours().empty());
  EXPECT_EQ(gone, (std::vector<messages::StationID>{7, 8}));
}

TEST(Ldm, CamWithoutPositionIsIgnored) {
  clock::ManualRuntime rt;
  Ldm ldm(rt);
  messages::Cam c;
  c.header.stationID = 9;
  ldm.add_cam(c, rt.wall_now());
  EXPECT_TRUE(ldm.neighbours().empty());
}

TEST(Ldm, ReverseDriveGivesNegativeSpeed) {
  clock::ManualRuntime rt;
  Ldm ldm(rt);
  auto c = cam_from(7, 48.0, 11.0, 2.0);
  c.cam.camParameters.highFrequencyContainer.driveDirection = messages::DriveDirection::backward;
  ldm.add_cam(c, rt.wall_now());
  EXPECT_NEAR(*ldm.neighbour(7)->latest().speed_mps, -2.0, 1e-9);
}

TEST(Ldm, DenmReceivingRules) {
  clock::ManualRuntime rt;
  Ldm ldm(rt);
  EXPECT_EQ(ldm.add_denm(denm_from(rt, 5, 1, 0)), DenmOutcome::kNew);
  EXPECT_EQ(ldm.add_denm(denm_from(rt, 5, 1, 0)), DenmOutcome::kRepetition);
  EXPECT_EQ(ldm.add_denm(denm_from(rt, 5, 1, -10)), DenmOutcome::kOutdated);
  EXPECT_EQ(ldm.add_denm(denm_from(rt, 5, 1, 10)), DenmOutcome::kUpdate);
  EXPECT_EQ(ldm.add_denm(denm_from(rt, 5, 2, 0)), DenmOutcome::kNew);  // another event
  EXPECT_EQ(ldm.active_events().size(), 2u);

  auto term = denm_from(rt, 5, 1, 20);
  term.denm.management.termination = messages::Termination::isCancellation;
  EXPECT_EQ(ldm.add_denm(term), DenmOutcome::kTerminated);
  EXPECT_EQ(ldm.event({5, 1}), nullptr);
  // A late repetition of the event (older reference time) cannot bring it back.
  EXPECT_EQ(ldm.add_denm(denm_from(rt, 5, 1, 10)), DenmOutcome::kOutdated);
  EXPECT_EQ(ldm.add_denm(denm_from(rt, 5, 1, 30)), DenmOutcome::kOutdated);
  auto unknown = denm_from(rt, 6, 1, 0);
  unknown.denm.management.termination = messages::Termination::isNegation;
  EXPECT_EQ(ldm.add_denm(unknown), DenmOutcome::kUnknownTermination);
  EXPECT_EQ(ldm.active_events().size(), 1u);

  auto old = denm_from(rt, 5, 3, 0);
  old.denm.management.detectionTime -= 6000;  // validity 5 s ended a second ago
  EXPECT_EQ(ldm.add_denm(old), DenmOutcome::kExpired);

  rt.advance(5s);
  EXPECT_TRUE(ldm.active_events().empty());
}

}  // namespace
}  // namespace tb::its::facilities
