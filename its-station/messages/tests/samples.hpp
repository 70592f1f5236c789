#pragma once
/// @file The sample messages of the golden vectors, shared by the unit tests, the tshark
/// interoperability test, the fuzz seed writer and the benchmarks.

#include "its-station/messages/cam.hpp"
#include "its-station/messages/denm.hpp"

namespace tb::its::messages::samples {

inline ReferencePosition istanbul() {
  ReferencePosition p;
  p.latitude = 410255000;   // 41.0255°
  p.longitude = 289742000;  // 28.9742°
  p.positionConfidenceEllipse = {500, 300, 900};
  p.altitude = {4000, AltitudeConfidence::alt_002_00};
  return p;
}

inline BasicVehicleContainerHighFrequency passenger_car_hf() {
  BasicVehicleContainerHighFrequency hf;
  hf.heading = {900, 10};
  hf.speed = {1389, 100};
  hf.driveDirection = DriveDirection::forward;
  hf.vehicleLength = {45, VehicleLengthConfidenceIndication::noTrailerPresent};
  hf.vehicleWidth = 18;
  hf.longitudinalAcceleration = {5, 10};
  hf.curvature = {0, CurvatureConfidence::unavailable};
  hf.curvatureCalculationMode = CurvatureCalculationMode::yawRateUsed;
  hf.yawRate = {-150, YawRateConfidence::degSec_001_00};
  return hf;
}

/// The 41-byte high-frequency-only passenger-car CAM.
inline Cam cam_hf() {
  Cam cam;
  cam.header.stationID = 1234567;
  cam.cam.generationDeltaTime = 12345;
  cam.cam.camParameters.basicContainer.stationType = station_type::kPassengerCar;
  cam.cam.camParameters.basicContainer.referencePosition = istanbul();
  cam.cam.camParameters.highFrequencyContainer = passenger_car_hf();
  return cam;
}

/// A CAM at the edges of several ranges, with HF optional fields, the LF container and three
/// path points.
inline Cam cam_lf() {
  Cam cam;
  cam.header.stationID = 7654321;
  cam.cam.generationDeltaTime = 65535;
  CamParameters& p = cam.cam.camParameters;
  p.basicContainer.referencePosition.latitude = -338688000;
  p.basicContainer.referencePosition.longitude = 1512093000;
  p.basicContainer.referencePosition.positionConfidenceEllipse = {
      kSemiAxisLengthUnavailable, kSemiAxisLengthOutOfRange, kHeadingValueUnavailable};
  p.basicContainer.referencePosition.altitude = {-100000, AltitudeConfidence::unavailable};
  p.highFrequencyContainer = passenger_car_hf();
  p.highFrequencyContainer.accelerationControl =
      acceleration_control::kBrakePedalEngaged | acceleration_control::kAccEngaged;
  p.highFrequencyContainer.steeringWheelAngle = SteeringWheelAngle{-20, 2};
  p.highFrequencyContainer.lateralAcceleration =
      LateralAcceleration{-12, kAccelerationConfidenceUnavailable};
  BasicVehicleContainerLowFrequency& lf = p.lowFrequencyContainer.emplace();
  lf.vehicleRole = VehicleRole::default_;
  lf.exteriorLights = exterior_lights::kLowBeamHeadlightsOn | exterior_lights::kLeftTurnSignalOn;
  lf.pathHistory.push_back(PathPoint{{-1234, 567, kDeltaAltitudeUnavailable}, 10});
  lf.pathHistory.push_back(PathPoint{{131072, -131071, -12700}, std::nullopt});
  lf.pathHistory.push_back(PathPoint{{0, 0, 0}, 65535});
  return cam;
}

/// A passenger-car CAM with the LF container and @p points path points (a car driving north).
inline Cam cam_with_path(std::size_t points) {
  Cam cam = cam_hf();
  BasicVehicleContainerLowFrequency& lf = cam.cam.camParameters.lowFrequencyContainer.emplace();
  lf.exteriorLights = exterior_lights::kLowBeamHeadlightsOn;
  for (std::size_t i = 0; i < points && i < kPathHistoryMaxPoints; ++i) {
    const auto k = static_cast<std::int32_t>(i + 1);
    lf.pathHistory.push_back(PathPoint{{-k * 1250, k * 37, static_cast<DeltaAltitude>(-k * 3)},
                                       static_cast<PathDeltaTime>(k * 100)});
  }
  return cam;
}

/// The DENM of the LCRW use case: collision risk (97), longitudinal (1).
inline Denm denm_collision_risk() {
  Denm d;
  d.header.stationID = 1234567;
  ManagementContainer& m = d.denm.management;
  m.actionID = {1234567, 42};
  m.detectionTime = 694224000000;
  m.referenceTime = 694224000100;
  m.eventPosition = istanbul();
  m.relevanceDistance = RelevanceDistance::lessThan200m;
  m.relevanceTrafficDirection = RelevanceTrafficDirection::upstreamTraffic;
  m.validityDuration = 10;
  m.transmissionInterval = 100;
  m.stationType = station_type::kPassengerCar;
  SituationContainer& s = d.denm.situation.emplace();
  s.informationQuality = 3;
  s.eventType = {cause_code::kCollisionRisk, collision_risk_sub_cause::kLongitudinalCollisionRisk};
  LocationContainer& l = d.denm.location.emplace();
  l.eventSpeed = Speed{1389, 100};
  l.eventPositionHeading = Heading{900, 10};
  PathHistory& trace = l.traces.emplace_back();
  trace.push_back(PathPoint{{100, -100, 0}, 50});
  trace.push_back(PathPoint{{250, -250, -10}, std::nullopt});
  l.roadType = RoadType::nonUrban_WithStructuralSeparationToOppositeLanes;
  return d;
}

}  // namespace tb::its::messages::samples
