#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "its-station/facilities/cdd_convert.hpp"
#include "its-station/facilities/its_time.hpp"
#include "its-station/facilities/ldm.hpp"

namespace tb::its::facilities {
namespace {

using namespace std::chrono_literals;

std::shared_ptr<messages::Cam> cam_from(messages::StationID id, double lat, double lon,
                                        double speed) {
  auto shared = std::make_shared<messages::Cam>();
  messages::Cam& c = *shared;
  c.header.stationID = id;
  auto& rp = c.cam.camParameters.basicContainer.referencePosition;
  rp.latitude = cdd::latitude(lat);
  rp.longitude = cdd::longitude(lon);
  (*messages::vehicle_hf(c.cam.camParameters)).speed.speedValue = cdd::speed_value(speed);
  (*messages::vehicle_hf(c.cam.camParameters)).heading.headingValue = 450;
  return shared;
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

// Expiry goes by the latest CAM of each neighbour, whatever the order they were first heard in.
TEST(Ldm, ANeighbourHeardAgainOutlivesOneHeardAfterIt) {
  clock::ManualRuntime rt;
  Ldm ldm(rt, LdmConfig{3000ms, 3, 50ms});
  std::vector<messages::StationID> gone;
  ldm.on_neighbour_gone([&](messages::StationID id) { gone.push_back(id); });
  ldm.add_cam(cam_from(7, 48.0, 11.0, 1.0), rt.wall_now());  // 0 ms
  rt.advance(100ms);
  ldm.add_cam(cam_from(8, 48.1, 11.0, 1.0), rt.wall_now());  // 100 ms
  rt.advance(100ms);
  ldm.add_cam(cam_from(9, 48.2, 11.0, 1.0), rt.wall_now());  // 200 ms
  rt.advance(800ms);
  ldm.add_cam(cam_from(7, 48.0, 11.0, 1.0), rt.wall_now());  // 1000 ms
  rt.advance(2150ms);                                        // 3150 ms
  EXPECT_EQ(gone, (std::vector<messages::StationID>{8}));
  EXPECT_NE(ldm.neighbour(7), nullptr);
  EXPECT_NE(ldm.neighbour(9), nullptr);
  rt.advance(100ms);  // 3250 ms
  EXPECT_EQ(gone, (std::vector<messages::StationID>{8, 9}));
  rt.advance(800ms);  // 4050 ms
  EXPECT_EQ(gone, (std::vector<messages::StationID>{8, 9, 7}));
  EXPECT_TRUE(ldm.neighbours().empty());
  // Heard again after it was forgotten: a new neighbour, forgotten again in its turn.
  ldm.add_cam(cam_from(8, 48.1, 11.0, 1.0), rt.wall_now());
  EXPECT_NE(ldm.neighbour(8), nullptr);
  rt.advance(3100ms);
  EXPECT_EQ(gone, (std::vector<messages::StationID>{8, 9, 7, 8}));
}

// The neighbour keeps the CAM handed over, not a copy of it.
TEST(Ldm, KeepsTheReceivedCamItself) {
  clock::ManualRuntime rt;
  Ldm ldm(rt);
  const auto first = cam_from(7, 48.0, 11.0, 1.0);
  ldm.add_cam(first, rt.wall_now());
  EXPECT_EQ(ldm.neighbour(7)->last_cam.get(), first.get());
  const auto second = cam_from(7, 48.0, 11.0, 2.0);
  ldm.add_cam(second, rt.wall_now());
  EXPECT_EQ(ldm.neighbour(7)->last_cam.get(), second.get());
  EXPECT_EQ(first.use_count(), 1) << "the older CAM is let go";
}

// Two LDMs sharing a SenderIndex (station-host's stations) find their neighbours through it,
// each its own, forget them as they would without it, and do not trust a wrong row.
TEST(Ldm, ASharedSenderIndexFindsEachLdmsOwnNeighbour) {
  clock::ManualRuntime rt;
  SenderIndex index;
  Ldm a(rt, LdmConfig{3000ms, 3, 50ms});
  Ldm b(rt, LdmConfig{3000ms, 3, 50ms});
  a.share_sender_index(index);
  b.share_sender_index(index);
  const auto row7 = index.row(7);
  const auto row8 = index.row(8);
  for (int i = 0; i < 4; ++i) {
    a.add_cam(cam_from(7, 48.0, 11.0, 10.0 + i), rt.wall_now(), row7);
    b.add_cam(cam_from(7, 48.0, 11.0, 20.0 + i), rt.wall_now(), row7);
    rt.advance(100ms);
  }
  EXPECT_EQ(a.neighbours().size(), 1u);
  EXPECT_EQ(a.neighbour(7)->history.size(), 3u);
  EXPECT_NEAR(*a.neighbour(7)->latest().speed_mps, 13.0, 1e-9);
  EXPECT_NEAR(*b.neighbour(7)->latest().speed_mps, 23.0, 1e-9);
  // A CAM of 8 said to be from row 7: the row's neighbour is 7, so 8 is looked up by its id.
  a.add_cam(cam_from(8, 48.1, 11.0, 5.0), rt.wall_now(), row7);
  ASSERT_NE(a.neighbour(8), nullptr);
  EXPECT_NEAR(*a.neighbour(7)->latest().speed_mps, 13.0, 1e-9) << "7 untouched";
  a.add_cam(cam_from(8, 48.1, 11.0, 6.0), rt.wall_now(), row8);
  EXPECT_NEAR(*a.neighbour(8)->latest().speed_mps, 6.0, 1e-9);
  EXPECT_EQ(a.neighbours().size(), 2u);
  // 7 forgotten (last heard at 300 ms), then heard again through its row: a new neighbour,
  // not the one that went.
  rt.advance(3100ms);
  EXPECT_EQ(a.neighbour(7), nullptr);
  EXPECT_EQ(b.neighbour(7), nullptr);
  a.add_cam(cam_from(7, 48.0, 11.0, 30.0), rt.wall_now(), row7);
  ASSERT_NE(a.neighbour(7), nullptr);
  EXPECT_EQ(a.neighbour(7)->history.size(), 1u);
  EXPECT_NEAR(*a.neighbour(7)->latest().speed_mps, 30.0, 1e-9);
  EXPECT_EQ(b.neighbour(7), nullptr);
}

TEST(Ldm, CamWithoutPositionIsIgnored) {
  clock::ManualRuntime rt;
  Ldm ldm(rt);
  auto c = std::make_shared<messages::Cam>();
  c->header.stationID = 9;
  ldm.add_cam(c, rt.wall_now());
  EXPECT_TRUE(ldm.neighbours().empty());
}

TEST(Ldm, ReverseDriveGivesNegativeSpeed) {
  clock::ManualRuntime rt;
  Ldm ldm(rt);
  auto c = cam_from(7, 48.0, 11.0, 2.0);
  (*messages::vehicle_hf(c->cam.camParameters)).driveDirection = messages::DriveDirection::backward;
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
  EXPECT_EQ(ldm.add_denm(term), DenmOutcome::kCancelled);
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

// The rules, one at a time, as TS 102 869-2 TP/DEN/MSRV checks them.
TEST(Ldm, DenmVersionsAreOrderedByReferenceThenDetectionTime) {
  clock::ManualRuntime rt;
  Ldm ldm(rt);
  std::vector<DenmOutcome> heard;
  ldm.on_event([&](const Event&, DenmOutcome o) { heard.push_back(o); });
  auto v = denm_from(rt, 5, 1, 0);
  EXPECT_EQ(ldm.add_denm(v), DenmOutcome::kNew);  // MSRV/BV-01
  // Same referenceTime, later detectionTime: newer (MSRV/BV-07); earlier or equal: dropped
  // (MSRV/BO-06).
  auto later = v;
  later.denm.management.detectionTime += 5;
  EXPECT_EQ(ldm.add_denm(later), DenmOutcome::kUpdate);
  auto earlier = v;
  earlier.denm.management.detectionTime -= 5;
  EXPECT_EQ(ldm.add_denm(earlier), DenmOutcome::kOutdated);
  EXPECT_EQ(ldm.add_denm(later), DenmOutcome::kRepetition);
  // Newer referenceTime wins even with an older detectionTime (MSRV/BV-02); older loses
  // (MSRV/BO-05).
  auto newer = v;
  newer.denm.management.referenceTime += 1;
  newer.denm.management.detectionTime -= 100;
  EXPECT_EQ(ldm.add_denm(newer), DenmOutcome::kUpdate);
  auto older = later;
  older.denm.management.referenceTime -= 1;
  older.denm.management.detectionTime += 100;
  EXPECT_EQ(ldm.add_denm(older), DenmOutcome::kOutdated);
  EXPECT_EQ(ldm.event({5, 1})->denm, newer);
  // Applications hear of the accepted ones only.
  EXPECT_EQ(heard, (std::vector<DenmOutcome>{DenmOutcome::kNew, DenmOutcome::kUpdate,
                                             DenmOutcome::kUpdate}));
}

TEST(Ldm, CancellationEndsAnEventForGoodNegationUntilTheOriginatorSpeaksAgain) {
  clock::ManualRuntime rt;
  Ldm ldm(rt);
  // Terminations of events we never held are dropped (MSRV/BO-03, BO-04).
  auto stray = denm_from(rt, 7, 1, 0);
  stray.denm.management.termination = messages::Termination::isCancellation;
  EXPECT_EQ(ldm.add_denm(stray), DenmOutcome::kUnknownTermination);
  EXPECT_EQ(ldm.any_event({7, 1}), nullptr);

  // Negation by another station: keeps the event's referenceTime, a later detectionTime.
  const auto event = denm_from(rt, 5, 1, 0);
  ASSERT_EQ(ldm.add_denm(event), DenmOutcome::kNew);
  auto negation = event;
  negation.header.stationID = 9;
  negation.denm.management.termination = messages::Termination::isNegation;
  negation.denm.management.detectionTime += 50;
  EXPECT_EQ(ldm.add_denm(negation), DenmOutcome::kNegated);
  EXPECT_EQ(ldm.event({5, 1}), nullptr);
  ASSERT_NE(ldm.any_event({5, 1}), nullptr);
  EXPECT_TRUE(ldm.any_event({5, 1})->terminated);
  // Its repetitions, and a later negation by a third station, change nothing.
  EXPECT_EQ(ldm.add_denm(negation), DenmOutcome::kRepetition);
  auto second = negation;
  second.header.stationID = 10;
  second.denm.management.detectionTime += 10;
  EXPECT_EQ(ldm.add_denm(second), DenmOutcome::kRepetition);
  // A late repetition of the negated version stays dropped ...
  EXPECT_EQ(ldm.add_denm(event), DenmOutcome::kOutdated);
  // ... but the originator's newer version brings the event back: it still sees it.
  auto update = event;
  update.denm.management.referenceTime += 100;
  update.denm.management.detectionTime += 100;
  EXPECT_EQ(ldm.add_denm(update), DenmOutcome::kUpdate);
  EXPECT_NE(ldm.event({5, 1}), nullptr);

  // The originator's cancellation is final: nothing but its own repetitions follows.
  auto cancel = update;
  cancel.denm.management.termination = messages::Termination::isCancellation;
  cancel.denm.management.referenceTime += 100;
  EXPECT_EQ(ldm.add_denm(cancel), DenmOutcome::kCancelled);
  auto after = cancel;
  after.denm.management.termination.reset();
  after.denm.management.referenceTime += 100;
  EXPECT_EQ(ldm.add_denm(after), DenmOutcome::kOutdated);
  auto cancel_again = cancel;
  cancel_again.denm.management.referenceTime += 200;
  EXPECT_EQ(ldm.add_denm(cancel_again), DenmOutcome::kRepetition);
  // A negation after the cancellation turns it into a negation for the record.
  auto negate_cancelled = cancel_again;
  negate_cancelled.denm.management.termination = messages::Termination::isNegation;
  negate_cancelled.denm.management.detectionTime += 1;
  EXPECT_EQ(ldm.add_denm(negate_cancelled), DenmOutcome::kNegated);
  EXPECT_TRUE(ldm.active_events().empty());

  // Tombstones last as long as the validity would have.
  rt.advance(6s);
  EXPECT_EQ(ldm.any_event({5, 1}), nullptr);
}

}  // namespace
}  // namespace tb::its::facilities
