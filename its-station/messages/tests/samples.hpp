#pragma once
/// @file The sample messages of the golden vectors, shared by the unit tests, the tshark
/// interoperability test, the fuzz seed writer and the benchmarks.

#include "its-station/messages/cam.hpp"
#include "its-station/messages/denm.hpp"

#include <vector>

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
  vehicle_hf(p)->accelerationControl =
      acceleration_control::kBrakePedalEngaged | acceleration_control::kAccEngaged;
  vehicle_hf(p)->steeringWheelAngle = SteeringWheelAngle{-20, 2};
  vehicle_hf(p)->lateralAcceleration = LateralAcceleration{-12, kAccelerationConfidenceUnavailable};
  BasicVehicleContainerLowFrequency& lf = p.lowFrequencyContainer.emplace();
  lf.vehicleRole = VehicleRole::default_;
  lf.exteriorLights = exterior_lights::kLowBeamHeadlightsOn | exterior_lights::kLeftTurnSignalOn;
  lf.pathHistory.push_back(PathPoint{{-1234, 567, kDeltaAltitudeUnavailable}, 10});
  lf.pathHistory.push_back(PathPoint{{131072, -131071, -12700}, std::nullopt});
  lf.pathHistory.push_back(PathPoint{{0, 0, 0}, 65535});
  return cam;
}

/// One CAM per special-vehicle container alternative (CHOICE index 0..6), every optional
/// component present.
inline std::vector<Cam> cams_special_vehicle() {
  std::vector<Cam> cams;
  auto with = [&](SpecialVehicleContainer c) {
    Cam cam = cam_hf();
    cam.cam.camParameters.specialVehicleContainer = c;
    cams.push_back(cam);
  };
  PublicTransportContainer pt{true, PtActivation{1, {0x01, 0x02, 0x03}}};
  with(pt);
  with(SpecialTransportContainer{0b1001, light_bar_siren::kLightBarActivated});
  with(DangerousGoodsContainer{19});
  ClosedLanes lanes{HardShoulderStatus::closed, HardShoulderStatus::availableForDriving,
                    DrivingLaneStatus{0b101, 3}};
  with(RoadWorksContainerBasic{4, light_bar_siren::kLightBarActivated, lanes});
  with(RescueContainer{light_bar_siren::kSirenActivated});
  with(EmergencyContainer{light_bar_siren::kLightBarActivated | light_bar_siren::kSirenActivated,
                          CauseCode{cause_code::kEmergencyVehicleApproaching, 1}, 0b01});
  with(SafetyCarContainer{light_bar_siren::kLightBarActivated, CauseCode{cause_code::kAccident, 2},
                          TrafficRule::passToLeft, 80});
  return cams;
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

/// A road-side unit's CAM: the RSU high-frequency container with two protected zones, one
/// with every optional component, one temporary (the extension value of ProtectedZoneType).
inline Cam cam_rsu() {
  Cam cam = cam_hf();
  cam.header.stationID = 5550001;
  cam.cam.camParameters.basicContainer.stationType = station_type::kRoadSideUnit;
  RSUContainerHighFrequency rsu;
  auto& zones = rsu.protectedCommunicationZonesRSU.emplace();
  zones.push_back(ProtectedCommunicationZone{ProtectedZoneType::permanentCenDsrcTolling,
                                             694224000000, 410260000, 289750000, 50, 12345});
  zones.push_back(ProtectedCommunicationZone{ProtectedZoneType::temporaryCenDsrcTolling,
                                             std::nullopt, 410270000, 289760000, std::nullopt,
                                             std::nullopt});
  cam.cam.camParameters.highFrequencyContainer = rsu;
  return cam;
}

/// The à-la-carte container with every member and every optional component present (values
/// of the golden table in denm_test.cpp).
inline AlacarteContainer alacarte_full() {
  AlacarteContainer a;
  a.lanePosition = 2;
  ImpactReductionContainer& ir = a.impactReduction.emplace();
  ir.heightLonCarrLeft = 40;
  ir.heightLonCarrRight = 41;
  ir.posLonCarrLeft = 50;
  ir.posLonCarrRight = 51;
  ir.positionOfPillars = {10, 25};
  ir.posCentMass = 20;
  ir.wheelBaseVehicle = 27;
  ir.turningRadius = 30;
  ir.posFrontAx = 9;
  ir.positionOfOccupants = (1u << 0) | (1u << 1) | (1u << 5);  // row 1 left and right, row 2 left
  ir.vehicleMass = 15;
  ir.requestResponseIndication = RequestResponseIndication::request;
  a.externalTemperature = -5;
  RoadWorksContainerExtended& rw = a.roadWorks.emplace();
  rw.lightBarSirenInUse = light_bar_siren::kLightBarActivated;
  rw.closedLanes =
      ClosedLanes{std::nullopt, HardShoulderStatus::closed, DrivingLaneStatus{0b10, 2}};
  rw.restriction = RestrictedTypes{station_type::kHeavyTruck, station_type::kBus};
  rw.speedLimit = 60;
  rw.incidentIndication = CauseCode{cause_code::kRoadworks, 1};
  rw.recommendedPath = ItineraryPath{istanbul()};
  rw.startingPointSpeedLimit = DeltaReferencePosition{100, -200, 0};
  rw.trafficFlowRule = TrafficRule::passToRight;
  rw.referenceDenms = ReferenceDenms{ActionID{1234567, 42}};
  a.positioningSolution = PositioningSolutionType::dGNSS;
  StationaryVehicleContainer& sv = a.stationaryVehicle.emplace();
  sv.stationarySince = StationarySince::lessThan2Minutes;
  sv.stationaryCause = CauseCode{cause_code::kStationaryVehicle, 2};
  DangerousGoodsExtended& g = sv.carryingDangerousGoods.emplace();
  g.dangerousGoodsType = 9;  // flammableLiquids
  g.unNumber = 1203;
  g.tunnelsRestricted = true;
  g.emergencyActionCode = char_string<24>("3YE");
  g.phoneNumber = char_string<24>("112");
  const char* company = "\xC3\x96lwerk";  // "Ölwerk": 6 characters in 7 octets
  g.companyName.emplace();
  for (const char* c = company; *c != '\0'; ++c)
    g.companyName->push_back(static_cast<std::uint8_t>(*c));
  sv.numberOfOccupants = 2;
  sv.vehicleIdentification = VehicleIdentification{char_string<3>("WVW"), char_string<6>("ZZZ1KZ")};
  sv.energyStorageType = 1u << 4;  // diesel
  return a;
}

/// Every CAM field present, at its lower (or upper) bound; the upper one has 40 path points.
inline Cam cam_at_bounds(bool upper) {
  Cam cam = cam_hf();
  cam.header.stationID = upper ? 4294967295u : 0u;
  cam.cam.generationDeltaTime = upper ? 65535 : 0;
  CamParameters& p = cam.cam.camParameters;
  p.basicContainer.stationType = upper ? 255 : 0;
  p.basicContainer.referencePosition =
      upper ? ReferencePosition{900000001,
                                1800000001,
                                {4095, 4095, 3601},
                                {800001, AltitudeConfidence::unavailable}}
            : ReferencePosition{
                  -900000000, -1800000000, {0, 0, 0}, {-100000, AltitudeConfidence::alt_000_01}};
  BasicVehicleContainerHighFrequency& hf = *vehicle_hf(p);
  hf.heading = upper ? Heading{3601, 127} : Heading{0, 1};
  hf.speed = upper ? Speed{16383, 127} : Speed{0, 1};
  hf.driveDirection = upper ? DriveDirection::unavailable : DriveDirection::forward;
  hf.vehicleLength = upper ? VehicleLength{1023, VehicleLengthConfidenceIndication::unavailable}
                           : VehicleLength{1, VehicleLengthConfidenceIndication::noTrailerPresent};
  hf.vehicleWidth = upper ? 62 : 1;
  hf.longitudinalAcceleration =
      upper ? LongitudinalAcceleration{161, 102} : LongitudinalAcceleration{-160, 0};
  hf.curvature = upper ? Curvature{1023, CurvatureConfidence::unavailable}
                       : Curvature{-1023, CurvatureConfidence::onePerMeter_0_00002};
  hf.curvatureCalculationMode =
      upper ? CurvatureCalculationMode::unavailable : CurvatureCalculationMode::yawRateUsed;
  hf.yawRate = upper ? YawRate{32767, YawRateConfidence::unavailable}
                     : YawRate{-32766, YawRateConfidence::degSec_000_01};
  hf.accelerationControl = upper ? 0x7F : 0;
  hf.lanePosition = static_cast<LanePosition>(upper ? 14 : -1);
  hf.steeringWheelAngle = upper ? SteeringWheelAngle{512, 127} : SteeringWheelAngle{-511, 1};
  hf.lateralAcceleration = upper ? LateralAcceleration{161, 102} : LateralAcceleration{-160, 0};
  hf.verticalAcceleration = upper ? VerticalAcceleration{161, 102} : VerticalAcceleration{-160, 0};
  hf.performanceClass = upper ? 7 : 0;
  hf.cenDsrcTollingZone = upper ? CenDsrcTollingZone{900000001, 1800000001, 134217727}
                                : CenDsrcTollingZone{-900000000, -1800000000, 0};
  BasicVehicleContainerLowFrequency& lf = p.lowFrequencyContainer.emplace();
  lf.vehicleRole = upper ? VehicleRole::reserved3 : VehicleRole::default_;
  lf.exteriorLights = upper ? 0xFF : 0;
  for (std::size_t i = 0; upper && i < kPathHistoryMaxPoints; ++i)
    lf.pathHistory.push_back(PathPoint{{131072, 131072, 12800}, 65535});
  return cam;
}

/// Every DENM field present, at its lower (or upper) bound; the upper one has 23 event points
/// and 7 traces of 40 points.
inline Denm denm_at_bounds(bool upper) {
  Denm d = denm_collision_risk();
  ManagementContainer& m = d.denm.management;
  m.actionID = {upper ? 4294967295u : 0u, static_cast<SequenceNumber>(upper ? 65535 : 0)};
  m.detectionTime = upper ? kTimestampItsMax : 0;
  m.referenceTime = upper ? kTimestampItsMax : 0;
  m.termination = upper ? Termination::isNegation : Termination::isCancellation;
  m.eventPosition.latitude = upper ? 900000001 : -900000000;
  m.eventPosition.longitude = upper ? 1800000001 : -1800000000;
  m.relevanceDistance = upper ? RelevanceDistance::over10km : RelevanceDistance::lessThan50m;
  m.relevanceTrafficDirection = upper ? RelevanceTrafficDirection::oppositeTraffic
                                      : RelevanceTrafficDirection::allTrafficDirections;
  m.validityDuration = upper ? 86400 : 0;
  m.transmissionInterval = static_cast<TransmissionInterval>(upper ? 10000 : 1);
  m.stationType = upper ? 255 : 0;
  SituationContainer& s = *d.denm.situation;
  s.informationQuality = upper ? 7 : 0;
  s.eventType = {static_cast<CauseCodeType>(upper ? 255 : 0),
                 static_cast<SubCauseCodeType>(upper ? 255 : 0)};
  s.linkedCause = CauseCode{cause_code::kAccident, 1};
  EventHistory& h = s.eventHistory.emplace();
  const std::size_t events = upper ? 23 : 1;
  for (std::size_t i = 0; i < events; ++i)
    h.push_back(EventPoint{{upper ? 131072 : -131071, upper ? 131072 : -131071,
                            static_cast<DeltaAltitude>(upper ? 12800 : -12700)},
                           static_cast<PathDeltaTime>(upper ? 65535 : 1),
                           static_cast<InformationQuality>(upper ? 7 : 0)});
  LocationContainer& l = *d.denm.location;
  l.eventSpeed = Speed{static_cast<SpeedValue>(upper ? 16383 : 0),
                       static_cast<SpeedConfidence>(upper ? 127 : 1)};
  l.eventPositionHeading = Heading{static_cast<HeadingValue>(upper ? 3601 : 0),
                                   static_cast<HeadingConfidence>(upper ? 127 : 1)};
  l.traces.clear();
  const std::size_t traces = upper ? 7 : 1;
  for (std::size_t t = 0; t < traces; ++t) {
    PathHistory& ph = l.traces.emplace_back();
    for (std::size_t i = 0; upper && i < kPathHistoryMaxPoints; ++i)
      ph.push_back(PathPoint{{131072, -131071, 12800}, 65535});
  }
  l.roadType = upper ? RoadType::nonUrban_WithStructuralSeparationToOppositeLanes
                     : RoadType::urban_NoStructuralSeparationToOppositeLanes;
  AlacarteContainer& a = d.denm.alacarte.emplace();
  a.lanePosition = static_cast<LanePosition>(upper ? 14 : -1);
  a.externalTemperature = static_cast<Temperature>(upper ? 67 : -60);
  a.positioningSolution =
      upper ? PositioningSolutionType::dR : PositioningSolutionType::noPositioningSolution;
  // Every à-la-carte member, at the ends of its ranges and sizes.
  ImpactReductionContainer& ir = a.impactReduction.emplace();
  ir.heightLonCarrLeft = ir.heightLonCarrRight = static_cast<HeightLonCarr>(upper ? 100 : 1);
  ir.posLonCarrLeft = ir.posLonCarrRight = static_cast<PosLonCarr>(upper ? 127 : 1);
  ir.positionOfPillars = upper ? PositionOfPillars{30, 30, 30} : PositionOfPillars{1};
  ir.posCentMass = static_cast<PosCentMass>(upper ? 63 : 1);
  ir.wheelBaseVehicle = static_cast<WheelBaseVehicle>(upper ? 127 : 1);
  ir.turningRadius = static_cast<TurningRadius>(upper ? 255 : 1);
  ir.posFrontAx = static_cast<PosFrontAx>(upper ? 20 : 1);
  ir.positionOfOccupants = upper ? 0xFFFFF : 0;
  ir.vehicleMass = static_cast<VehicleMass>(upper ? 1024 : 1);
  ir.requestResponseIndication =
      upper ? RequestResponseIndication::response : RequestResponseIndication::request;
  RoadWorksContainerExtended& rw = a.roadWorks.emplace();
  rw.lightBarSirenInUse = static_cast<LightBarSirenInUse>(upper ? 3 : 0);
  rw.closedLanes =
      ClosedLanes{HardShoulderStatus::availableForDriving, HardShoulderStatus::availableForStopping,
                  DrivingLaneStatus{static_cast<std::uint16_t>(upper ? 0x1FFF : 0),
                                    static_cast<std::uint8_t>(upper ? 13 : 1)}};
  rw.restriction = upper ? RestrictedTypes{255, 255, 255} : RestrictedTypes{0};
  rw.speedLimit = static_cast<SpeedLimit>(upper ? 255 : 1);
  rw.incidentIndication = CauseCode{static_cast<CauseCodeType>(upper ? 255 : 0),
                                    static_cast<SubCauseCodeType>(upper ? 255 : 0)};
  ItineraryPath& path = rw.recommendedPath.emplace();
  for (std::size_t i = 0; i < (upper ? 40u : 1u); ++i)
    path.push_back(m.eventPosition);
  rw.startingPointSpeedLimit = upper ? DeltaReferencePosition{131072, 131072, 12800}
                                     : DeltaReferencePosition{-131071, -131071, -12700};
  rw.trafficFlowRule = upper ? TrafficRule::passToLeft : TrafficRule::noPassing;
  ReferenceDenms& refs = rw.referenceDenms.emplace();
  for (std::size_t i = 0; i < (upper ? 8u : 1u); ++i)
    refs.push_back(m.actionID);
  StationaryVehicleContainer& sv = a.stationaryVehicle.emplace();
  sv.stationarySince =
      upper ? StationarySince::equalOrGreater15Minutes : StationarySince::lessThan1Minute;
  sv.stationaryCause = s.eventType;
  DangerousGoodsExtended& g = sv.carryingDangerousGoods.emplace();
  g.dangerousGoodsType = static_cast<DangerousGoodsBasic>(upper ? 19 : 0);
  g.unNumber = static_cast<std::uint16_t>(upper ? 9999 : 0);
  g.elevatedTemperature = g.tunnelsRestricted = g.limitedQuantity = upper;
  g.emergencyActionCode =
      upper ? char_string<24>("~~~~~~~~~~~~~~~~~~~~~~~~") : char_string<24>(" ");
  g.phoneNumber = upper ? char_string<24>("9999999999999999") : char_string<24>(" ");
  auto& company = g.companyName.emplace();
  for (std::size_t i = 0; i < (upper ? 24u : 1u); ++i)
    for (std::uint8_t b : {0xF0, 0x9F, 0x9A, 0x97})  // U+1F697 AUTOMOBILE, 4 octets
      company.push_back(b);
  sv.numberOfOccupants = static_cast<NumberOfOccupants>(upper ? 127 : 0);
  sv.vehicleIdentification =
      VehicleIdentification{upper ? char_string<3>("ZZZ") : char_string<3>("A"),
                            char_string<6>(upper ? "~~~~~~" : "      ")};
  sv.energyStorageType = static_cast<EnergyStorageType>(upper ? 0x7F : 0);
  return d;
}

/// @p d as protocolVersion 1: the same but for what CDD version 1 cannot carry (an inner hard
/// shoulder; its ClosedLanes has one hard shoulder only).
inline Denm as_version1(Denm d) {
  d.header.protocolVersion = kProtocolVersion1;
  if (d.denm.alacarte && d.denm.alacarte->roadWorks && d.denm.alacarte->roadWorks->closedLanes)
    d.denm.alacarte->roadWorks->closedLanes->innerhardShoulderStatus.reset();
  return d;
}

}  // namespace tb::its::messages::samples
