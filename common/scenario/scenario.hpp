#pragma once
/// @file The scenario model: everything a run of the testbed is configured from.
///
/// Loaded from JSON by scenario/loader.hpp, documented field by field in docs/scenario.md.
/// Units are SI (metres, seconds, m/s, radians for internal angles) unless a field's name says
/// otherwise (_deg, _kmh, _ms, _hz, _dbm, _db).

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "common/geodesy/wgs84.hpp"

namespace tb::map::odr {
struct RoadNetwork;
}

namespace tb::scenario {

// ---------------------------------------------------------------------------------------------
// Map: an OpenDRIVE file, or a built-in road layout generated into the same model
// (common/map/builtin_network.hpp). Geometry lives in common/map.

enum class MapType { kStraight, kRing, kCrossing, kOpenDrive };

struct MapSpec {
  MapType type = MapType::kStraight;
  /// opendrive: the file as the scenario names it (relative to the scenario file).
  std::string file = {};
  // Built-in layouts only:
  int lanes = 2;              ///< lanes per road, counted from the right edge
  int oncoming_lanes = 1;     ///< how many of them (the leftmost) run the other way
  double lane_width = 3.5;    ///< m
  double length = 1000.0;     ///< straight: road length along +x from x = 0, m
  double radius = 150.0;      ///< ring: radius of the road's centre line, m
  double arm_length = 300.0;  ///< crossing: length of each of the four arms from the centre, m
};

// ---------------------------------------------------------------------------------------------
// Vehicle model. Defaults: a compact passenger car, the Volkswagen Golf VII 1.4 TSI (90 kW);
// figures from the manufacturer's 2013 data sheet: 0–100 km/h 9.3 s, top speed 203 km/h,
// turning circle 10.9 m, kerb weight 1270 kg (see sim-server/README.md for the checks).

struct TorquePoint {
  double rpm = 0.0;
  double torque_nm = 0.0;
};

/// Where the GNSS antenna sits, relative to the centre of the vehicle's bounding box on the
/// ground (horizontal only: the fix is moved to the ground reference point, EN 302 637-2 B.3).
/// Default: a roof antenna at the centre.
struct GnssAntenna {
  double forward_m = 0.0;
  double left_m = 0.0;
};

struct VehicleModel {
  double mass_kg = 1270.0;
  double length_m = 4.255;
  double width_m = 1.799;
  double height_m = 1.452;
  double wheelbase_m = 2.637;
  double track_m = 1.540;
  double wheel_radius_m = 0.316;          ///< 205/55 R16
  double centre_of_mass_height_m = 0.55;  ///< above the ground
  double suspension_stiffness = 35.0;     ///< per unit mass (Bullet's convention), 1/s²
  double suspension_damping = 4.5;        ///< relative damping in compression and relaxation
  double suspension_travel_m = 0.15;
  double tyre_friction = 1.0;  ///< peak friction coefficient on a dry road
  /// 200 Nm from 1500 to 4000 rpm, 90 kW from 5000 to 6000 rpm (data sheet).
  std::vector<TorquePoint> torque_curve{{1000, 140}, {1500, 200}, {4000, 200},
                                        {5000, 172}, {6000, 143}, {6500, 120}};
  std::vector<double> gear_ratios{3.62, 2.13, 1.37, 0.97, 0.76, 0.62};
  double reverse_ratio = 3.3;
  double final_drive = 3.94;
  double drivetrain_efficiency = 0.9;
  double idle_rpm = 800.0;
  double shift_up_rpm = 6000.0;
  double shift_down_rpm = 2000.0;
  /// All four wheels together, at full pedal: enough to reach the tyres' grip on a dry road
  /// at every wheel (a stop from 100 km/h in about 36 m, sim-server/README.md).
  double brake_torque_nm = 5000.0;
  double handbrake_torque_nm = 1500.0;  ///< rear wheels
  double max_steer_deg = 36.0;          ///< road-wheel angle at full lock
  double steering_ratio = 14.8;         ///< steering-wheel angle / road-wheel angle
  double drag_coefficient = 0.30;       ///< Cd
  double frontal_area_m2 = 2.19;
  double rolling_resistance = 0.011;  ///< coefficient
  GnssAntenna antenna;
};

// ---------------------------------------------------------------------------------------------
// Spawn: a lane and a distance along it, or an explicit pose in the local frame.

/// A lane of a built-in layout (its own numbering; common/map turns it into RoadSpawn's form).
struct LaneSpawn {
  int road = 0;  ///< crossing: 0 = east–west road, 1 = north–south road
  int lane = 0;
  double s = 0.0;        ///< distance along the lane in its direction of travel, m
  bool against = false;  ///< drive against the lane's direction (head-on cases)
};

/// A lane of the map's OpenDRIVE network: the spawn form of OpenDRIVE maps.
struct RoadSpawn {
  std::string road;      ///< OpenDRIVE road id
  int lane = 0;          ///< OpenDRIVE lane id: negative right of the reference line
  double s = 0.0;        ///< along the road's reference line (OpenDRIVE s), m
  double offset = 0.0;   ///< left of the lane's centre (seen along s), m
  bool against = false;  ///< face against the lane's direction of travel
};

struct PoseSpawn {
  double x = 0.0;            ///< east, m
  double y = 0.0;            ///< north, m
  double heading_deg = 0.0;  ///< ETSI convention: clockwise from north
};

struct Spawn {
  std::variant<LaneSpawn, PoseSpawn, RoadSpawn> where;
  double speed = 0.0;  ///< initial speed, m/s
};

// ---------------------------------------------------------------------------------------------
// Drivers.

struct HumanDriver {};

/// At t seconds: controls; each entry holds until the next one.
struct ControlStep {
  double t = 0.0;
  double throttle = 0.0;  ///< [0, 1]
  double brake = 0.0;     ///< [0, 1]
  double steer = 0.0;     ///< [-1, 1], positive = right (as CARLA)
  bool reverse = false;
  bool handbrake = false;
};
struct TimelineDriver {
  std::vector<ControlStep> steps;
};

/// Target speed, interpolated linearly between points given over time or over distance.
struct SpeedPoint {
  double at = 0.0;     ///< s (time) or m (distance), see LaneFollowDriver::by_distance
  double speed = 0.0;  ///< m/s
};
/// A lane position named in the scenario: OpenDRIVE road id, lane id, s along the road (m).
struct RouteGoal {
  std::string road;
  int lane = 0;
  double s = 0.0;
};

/// Where a lane-following driver goes when its lane ends or forks (docs/scenario.md).
struct DriveRoute {
  enum class Kind {
    kLane,    ///< no route given: the lane and its straightest continuation
    kRandom,  ///< "random": a random successor at every fork, seeded by Scenario::seed
    kRoads,   ///< a list of road ids driven in order
    kTo,      ///< "to": the shortest path to a lane position
  };
  Kind kind = Kind::kLane;
  std::vector<std::string> roads;  ///< kRoads
  RouteGoal to;                    ///< kTo
};

struct LaneFollowDriver {
  std::vector<SpeedPoint> profile;
  bool by_distance = false;
  double max_accel = 2.0;          ///< comfortable acceleration, m/s²
  double max_decel = 3.0;          ///< comfortable deceleration, m/s²
  double max_lateral_accel = 3.0;  ///< slows for curves to keep v²·curvature below this, m/s²
  DriveRoute route;
  /// Follow the vehicle ahead and yield at junctions ("traffic": "yield"), or drive the
  /// profile whatever the others do ("ignore", the scripted near misses of the LCRW cases).
  /// Default: yield when a route is given, ignore otherwise.
  bool yield_to_traffic = false;
  /// Stop for red, red + amber and an amber it can stop for comfortably at the stop lines of
  /// signalised junctions (issue 34; sim-client/README.md, "Scripted drivers"); false runs
  /// every light (a test of the red-light warning).
  bool obey_signals = true;
};

using Driver = std::variant<HumanDriver, TimelineDriver, LaneFollowDriver>;

/// The vehicle's role in road traffic: CDD VehicleRole (TS 102 894-2), the enumerator's value
/// being the CDD's. Its station says it in the CAM's low-frequency container and, for the roles
/// 1 to 7, sends the special-vehicle container of that role (EN 302 637-2 B.2.x).
enum class VehicleRole : std::uint8_t {
  kDefault = 0,
  kPublicTransport = 1,
  kSpecialTransport = 2,
  kDangerousGoods = 3,
  kRoadWork = 4,
  kRescue = 5,
  kEmergency = 6,
  kSafetyCar = 7,
  kAgriculture = 8,
  kCommercial = 9,
  kMilitary = 10,
  kRoadOperator = 11,
  kTaxi = 12,
};

/// "station": {"kind": ...}: where a vehicle's ITS station runs (issue 33). A full station is a
/// process of its own (its-station, or the vehicle's "command"); pooled stations run, many to a
/// process, inside station-host, fed from the emulator's state stream.
enum class StationKind { kFull, kPooled };

struct Vehicle {
  std::string id;
  std::uint32_t station_id = 0;   ///< ETSI StationID
  int station_type = 5;           ///< CDD StationType: 5 = passengerCar
  std::string color = "#d02020";  ///< for the drivers' views
  VehicleModel model;
  Spawn spawn;
  Driver driver;
  /// "station": {"command": [...]}: a program run in place of its-station for this vehicle
  /// (bring your own stack, docs/station-contract.md); empty: its-station. Placeholders such as
  /// {station_id} are the launcher's to fill.
  std::vector<std::string> station_command;
  /// "station": {"pki": NAME}: the test PKI this station's certificates come from and whose
  /// root it trusts, when not the scenario's (security signed): the launcher makes PKI NAME
  /// beside the scenario's. Stations of different PKIs drop each other's packets
  /// (untrusted_root): a foreign or misconfigured vehicle. Empty: the scenario's PKI.
  std::string station_pki;
  /// "station": {"kind": "full" | "pooled"}. Pooled needs a scripted driver and its-station's
  /// stack (no "command").
  StationKind station_kind = StationKind::kFull;
  /// "station": {"mqtt": bool}: whether the station mirrors its state to MQTT. Default true for
  /// full stations; false for pooled ones (hundreds of mirrors at 10 Hz would flood the broker).
  bool station_mqtt = true;
  /// "station": {"lcrw": bool}: whether the station runs LCRW. Default true for full stations,
  /// false for pooled ones.
  bool station_lcrw = true;
  /// "station": {"signals": bool}: whether the station runs the signal application (MAPEM and
  /// SPATEM received, RLVW, GLOSA; issue 34). Default true for full stations, false for pooled
  /// ones (which then neither decode nor verify MAPEM/SPATEM).
  bool station_signals = true;
  /// "role": a CDD VehicleRole name ("emergency", "publicTransport", …).
  VehicleRole role = VehicleRole::kDefault;
  /// "dangerous_goods": the CDD DangerousGoodsBasic (0 explosives1 … 19
  /// miscellaneousDangerousSubstances) a "dangerousGoods" vehicle carries; only for that role.
  std::optional<int> dangerous_goods;
  /// "lights": the light switches (wire::Light bits) on from the start. A scripted driver keeps
  /// them; a human driver starts from them and switches with the keys.
  std::uint16_t lights = 0;
};

// ---------------------------------------------------------------------------------------------
// Rates, positioning errors, CAM policy and the radio channel.

struct Rates {
  double physics_hz = 100.0;
  double gnss_hz = 10.0;
  double can_dynamics_hz = 100.0;
  double can_body_hz = 10.0;
};

struct FixLossWindow {
  double from_s = 0.0;
  double to_s = 0.0;
};

/// GNSS receiver error model (network-emulator's GPS agents). ideal = no noise.
struct GnssErrors {
  bool ideal = true;
  double white_noise_m = 0.0;  ///< horizontal 1-sigma per axis
  double bias_walk_m = 0.0;    ///< random-walk intensity, m/√s per axis
  double vertical_noise_m = 0.0;
  double hdop = 0.9;
  double vdop = 1.2;
  int satellites = 9;
  std::vector<FixLossWindow> fix_loss;
};

struct CamPolicy {
  enum class Kind { kEtsi, kFixed };
  Kind kind = Kind::kEtsi;
  double period_ms = 100.0;  ///< fixed policy only
};

struct ChannelModel {
  enum class Kind { kIdeal, kRange, kLogDistance, kTwoRay };
  Kind kind = Kind::kIdeal;
  double range_m = 300.0;            ///< range model
  double tx_power_dbm = 23.0;        ///< log-distance and two-ray
  double sensitivity_dbm = -85.0;    ///< frames received below this are lost
  double reference_loss_db = 47.86;  ///< log-distance: loss at 1 m (free space at 5.9 GHz)
  double path_loss_exponent = 2.0;   ///< log-distance
  double antenna_height_m = 1.5;     ///< two-ray
  double frequency_mhz = 5900.0;
  double packet_error_rate = 0.0;  ///< extra random loss on links in range, [0, 1]
  double delay_ms = 0.0;
  double jitter_ms = 0.0;
};

/// `security` (issue 20): what the stations do with TS 103 097 signatures. Stations of one
/// scenario trust its test PKI's root (its-pki).
enum class SecurityMode {
  kNone,              ///< unsecured packets only
  kSigned,            ///< sign; verify and drop what fails
  kSignedPermissive,  ///< sign; pass up what fails verification, with the reason
};

/// One entry of `security_time_windows` (issue 31): how far a signed packet's generationTime may
/// lie before (past_ms) and after (future_ms) a receiving station's time, for one ITS-AID. What
/// is not given keeps the station's default for that ITS-AID (its-station/security/verifier.hpp).
struct SecurityTimeWindow {
  std::optional<std::int64_t> past_ms;
  std::optional<std::int64_t> future_ms;
};

// ---------------------------------------------------------------------------------------------
// Traffic lights (issue 34): a fixed-time plan per signalised junction of the map. Signal
// groups are the OpenDRIVE file's <controller>s (id = SignalGroupID, ISO TS 19091); the
// junction is the OpenDRIVE junction (id = IntersectionID).

/// One phase of a fixed-time plan: the signal groups that are green together, for how long.
struct SignalPhase {
  std::vector<int> green;  ///< SignalGroupIDs, ascending
  double duration_s = 20.0;
};

/// `signals[]`: how one junction's lights run. The cycle is the phases in order, each its green
/// time and then the change to the next: amber for the groups that lose green, all-red, and
/// red+amber for the groups that gain it; a group green in both phases stays green. The cycle
/// starts offset_s after the world's start time (docs/scenario.md, "Signals").
struct SignalPlan {
  std::string junction;  ///< OpenDRIVE junction id
  double offset_s = 0.0;
  double amber_s = 3.0;      ///< MovementPhaseState protected-clearance (8)
  double all_red_s = 2.0;    ///< every group stop-And-Remain (3)
  double red_amber_s = 0.0;  ///< pre-Movement (4); 0: none (German practice has 1 s)
  std::vector<SignalPhase> phases;
  /// Chosen by the loader: the map has lights at the junction and the scenario no plan.
  bool default_plan = false;
  /// Every group the junction has (ascending), whether or not a phase names it.
  std::vector<int> groups;
  /// One cycle: the phases' green times and one change after each.
  double cycle_s() const;
};

// ---------------------------------------------------------------------------------------------
// Road-side units (issue 34): full ITS stations of type roadSideUnit (CDD StationType 15) that
// serve one signalised junction with MAPEM and SPATEM. No CAN, no driver; the network emulator
// feeds their fixed position through gpsd and their junction's signal states over UDP.

struct Rsu {
  std::string id;                ///< like a vehicle id: names the station's namespace and login
  std::uint32_t station_id = 0;  ///< ETSI StationID, unique across vehicles and RSUs
  std::string junction;          ///< OpenDRIVE junction id of the signalised junction it serves
  double x = 0.0, y = 0.0;       ///< map frame (as a pose spawn), m
  double height_m = 0.0;         ///< antenna above the ground, m
};

/// The warm-up a scenario gets unless it says otherwise: a GNSS receiver reports its first fix
/// about 1.3 s after its first epoch (gpsd waits for a whole cycle), and a CAM follows; 3 s
/// leaves room for that on a loaded machine.
inline constexpr double kDefaultWarmupS = 3.0;
inline constexpr double kMaxWarmupS = 60.0;

struct Scenario {
  std::string name;
  std::string description;
  std::string source;  ///< the file it was loaded from, for messages
  MapSpec map;
  /// The road network of the map: the OpenDRIVE file read, or the built-in layout generated
  /// (never null after loading). Shared, immutable.
  std::shared_ptr<const map::odr::RoadNetwork> network;
  /// opendrive: the file's text, as sim-server hands it to its clients; null for built-in maps.
  std::shared_ptr<const std::string> map_text;
  /// The `origin` field: where (0, 0, 0) of the local frame lies, unless the OpenDRIVE file's
  /// geoReference says (common/map/scenario_map.hpp decides).
  std::optional<geodesy::Geodetic> origin;
  /// UTC instant of sim time 0 when the scenario pins it (`start_time`); GNSS fixes are stamped
  /// start time + sim time. Empty: the world starts at the host's clock when sim-server starts
  /// (world_start()), so that the world runs on real time (docs/time.md).
  std::optional<std::chrono::system_clock::time_point> start_time;
  std::optional<double> duration_s;  ///< empty: run until stopped, counted from sim time 0
  /// Sim time before 0 during which sim-server holds every vehicle on its run-up to its spawn
  /// pose (sim time runs from -warmup_s), so that at sim time 0 every station already has a
  /// fix and sends CAMs (docs/scenario.md, "Warm-up").
  double warmup_s = kDefaultWarmupS;
  Rates rates;
  GnssErrors gnss;
  CamPolicy cam;
  ChannelModel channel;
  SecurityMode security = SecurityMode::kNone;
  /// `security_time_windows`: by ITS-AID (PSID: 36 CAM, 37 DENM, 141 GN-MGMT, ...).
  std::map<std::uint64_t, SecurityTimeWindow> security_time_windows;
  /// Seeds the scenario's random choices (random routes), so that a run repeats.
  std::uint64_t seed = 1;
  std::vector<Vehicle> vehicles;
  /// One plan per signalised junction of the map (given, or the default), in the order of the
  /// scenario's `signals`, then the defaults by junction id.
  std::vector<SignalPlan> signals;
  /// `rsus`: the road-side units, in the scenario's order.
  std::vector<Rsu> rsus;

  const Vehicle* find_vehicle(std::string_view id) const;
  /// The vehicle with that StationID; nullptr for an RSU's or an unknown one.
  const Vehicle* find_station(std::uint32_t station_id) const;
  /// The RSU with that StationID; nullptr for a vehicle's or an unknown one.
  const Rsu* find_rsu(std::uint32_t station_id) const;
};

/// The world's start time (UTC of sim time 0) of a run that starts at @p now: the scenario's
/// pinned start_time, else @p now rounded down to the second. sim-server fixes it once and hands
/// it to every program (docs/time.md).
inline std::chrono::system_clock::time_point world_start(
    const Scenario& s, std::chrono::system_clock::time_point now) {
  return s.start_time ? *s.start_time : std::chrono::floor<std::chrono::seconds>(now);
}

}  // namespace tb::scenario
