// CA service against EN 302 637-2 V1.4.1 clause 6.1.3, with a manual clock and scripted motion.
//
// The harness delivers one fix every 100 ms (10 Hz GNSS), fix k at t = k × 100 ms, its fix time
// the wall-clock time of that instant. A time-triggered CAM is made from the fix of its due
// instant (one arriving at most CamTiming::fresh_fix_wait, 10 ms, before it), or from the next
// fix when it falls due between fixes, within one T_CheckCamGen. The service's rules (clause
// 6.1.3):
//   condition 1 — elapsed ≥ T_GenCam_Dcc (100 ms) and, against the last CAM, |Δheading| > 4°
//                 or displacement > 4 m or |Δspeed| > 0.5 m/s → CAM; T_GenCam := elapsed;
//   condition 2 — elapsed ≥ T_GenCam → CAM; after N_GenCam = 3 such CAMs in a row
//                 T_GenCam := T_GenCamMax (1000 ms).
// The expected instants below are derived by hand from these rules, step by step.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <variant>

#include "common/geodesy/local_frame.hpp"
#include "its-station/facilities/ca_service.hpp"
#include "its-station/facilities/its_time.hpp"
#include "its-station/facilities/tests/test_support.hpp"
#include "its-station/messages/tests/samples.hpp"

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
  explicit CaHarness(scenario::CamPolicy policy = {},
                     messages::VehicleRole role = messages::VehicleRole::default_,
                     messages::StationType type = messages::station_type::kPassengerCar) {
    CaConfig cfg;
    cfg.station_id = 1001;
    cfg.station_type = type;
    cfg.policy = policy;
    cfg.vehicle_length_m = 4.255;
    cfg.vehicle_width_m = 1.799;
    cfg.vehicle_role = role;
    ca = std::make_unique<CaService>(rt, position, &vehicle, sender, ldm, cfg);
    ca->on_sent([this](const messages::Cam& cam, CamTrigger why, const PositionFix& fix) {
      cams.push_back({ms_now(), why});
      sent_at.push_back(rt.steady_now());
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
  std::vector<clock::SteadyTime> sent_at;
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

TEST(CaService, ConstantFastSpeedTriggersOnPosition) {
  // 15 m/s east = 1.5 m per fix: 3.0 m after 200 ms (no), 4.5 m after 300 ms (> 4 m) →
  // a position-triggered CAM every 300 ms; T_GenCam := 300 ms each time, but condition 1
  // always comes first (at the same instant, and it is checked first).
  CaHarness h;
  h.drive([](double t) { return Motion{15.0 * t, 0.0, 90.0, 15.0}; }, 2.0);
  EXPECT_EQ(h.cams, (std::vector<CamAt>{{0, CamTrigger::kFirst},
                                        {300, CamTrigger::kPosition},
                                        {600, CamTrigger::kPosition},
                                        {900, CamTrigger::kPosition},
                                        {1200, CamTrigger::kPosition},
                                        {1500, CamTrigger::kPosition},
                                        {1800, CamTrigger::kPosition}}));
  EXPECT_EQ(h.ca->rules().T_GenCam(), 300ms);
}

TEST(CaService, BrakingTriggersOnSpeedChange) {
  // 3 m/s east until t = 2 s, then braking at 2 m/s² to a stop at t = 3.5 s: the fix at
  // 2.0 + 0.1 k has v = 3 − 0.2 k. Displacements stay below 4 m throughout.
  //   0, 1000, 2000   as in the constant-speed case (the CAM at 2000 has v = 3.0).
  //   2100 v = 2.8 (Δ 0.2), 2200 v = 2.6 (Δ 0.4): nothing.
  //   2300  v = 2.4: |2.4 − 3.0| = 0.6 > 0.5 → speed; T_GenCam := 300.
  //   2600  v = 1.8: Δ 0.6 → speed (condition 1 before condition 2); T_GenCam := 300.
  //   2900  v = 1.2, 3200 v = 0.6, 3500 v = 0.0: Δ 0.6 each → speed.
  //   Standing from 3500: Δ 0, so condition 2 with T_GenCam = 300 ms: 3800 (1), 4100 (2),
  //   4400 (3) → T_GenCam := 1000 after N_GenCam = 3; then 5400.
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
                                        {2600, CamTrigger::kSpeed},
                                        {2900, CamTrigger::kSpeed},
                                        {3200, CamTrigger::kSpeed},
                                        {3500, CamTrigger::kSpeed},
                                        {3800, CamTrigger::kTime},
                                        {4100, CamTrigger::kTime},
                                        {4400, CamTrigger::kTime},
                                        {5400, CamTrigger::kTime}}));
  // Each CAM carries the speed of the fix of its own instant.
  EXPECT_EQ(messages::vehicle_hf(h.sent[3].cam.camParameters)->speed.speedValue, 240);
  EXPECT_EQ(messages::vehicle_hf(h.sent[4].cam.camParameters)->speed.speedValue, 180);
  EXPECT_EQ(messages::vehicle_hf(h.sent[7].cam.camParameters)->speed.speedValue, 0);
}

TEST(CaService, TurningTriggersOnHeadingChangeAcrossNorth) {
  // Standing still at the origin (no displacement), heading 354° until t = 2 s, then turning
  // right at 12 °/s for 2 s (1.2° per fix), through north: the wrap must not look like a
  // 360° jump. Relative heading h_k = 1.2 k after 2.0 s.
  //   0, 1000, 2000   time (h = 0).
  //   2100–2300  Δh 1.2, 2.4, 3.6: nothing; 2400 Δh 4.8 > 4 → heading; T_GenCam := 400.
  //   2800, 3200, 3600, 4000  Δh 4.8 each → heading (the turn ends at 4000, h = 24.0).
  //   Straight on: condition 2 at T_GenCam = 400 ms: 4400, 4800, 5200 (N_GenCam = 3), then
  //   T_GenCam = 1000 ms: 6200.
  CaHarness h;
  h.drive(
      [](double t) {
        const double turned = 12.0 * std::clamp(t - 2.0, 0.0, 2.0);
        return Motion{0.0, 0.0, geodesy::wrap_360(354.0 + turned), 0.0};
      },
      6.5);
  EXPECT_EQ(h.cams, (std::vector<CamAt>{{0, CamTrigger::kFirst},
                                        {1000, CamTrigger::kTime},
                                        {2000, CamTrigger::kTime},
                                        {2400, CamTrigger::kHeading},
                                        {2800, CamTrigger::kHeading},
                                        {3200, CamTrigger::kHeading},
                                        {3600, CamTrigger::kHeading},
                                        {4000, CamTrigger::kHeading},
                                        {4400, CamTrigger::kTime},
                                        {4800, CamTrigger::kTime},
                                        {5200, CamTrigger::kTime},
                                        {6200, CamTrigger::kTime}}));
  EXPECT_EQ(messages::vehicle_hf(h.sent[7].cam.camParameters)->heading.headingValue, 180);
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

TEST(CaService, ARoadSideUnitSendsItsContainerOnceASecondWhateverItsFixSays) {
  // EN 302 637-2 clause 6.1.4: an RSU's CAM at a fixed interval (T_GenCamMax), none of the
  // vehicle's dynamic triggers — even when its GNSS fix wanders by metres and degrees, as a
  // receiver's noise does.
  CaHarness h({}, messages::VehicleRole::default_, messages::station_type::kRoadSideUnit);
  h.drive(
      [](double t) {
        const double wobble = (static_cast<int>(t * 10) % 2 == 0) ? 5.0 : -5.0;
        return Motion{wobble, 0.0, 90.0 + 10 * wobble, 0.0};
      },
      3.05);
  ASSERT_EQ(h.cams.size(), 4u);
  for (std::size_t i = 0; i < h.cams.size(); ++i)
    EXPECT_EQ(h.cams[i].ms, static_cast<std::int64_t>(i) * 1000);
  for (const messages::Cam& cam : h.sent) {
    EXPECT_EQ(cam.cam.camParameters.basicContainer.stationType,
              messages::station_type::kRoadSideUnit);
    EXPECT_TRUE(std::holds_alternative<messages::RSUContainerHighFrequency>(
        cam.cam.camParameters.highFrequencyContainer));
    EXPECT_EQ(messages::vehicle_hf(cam.cam.camParameters), nullptr);
    EXPECT_FALSE(cam.cam.camParameters.lowFrequencyContainer.has_value());
    EXPECT_FALSE(cam.cam.camParameters.specialVehicleContainer.has_value());
  }
  // What went on the air decodes to an RSU's CAM at the fix's position.
  ASSERT_FALSE(h.sender.packets.empty());
  const auto back = messages::decode_cam(h.sender.packets.back().payload);
  ASSERT_TRUE(back.has_value());
  EXPECT_TRUE(std::holds_alternative<messages::RSUContainerHighFrequency>(
      back->cam.camParameters.highFrequencyContainer));
  EXPECT_EQ(back->cam.camParameters.basicContainer.referencePosition.latitude,
            std::lround(h.fixes.back().latitude_deg * 1e7));
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
  // CAMs at 0, 300, 600, 900, 1200, 1500, 1800 → LF at 0, 600, 1200, 1800.
  std::vector<std::int64_t> lf;
  for (std::size_t i = 0; i < h.sent.size(); ++i)
    if (h.sent[i].cam.camParameters.lowFrequencyContainer)
      lf.push_back(h.cams[i].ms);
  EXPECT_EQ(lf, (std::vector<std::int64_t>{0, 600, 1200, 1800}));
  // By 1200 ms the car has covered 18 m: path points recorded every 5 m (at 0, 6 and 12 m).
  ASSERT_EQ(h.cams[4].ms, 1200);
  const auto& ph = h.sent[4].cam.camParameters.lowFrequencyContainer->pathHistory;
  EXPECT_EQ(ph.size(), 3u);
  EXPECT_GE(ph.size(), 3u);
  // Each point is behind the previous one (west, negative longitude delta), ≤ ~13 m apart.
  for (const auto& p : ph) {
    EXPECT_LT(p.pathPosition.deltaLongitude, 0);
    EXPECT_TRUE(p.pathDeltaTime.has_value());
  }
}

TEST(CaService, AnEmergencyVehicleSendsItsContainerEvery500msWithTheStatesLightBarAndSiren) {
  CaHarness h({}, messages::VehicleRole::emergency);
  VehicleData d;
  d.light_bar = true;
  d.siren = false;
  h.vehicle.inject(d);
  h.drive([](double t) { return Motion{15.0 * t, 0.0, 90.0, 15.0}; }, 2.0);
  // The same clock as the LF container (clause 6.1.3): CAMs at 0, 300, …, 1800 ms → the
  // special-vehicle container at 0, 600, 1200, 1800.
  std::vector<std::int64_t> special;
  for (std::size_t i = 0; i < h.sent.size(); ++i) {
    const auto& p = h.sent[i].cam.camParameters;
    if (!p.specialVehicleContainer)
      continue;
    special.push_back(h.cams[i].ms);
    const auto* e = std::get_if<messages::EmergencyContainer>(&*p.specialVehicleContainer);
    ASSERT_NE(e, nullptr);
    EXPECT_EQ(e->lightBarSirenInUse, messages::light_bar_siren::kLightBarActivated);
    EXPECT_FALSE(e->incidentIndication);
    EXPECT_FALSE(e->emergencyPriority);
  }
  EXPECT_EQ(special, (std::vector<std::int64_t>{0, 600, 1200, 1800}));
  ASSERT_TRUE(h.sent[0].cam.camParameters.lowFrequencyContainer);
  EXPECT_EQ(h.sent[0].cam.camParameters.lowFrequencyContainer->vehicleRole,
            messages::VehicleRole::emergency);
  // What went on the air decodes to it.
  auto decoded = messages::decode_cam(h.sender.packets[0].payload);
  ASSERT_TRUE(decoded) << asn1::to_string(decoded.error());
  EXPECT_EQ(*decoded, h.sent[0]);
}

TEST(CaService, EveryRoleGetsItsOwnContainerOrNone) {
  namespace m = messages;
  CaConfig cfg;
  VehicleData both;
  both.light_bar = true;
  both.siren = true;
  const m::LightBarSirenInUse on =
      m::light_bar_siren::kLightBarActivated | m::light_bar_siren::kSirenActivated;
  auto with = [&](m::VehicleRole r, const VehicleData* d) {
    cfg.vehicle_role = r;
    return special_vehicle_container(cfg, d);
  };
  // The CHOICE index of each role's container is its role value less one (B.2.x).
  for (int role = 1; role <= 7; ++role) {
    const auto c = with(static_cast<m::VehicleRole>(role), &both);
    ASSERT_TRUE(c) << role;
    EXPECT_EQ(c->index(), static_cast<std::size_t>(role - 1)) << role;
  }
  EXPECT_EQ(std::get<m::SpecialTransportContainer>(*with(m::VehicleRole::specialTransport, &both))
                .lightBarSirenInUse,
            on);
  EXPECT_EQ(std::get<m::RoadWorksContainerBasic>(*with(m::VehicleRole::roadWork, &both))
                .lightBarSirenInUse,
            on);
  EXPECT_EQ(std::get<m::RescueContainer>(*with(m::VehicleRole::rescue, &both)).lightBarSirenInUse,
            on);
  EXPECT_EQ(
      std::get<m::SafetyCarContainer>(*with(m::VehicleRole::safetyCar, &both)).lightBarSirenInUse,
      on);
  // No vehicle data, or a bus without the signals: both off.
  EXPECT_EQ(std::get<m::RescueContainer>(*with(m::VehicleRole::rescue, nullptr)).lightBarSirenInUse,
            0);
  const VehicleData unknown;
  EXPECT_EQ(
      std::get<m::RescueContainer>(*with(m::VehicleRole::rescue, &unknown)).lightBarSirenInUse, 0);
  cfg.dangerous_goods = 9;  // flammableLiquids
  EXPECT_EQ(std::get<m::DangerousGoodsContainer>(*with(m::VehicleRole::dangerousGoods, nullptr))
                .dangerousGoodsBasic,
            9);
  for (m::VehicleRole r :
       {m::VehicleRole::default_, m::VehicleRole::agriculture, m::VehicleRole::commercial,
        m::VehicleRole::military, m::VehicleRole::roadOperator, m::VehicleRole::taxi})
    EXPECT_FALSE(with(r, &both)) << static_cast<int>(r);
  // A plain car's CAMs never carry one.
  CaHarness h;
  h.drive([](double t) { return Motion{15.0 * t, 0.0, 90.0, 15.0}; }, 1.0);
  for (const auto& cam : h.sent)
    EXPECT_FALSE(cam.cam.camParameters.specialVehicleContainer);
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
                               .exterior_lights = lights::kLowBeam | lights::kLeftTurnSignal,
                               .light_bar = std::nullopt,
                               .siren = std::nullopt});
  h.drive([](double t) { return Motion{15.0 * t, 0.0, 90.0, 15.0}; }, 0.0);
  ASSERT_EQ(h.sender.packets.size(), 1u);
  auto decoded = messages::decode_cam(h.sender.packets[0].payload);
  ASSERT_TRUE(decoded) << asn1::to_string(decoded.error());
  EXPECT_EQ(*decoded, h.sent[0]);
  const auto& hf = *messages::vehicle_hf(decoded->cam.camParameters);
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
  // The CAN signals say nothing of their sensors' accuracy: every such confidence is sent as
  // unavailable, never as the best class.
  EXPECT_EQ(hf.steeringWheelAngle->steeringWheelAngleConfidence,
            messages::kSteeringWheelAngleConfidenceUnavailable);
  EXPECT_EQ(hf.yawRate.yawRateConfidence, messages::YawRateConfidence::unavailable);
  EXPECT_EQ(hf.longitudinalAcceleration.longitudinalAccelerationConfidence,
            messages::kAccelerationConfidenceUnavailable);
  EXPECT_EQ(hf.lateralAcceleration->lateralAccelerationConfidence,
            messages::kAccelerationConfidenceUnavailable);
  EXPECT_EQ(hf.curvature.curvatureConfidence, messages::CurvatureConfidence::unavailable);
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

TEST(CaService, WithoutNewFixesTheTimerMakesTheTimeCamAfterTheFreshFixWait) {
  // The fix stays valid but no newer one comes (a stalled receiver, before the provider's
  // stale timeout): the CAM due at 1000 ms is made by the timer at 1000 + 10 ms.
  CaHarness h;
  h.drive([](double t) { return Motion{3.0 * t, 0.0, 90.0, 3.0}; }, 0.0);
  h.rt.advance(1500ms);
  EXPECT_EQ(h.cams, (std::vector<CamAt>{{0, CamTrigger::kFirst}, {1010, CamTrigger::kTime}}));
}

TEST(CaService, TimeCamsWaitForTheFixOfTheirInstantNotForVehicleData) {
  // CAN data at 100 Hz between fixes: neither a CAN frame at 999.5 ms or 1000.5 ms nor the
  // timer (just before the fix of 1000 ms arrives) may make the time-based CAM from the fix of
  // 900 ms.
  CaHarness h;
  h.drive([](double t) { return Motion{3.0 * t, 0.0, 90.0, 3.0}; }, 0.9);
  VehicleData vd;
  vd.speed_mps = 3.0;
  h.rt.advance(99'500us);  // 999.5 ms
  h.vehicle.inject(vd);
  h.rt.advance(1ms);  // 1000.5 ms
  h.vehicle.inject(vd);
  ASSERT_EQ(h.cams.size(), 1u);
  h.rt.advance(500us);  // the fix of 1000 ms arrives at 1001 ms
  h.position.inject(h.fix_of({3.0, 0.0, 90.0, 3.0}));
  ASSERT_EQ(h.cams.size(), 2u);
  EXPECT_EQ(h.cams[1], (CamAt{1001, CamTrigger::kTime}));
  EXPECT_EQ(h.fixes[1].time, h.rt.wall_now());
}

TEST(CaService, FixJustBeforeTGenCamDccIsSentTheInstantItElapses) {
  // The fix of 100 ms arrives 0.5 ms early (jitter) and shows a 5 m jump: condition 1 holds
  // but T_GenCam_Dcc (100 ms) has not elapsed. The CAM is made at exactly 100.0 ms from that
  // fix — not earlier (clause 6.1.3), and not at the next check or fix.
  CaHarness h;
  h.drive([](double t) { return Motion{3.0 * t, 0.0, 90.0, 3.0}; }, 0.0);
  h.rt.advance_to(h.start + 99'500us);
  const auto jumped = h.fix_of({5.0, 0.0, 90.0, 3.0});
  h.position.inject(jumped);
  ASSERT_EQ(h.cams.size(), 1u);
  h.rt.advance_to(h.start + 100ms - 1ns);
  ASSERT_EQ(h.cams.size(), 1u);
  h.rt.advance_to(h.start + 150ms);
  ASSERT_EQ(h.cams.size(), 2u);
  EXPECT_EQ(h.cams[1].why, CamTrigger::kPosition);
  EXPECT_EQ(h.sent_at[1], h.start + 100ms);
  EXPECT_EQ(h.fixes[1].time, jumped.time);
}

TEST(CaService, FixJustBeforeATimeCamIsDueIsSentWhenItFallsDue) {
  // 3 m/s: time CAMs every 1000 ms. The fix of 1000 ms arrives at 999.5 ms: the CAM due at
  // 1000 ms is made at 1000.0 ms from that fix (not at 1010 ms, not from the fix of 900 ms).
  CaHarness h;
  h.drive([](double t) { return Motion{3.0 * t, 0.0, 90.0, 3.0}; }, 0.9);
  h.rt.advance_to(h.start + 999'500us);
  const auto early = h.fix_of({3.0, 0.0, 90.0, 3.0});
  h.position.inject(early);
  ASSERT_EQ(h.cams.size(), 1u);
  h.rt.advance_to(h.start + 1050ms);
  ASSERT_EQ(h.cams.size(), 2u);
  EXPECT_EQ(h.cams[1].why, CamTrigger::kTime);
  EXPECT_EQ(h.sent_at[1], h.start + 1000ms);
  EXPECT_EQ(h.fixes[1].time, early.time);
}

TEST(CaService, TimeCamDueBetweenFixesIsMadeFromTheNextFix) {
  // A late epoch makes the fixes arrive at 0, 100, 250 and then every 100 ms (350, 450, ...).
  //   0     first.
  //   250   moved 5 m → position; T_GenCam := 250 ms. Standing from there on.
  //   500   condition 2 falls due between the fixes of 450 and 550. The CAM is made on the
  //         arrival of the fix of 550 (within T_CheckCamGen of 500), carrying that fix, not at
  //         510 from the fix of 450.
  //   800   T_GenCam (250) is due again between fixes (the last CAM was at 550): fix of 850.
  CaHarness h;
  h.drive([](double) { return Motion{0.0, 0.0, 90.0, 0.0}; }, 0.1);
  const auto fix_at = [&](std::int64_t ms, double east) {
    h.rt.advance_to(h.start + std::chrono::milliseconds(ms));
    h.position.inject(h.fix_of({east, 0.0, 90.0, 0.0}));
  };
  for (std::int64_t ms = 250; ms <= 950; ms += 100)
    fix_at(ms, 5.0);
  EXPECT_EQ(h.cams, (std::vector<CamAt>{{0, CamTrigger::kFirst},
                                        {250, CamTrigger::kPosition},
                                        {550, CamTrigger::kTime},
                                        {850, CamTrigger::kTime}}));
  ASSERT_EQ(h.fixes.size(), 4u);
  EXPECT_EQ(h.fixes[2].received, h.start + 550ms);
  EXPECT_EQ(h.fixes[3].received, h.start + 850ms);
}

TEST(CaService, TimeCamDueBetweenFixesFallsBackToTheOldFixAfterOneCheckPeriod) {
  // As above, but no fix comes after the one of 450 ms: the CAM due at 500 ms is made at
  // 600 ms (one T_CheckCamGen later) from the fix of 450 ms.
  CaHarness h;
  h.drive([](double) { return Motion{0.0, 0.0, 90.0, 0.0}; }, 0.1);
  for (std::int64_t ms = 250; ms <= 450; ms += 100) {
    h.rt.advance_to(h.start + std::chrono::milliseconds(ms));
    h.position.inject(h.fix_of({5.0, 0.0, 90.0, 0.0}));
  }
  h.rt.advance_to(h.start + 700ms);
  EXPECT_EQ(h.cams,
            (std::vector<CamAt>{
                {0, CamTrigger::kFirst}, {250, CamTrigger::kPosition}, {600, CamTrigger::kTime}}));
  EXPECT_EQ(h.fixes.back().received, h.start + 450ms);
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

// Stations of one thread that share a decoder keep one decoded CAM per frame between them; a
// different frame, or one after an undecodable one, is decoded anew.
TEST(CaService, StationsSharingADecoderKeepOneCamPerFrame) {
  clock::ManualRuntime rt;
  RecordingSender sender;
  InjectedPositionProvider pos;
  SharedCamDecoder decoder;
  Ldm ldm_a(rt);
  Ldm ldm_b(rt);
  CaConfig cfg;
  cfg.station_id = 2002;
  CaService a(rt, pos, nullptr, sender, ldm_a, cfg);
  cfg.station_id = 2003;
  CaService b(rt, pos, nullptr, sender, ldm_b, cfg);
  a.set_shared_decoder(&decoder);
  b.set_shared_decoder(&decoder);

  auto encoded = [](messages::Cam cam, messages::StationID from) {
    cam.header.stationID = from;
    auto bytes = messages::encode(cam);
    EXPECT_TRUE(bytes);
    return *bytes;
  };
  const auto samples = messages::samples::cams_special_vehicle();
  const auto first = encoded(samples[0], 77);
  const auto second = encoded(samples[1], 77);
  a.receive(first, rt.wall_now());
  b.receive(first, rt.wall_now());
  ASSERT_NE(ldm_a.neighbour(77), nullptr);
  ASSERT_NE(ldm_b.neighbour(77), nullptr);
  EXPECT_EQ(ldm_a.neighbour(77)->last_cam.get(), ldm_b.neighbour(77)->last_cam.get());
  EXPECT_EQ(*ldm_a.neighbour(77)->last_cam, *messages::decode_cam(first));
  EXPECT_EQ(decoder.decoded(), 1u);
  EXPECT_EQ(decoder.reused(), 1u);

  a.receive(second, rt.wall_now());
  EXPECT_NE(ldm_a.neighbour(77)->last_cam.get(), ldm_b.neighbour(77)->last_cam.get());
  EXPECT_EQ(*ldm_a.neighbour(77)->last_cam, *messages::decode_cam(second));
  EXPECT_EQ(decoder.decoded(), 2u);

  const std::vector<std::uint8_t> junk{0x02, 0x02, 0xff};
  a.receive(junk, rt.wall_now());
  b.receive(junk, rt.wall_now());
  EXPECT_EQ(a.counters().decode_errors, 1u);
  EXPECT_EQ(b.counters().decode_errors, 1u);
  b.receive(second, rt.wall_now());
  EXPECT_EQ(*ldm_b.neighbour(77)->last_cam, *messages::decode_cam(second));
  EXPECT_EQ(decoder.decoded(), 3u);
  EXPECT_EQ(decoder.reused(), 1u);
}

TEST(CaService, ASignedCamIsCheckedAgainstItsSignersSsp) {
  CaHarness b;
  InjectedPositionProvider pos;
  CaConfig cfg;
  cfg.station_id = 2002;
  CaService c(b.rt, pos, nullptr, b.sender, b.ldm, cfg);
  messages::Cam emergency = messages::samples::cams_special_vehicle()[5];
  std::array<std::uint8_t, messages::kCamMaxEncodedSize> buf;
  const auto n = messages::encode(emergency, buf);
  ASSERT_TRUE(n);
  const auto bytes = std::span(buf).first(*n);
  // An ordinary car's AT (its-pki's CAM SSP 01 00 00): not an emergency vehicle.
  const std::array<std::uint8_t, 3> car{0x01, 0x00, 0x00};
  c.receive(bytes, b.rt.wall_now(), std::span<const std::uint8_t>(car));
  EXPECT_EQ(c.counters().not_permitted, 1u);
  EXPECT_EQ(c.counters().received, 0u);
  EXPECT_EQ(b.ldm.neighbour(emergency.header.stationID), nullptr);
  // Unsecured (security none): nothing to check it against.
  c.receive(bytes, b.rt.wall_now());
  EXPECT_EQ(c.counters().received, 1u);
  // An emergency vehicle's AT with the right-of-way bit its emergencyPriority claims.
  const std::array<std::uint8_t, 3> ambulance{0x01, 0x02, 0x40};
  c.receive(bytes, b.rt.wall_now(), std::span<const std::uint8_t>(ambulance));
  EXPECT_EQ(c.counters().received, 2u);
  EXPECT_EQ(c.counters().not_permitted, 1u);
}

}  // namespace
}  // namespace tb::its::facilities
