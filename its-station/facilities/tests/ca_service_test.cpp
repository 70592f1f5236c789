// CA service against EN 302 637-2 V1.4.1 clause 6.1.3, with a manual clock and scripted motion.
//
// The harness delivers one fix every 100 ms (10 Hz GNSS), fix k at t = k × 100 ms, its fix time
// the wall-clock time of that instant. Timers due at an instant fire before the fix of that
// instant is delivered (the fix comes a moment after its epoch), so a time-triggered CAM due
// at t is built from the fix of t − 100 ms. The service's rules (clause 6.1.3):
//   condition 1 — elapsed ≥ T_GenCam_Dcc (100 ms) and, against the last CAM, |Δheading| > 4°
//                 or displacement > 4 m or |Δspeed| > 0.5 m/s → CAM; T_GenCam := elapsed;
//   condition 2 — elapsed ≥ T_GenCam → CAM; after N_GenCam = 3 such CAMs in a row
//                 T_GenCam := T_GenCamMax (1000 ms).
// The expected instants below are derived by hand from these rules, step by step.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "common/geodesy/local_frame.hpp"
#include "its-station/facilities/ca_service.hpp"
#include "its-station/facilities/its_time.hpp"
#include "its-station/facilities/tests/test_support.hpp"

namespace tb::its::facilities {
namespace {

using namespace std::chrono_literals;
using testing::RecordingSender;

struct Motion {
  double east = 0.0, north = 0.0;  ///< m in the local frame
  double heading_deg = 90.0;
  double speed_mps = 0.0;
};

struct CamAt {
  std::int64_t ms;
  CamTrigger why;
  bool operator==(const CamAt&) const = default;
};
std::ostream& operator<<(std::ostream& os, const CamAt& c) {
  return os << "{" << c.ms << " ms, " << to_string(c.why) << "}";
}

class CaHarness {
 public:
  explicit CaHarness(scenario::CamPolicy policy = {}) {
    CaConfig cfg;
    cfg.station_id = 1001;
    cfg.policy = policy;
    cfg.vehicle_length_m = 4.255;
    cfg.vehicle_width_m = 1.799;
    ca = std::make_unique<CaService>(rt, position, &vehicle, sender, ldm, cfg);
    ca->on_sent([this](const messages::Cam& cam, CamTrigger why, const PositionFix& fix) {
      cams.push_back({ms_now(), why});
      sent.push_back(cam);
      fixes.push_back(fix);
    });
  }

  std::int64_t ms_now() const {
    return std::chrono::duration_cast<std::chrono::milliseconds>(rt.steady_now() - start).count();
  }

  PositionFix fix_of(const Motion& m) const {
    PositionFix f;
    const auto g = frame.to_geodetic({m.east, m.north, 0.0});
    f.time = rt.wall_now();
    f.received = rt.steady_now();
    f.latitude_deg = g.latitude_deg;
    f.longitude_deg = g.longitude_deg;
    f.altitude_m = 520.0;
    f.heading_deg = m.heading_deg;
    f.speed_mps = m.speed_mps;
    f.position_confidence = PositionFix::Ellipse{2.5, 1.5, 30.0};
    f.speed_confidence_mps = 0.1;
    f.heading_confidence_deg = 1.0;
    return f;
  }

  /// Fixes at 10 Hz from t = 0 to @p seconds; the service starts right after the first one.
  void drive(const std::function<Motion(double)>& motion, double seconds) {
    const int n = static_cast<int>(std::lround(seconds * 10));
    for (int k = 0; k <= n; ++k) {
      rt.advance_to(start + k * 100ms);
      position.inject(fix_of(motion(k * 0.1)));
      if (k == 0)
        ca->start();
    }
  }

  clock::ManualRuntime rt;
  clock::SteadyTime start = rt.steady_now();
  geodesy::LocalFrame frame{{48.0, 11.0, 500.0}};
  InjectedPositionProvider position;
  InjectedVehicleDataProvider vehicle;
  RecordingSender sender;
  Ldm ldm{rt};
  std::unique_ptr<CaService> ca;
  std::vector<CamAt> cams;
  std::vector<messages::Cam> sent;
  std::vector<PositionFix> fixes;
};

TEST(CaService, ConstantSlowSpeedStraightAheadGivesOneCamPerSecond) {
  // 3 m/s east. Between two CAMs 1 s apart the station moves 3 m (< 4 m), speed and heading
  // stay: condition 1 never holds, condition 2 fires every T_GenCamMax = 1000 ms.
  CaHarness h;
  h.drive([](double t) { return Motion{3.0 * t, 0.0, 90.0, 3.0}; }, 5.0);
  EXPECT_EQ(h.cams, (std::vector<CamAt>{{0, CamTrigger::kFirst},
                                        {1000, CamTrigger::kTime},
                                        {2000, CamTrigger::kTime},
                                        {3000, CamTrigger::kTime},
                                        {4000, CamTrigger::kTime},
                                        {5000, CamTrigger::kTime}}));
  EXPECT_EQ(h.sender.packets.size(), 6u);
  for (const auto& p : h.sender.packets) {
    EXPECT_EQ(p.port, kBtpPortCam);
    EXPECT_FALSE(p.area);  // single-hop broadcast
  }
}

TEST(CaService, ConstantFastSpeedTriggersOnPositionAndKeepsTGenCam) {
  // 15 m/s east = 1.5 m per fix.
  //   0    first CAM at x = 0 (T_GenCam = 1000).
  //   300  fix x = 4.5: 4.5 m > 4 → position; T_GenCam := 300.
  //   600  timer due (300 + 300) before fix 600; fix 500 (x = 7.5) is 3.0 m away → time (1).
  //   800  fix x = 12.0 is 4.5 m from 7.5 → position; T_GenCam := 200.
  //   1000 timer, fix 900 (13.5): 1.5 m → time (1); 1200 fix 1100 (16.5): 3 m → time (2);
  //   1400 fix 1300 (19.5): 3 m → time (3): T_GenCam := 1000.
  //   1600 fix x = 24.0 is 4.5 m from 19.5 → position; T_GenCam := 200.
  //   1800 fix 1700 (25.5): 1.5 m → time (1); 2000 fix 1900 (28.5): 3 m → time (2).
  CaHarness h;
  h.drive([](double t) { return Motion{15.0 * t, 0.0, 90.0, 15.0}; }, 2.0);
  EXPECT_EQ(h.cams, (std::vector<CamAt>{{0, CamTrigger::kFirst},
                                        {300, CamTrigger::kPosition},
                                        {600, CamTrigger::kTime},
                                        {800, CamTrigger::kPosition},
                                        {1000, CamTrigger::kTime},
                                        {1200, CamTrigger::kTime},
                                        {1400, CamTrigger::kTime},
                                        {1600, CamTrigger::kPosition},
                                        {1800, CamTrigger::kTime},
                                        {2000, CamTrigger::kTime}}));
}

TEST(CaService, BrakingTriggersOnSpeedChange) {
  // 3 m/s east until t = 2 s, then braking at 2 m/s² to a stop at t = 3.5 s: the fix at
  // 2.0 + 0.1 k has v = 3 − 0.2 k. Displacements stay below 4 m throughout.
  //   0, 1000, 2000   as in the constant-speed case (the CAM at 2000 takes fix 1900, v = 3.0).
  //   2300  v = 2.4: |2.4 − 3.0| = 0.6 > 0.5 → speed; T_GenCam := 300.
  //   2600  timer before fix 2600; fix 2500 v = 2.0: 0.4 → time (1), v_last = 2.0.
  //   2800  v = 1.4: 0.6 → speed; T_GenCam := 200.
  //   3000  timer, fix 2900 v = 1.2: 0.2 → time (1); 3200 fix 3100 v = 0.8: 0.4 → time (2);
  //   3400  fix 3300 v = 0.4: 0.4 → time (3): T_GenCam := 1000.
  //   3500  v = 0 (0.4 from 0.4, no trigger), standing: 4400, 5400 time.
  CaHarness h;
  h.drive(
      [](double t) {
        if (t <= 2.0)
          return Motion{3.0 * t, 0.0, 90.0, 3.0};
        const double tb = std::min(t - 2.0, 1.5);
        return Motion{6.0 + 3.0 * tb - tb * tb, 0.0, 90.0, 3.0 - 2.0 * tb};
      },
      6.0);
  EXPECT_EQ(h.cams, (std::vector<CamAt>{{0, CamTrigger::kFirst},
                                        {1000, CamTrigger::kTime},
                                        {2000, CamTrigger::kTime},
                                        {2300, CamTrigger::kSpeed},
                                        {2600, CamTrigger::kTime},
                                        {2800, CamTrigger::kSpeed},
                                        {3000, CamTrigger::kTime},
                                        {3200, CamTrigger::kTime},
                                        {3400, CamTrigger::kTime},
                                        {4400, CamTrigger::kTime},
                                        {5400, CamTrigger::kTime}}));
  // The CAM of each instant carries the speed of the fix it was built from.
  EXPECT_EQ(h.sent[3].cam.camParameters.highFrequencyContainer.speed.speedValue, 240);
  EXPECT_EQ(h.sent[4].cam.camParameters.highFrequencyContainer.speed.speedValue, 200);
}

TEST(CaService, TurningTriggersOnHeadingChangeAcrossNorth) {
  // Standing still at the origin (no displacement), heading 354° until t = 2 s, then turning
  // right at 12 °/s for 2 s (1.2° per fix), through north: the wrap must not look like a
  // 360° jump. Relative heading h_k = 1.2 k after 2.0 s.
  //   0, 1000, 2000   time (the CAM at 2000 takes fix 1900, h = 0).
  //   2400  h = 4.8 > 4 → heading; T_GenCam := 400.
  //   2800  timer before fix 2800; fix 2700 h = 8.4: 3.6 → time (1).
  //   3100  h = 13.2: 4.8 → heading; T_GenCam := 300.
  //   3400  timer, fix 3300 h = 15.6: 2.4 → time (1).
  //   3700  timer, fix 3600 h = 19.2: 3.6 → time (2).
  //   4000  timer, fix 3900 h = 22.8: 3.6 → time (3): T_GenCam := 1000. Fix 4000 h = 24.0
  //         (1.2 from 22.8) ends the turn. 5000, 6000 time.
  CaHarness h;
  h.drive(
      [](double t) {
        const double turned = 12.0 * std::clamp(t - 2.0, 0.0, 2.0);
        return Motion{0.0, 0.0, geodesy::wrap_360(354.0 + turned), 0.0};
      },
      6.0);
  EXPECT_EQ(h.cams, (std::vector<CamAt>{{0, CamTrigger::kFirst},
                                        {1000, CamTrigger::kTime},
                                        {2000, CamTrigger::kTime},
                                        {2400, CamTrigger::kHeading},
                                        {2800, CamTrigger::kTime},
                                        {3100, CamTrigger::kHeading},
                                        {3400, CamTrigger::kTime},
                                        {3700, CamTrigger::kTime},
                                        {4000, CamTrigger::kTime},
                                        {5000, CamTrigger::kTime},
                                        {6000, CamTrigger::kTime}}));
}

TEST(CaService, FixedPolicySendsAtItsPeriodWhateverTheDynamics) {
  scenario::CamPolicy fixed;
  fixed.kind = scenario::CamPolicy::Kind::kFixed;
  fixed.period_ms = 100.0;
  CaHarness h(fixed);
  h.drive([](double t) { return Motion{15.0 * t, 0.0, 90.0 + 20.0 * t, 15.0}; }, 1.0);
  ASSERT_EQ(h.cams.size(), 11u);
  for (std::size_t i = 0; i < h.cams.size(); ++i)
    EXPECT_EQ(h.cams[i].ms, static_cast<std::int64_t>(i) * 100);
  EXPECT_EQ(h.cams[1].why, CamTrigger::kFixed);
}

TEST(CaService, CamNamesItsFixAndCarriesLowFrequencyEvery500ms) {
  CaHarness h;
  h.drive([](double t) { return Motion{15.0 * t, 0.0, 90.0, 15.0}; }, 2.0);
  ASSERT_GE(h.sent.size(), 6u);
  for (std::size_t i = 0; i < h.sent.size(); ++i) {
    const auto& cam = h.sent[i];
    const auto& fix = h.fixes[i];
    EXPECT_EQ(cam.header.stationID, 1001u);
    EXPECT_EQ(cam.cam.generationDeltaTime, generation_delta_time(timestamp_its(fix.time)));
    EXPECT_EQ(cam.cam.camParameters.basicContainer.referencePosition.latitude,
              std::lround(fix.latitude_deg * 1e7));
    EXPECT_EQ(cam.cam.camParameters.basicContainer.referencePosition.longitude,
              std::lround(fix.longitude_deg * 1e7));
  }
  // LF container: first CAM (0), then the first CAM ≥ 500 ms after the last one that had it:
  // CAMs at 0, 300, 600, 800, 1000, 1200, 1400, 1600 … → LF at 0, 600, 1200, 1800.
  std::vector<std::int64_t> lf;
  for (std::size_t i = 0; i < h.sent.size(); ++i)
    if (h.sent[i].cam.camParameters.lowFrequencyContainer)
      lf.push_back(h.cams[i].ms);
  EXPECT_EQ(lf, (std::vector<std::int64_t>{0, 600, 1200, 1800}));
  // By 1200 ms the car has covered 16.5 m behind the fix: path points every 5 m (or more).
  const auto& ph = h.sent[5].cam.camParameters.lowFrequencyContainer->pathHistory;
  EXPECT_GE(ph.size(), 3u);
  // Each point is behind the previous one (west, negative longitude delta), ≤ ~13 m apart.
  for (const auto& p : ph) {
    EXPECT_LT(p.pathPosition.deltaLongitude, 0);
    EXPECT_TRUE(p.pathDeltaTime.has_value());
  }
}

TEST(CaService, EncodedCamDecodesToWhatWasBuilt) {
  CaHarness h;
  messages::Cam seen;
  h.vehicle.inject(VehicleData{.received = {},
                               .speed_mps = 15.0,
                               .yaw_rate_dps = 2.0,
                               .longitudinal_acceleration_mps2 = -1.25,
                               .lateral_acceleration_mps2 = 0.5,
                               .steering_wheel_angle_deg = 30.0,
                               .brake_pedal = true,
                               .gas_pedal = false,
                               .reversing = false,
                               .exterior_lights = lights::kLowBeam | lights::kLeftTurnSignal});
  h.drive([](double t) { return Motion{15.0 * t, 0.0, 90.0, 15.0}; }, 0.0);
  ASSERT_EQ(h.sender.packets.size(), 1u);
  auto decoded = messages::decode_cam(h.sender.packets[0].payload);
  ASSERT_TRUE(decoded) << asn1::to_string(decoded.error());
  EXPECT_EQ(*decoded, h.sent[0]);
  const auto& hf = decoded->cam.camParameters.highFrequencyContainer;
  EXPECT_EQ(hf.heading.headingValue, 900);
  EXPECT_EQ(hf.heading.headingConfidence, 10);
  EXPECT_EQ(hf.speed.speedValue, 1500);
  EXPECT_EQ(hf.speed.speedConfidence, 10);
  EXPECT_EQ(hf.driveDirection, messages::DriveDirection::forward);
  EXPECT_EQ(hf.vehicleLength.vehicleLengthValue, 43);
  EXPECT_EQ(hf.vehicleWidth, 18);
  EXPECT_EQ(hf.longitudinalAcceleration.longitudinalAccelerationValue, -13);  // −1.25 → −12.5
  EXPECT_EQ(hf.yawRate.yawRateValue, 200);
  EXPECT_EQ(hf.steeringWheelAngle->steeringWheelAngleValue, 20);
  EXPECT_EQ(*hf.accelerationControl, messages::acceleration_control::kBrakePedalEngaged);
  // κ = ω / v = (2° /s in rad) / 15 m/s = 0.002327 1/m → 23 in 1/10000 m.
  EXPECT_EQ(hf.curvature.curvatureValue, 23);
  const auto& bc = decoded->cam.camParameters.basicContainer;
  EXPECT_EQ(bc.referencePosition.positionConfidenceEllipse.semiMajorConfidence, 250);
  EXPECT_EQ(bc.referencePosition.positionConfidenceEllipse.semiMinorConfidence, 150);
  EXPECT_EQ(bc.referencePosition.positionConfidenceEllipse.semiMajorOrientation, 300);
  EXPECT_EQ(bc.referencePosition.altitude.altitudeValue, 52000);
  ASSERT_TRUE(decoded->cam.camParameters.lowFrequencyContainer);
  EXPECT_EQ(decoded->cam.camParameters.lowFrequencyContainer->exteriorLights,
            messages::exterior_lights::kLowBeamHeadlightsOn |
                messages::exterior_lights::kLeftTurnSignalOn);
}

TEST(CaService, NoFixNoCamAndFirstCamAgainAfterTheFixReturns) {
  CaHarness h;
  h.drive([](double t) { return Motion{3.0 * t, 0.0, 90.0, 3.0}; }, 1.0);
  ASSERT_EQ(h.cams.size(), 2u);  // 0 and 1000
  h.position.lose_fix();
  h.rt.advance(5s);  // 5 s without fix: no CAM, and checks keep running
  EXPECT_EQ(h.cams.size(), 2u);
  EXPECT_GT(h.ca->counters().suppressed_no_fix, 10u);
  h.position.inject(h.fix_of({10.0, 0.0, 90.0, 3.0}));
  ASSERT_EQ(h.cams.size(), 3u);
  EXPECT_EQ(h.cams.back(), (CamAt{6000, CamTrigger::kFirst}));
  EXPECT_TRUE(h.sent.back().cam.camParameters.lowFrequencyContainer);
}

TEST(CaService, ReceivedCamsReachTheLdmButOwnAreDropped) {
  CaHarness a;
  CaHarness b;
  a.drive([](double t) { return Motion{3.0 * t, 0.0, 90.0, 3.0}; }, 0.0);
  ASSERT_EQ(a.sender.packets.size(), 1u);
  b.ca->receive(a.sender.packets[0].payload, b.rt.wall_now());
  // Same station id 1001 in both harnesses: b drops it as its own.
  EXPECT_EQ(b.ca->counters().own_dropped, 1u);
  EXPECT_TRUE(b.ldm.neighbours().empty());

  CaConfig cfg;
  cfg.station_id = 2002;
  InjectedPositionProvider pos;
  CaService c(b.rt, pos, nullptr, b.sender, b.ldm, cfg);
  c.receive(a.sender.packets[0].payload, b.rt.wall_now());
  const auto* n = b.ldm.neighbour(1001);
  ASSERT_NE(n, nullptr);
  EXPECT_NEAR(n->latest().speed_mps.value(), 3.0, 1e-9);
  EXPECT_NEAR(n->latest().heading_deg.value(), 90.0, 1e-9);
  EXPECT_NEAR(n->latest().latitude_deg, a.fixes[0].latitude_deg, 1e-7);

  const std::uint8_t junk[] = {0x02, 0x02, 0xff};
  c.receive(junk, b.rt.wall_now());
  EXPECT_EQ(c.counters().decode_errors, 1u);
}

}  // namespace
}  // namespace tb::its::facilities
