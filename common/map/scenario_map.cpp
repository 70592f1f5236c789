#include "common/map/scenario_map.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "common/geodesy/local_frame.hpp"
#include "common/map/builtin_network.hpp"
#include "common/map/opendrive/geo_reference.hpp"

namespace tb::map {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// A map's geoReference as the testbed's georeferencing.
class ProjGeoreferencing final : public geodesy::Georeferencing {
 public:
  explicit ProjGeoreferencing(odr::GeoReference g) : g_(std::move(g)) {}
  geodesy::Geodetic to_geodetic(const geodesy::Enu& p) const override {
    return g_.to_wgs84(p.east, p.north, p.up);
  }
  geodesy::Enu to_local(const geodesy::Geodetic& g) const override {
    geodesy::Enu p;
    g_.from_wgs84(g, p.east, p.north, p.up);
    return p;
  }
  /// Grid north is not true north away from the projection's central meridian: the bearing of
  /// a point 10 m along the direction, in the ellipsoidal ENU frame at p, is the true heading.
  double heading_deg(const geodesy::Enu& p, double yaw_rad) const override {
    constexpr double kStep = 10.0;
    const geodesy::Geodetic a = to_geodetic(p);
    const geodesy::Geodetic b = to_geodetic(
        {p.east + kStep * std::cos(yaw_rad), p.north + kStep * std::sin(yaw_rad), p.up});
    const geodesy::Enu d = geodesy::LocalFrame(a).to_enu(b);
    return geodesy::yaw_to_heading_deg(std::atan2(d.north, d.east));
  }

 private:
  odr::GeoReference g_;
};

bool all_zero(const odr::CubicProfile& p) {
  return std::all_of(p.records().begin(), p.records().end(), [](const odr::CubicRecord& r) {
    return r.a == 0.0 && r.b == 0.0 && r.c == 0.0 && r.d == 0.0;
  });
}

bool is_flat(const odr::RoadNetwork& net) {
  return std::all_of(net.roads.begin(), net.roads.end(), [](const odr::Road& r) {
    return all_zero(r.elevation) && all_zero(r.superelevation);
  });
}

/// Normal of the road surface whose s direction has @p heading and @p pitch (positive uphill)
/// and whose left side is raised by @p roll: the cross product of the s and t directions.
void surface_normal(double heading, double pitch, double roll, double n[3]) {
  const double ts[3] = {std::cos(heading) * std::cos(pitch), std::sin(heading) * std::cos(pitch),
                        std::sin(pitch)};
  // Lateral positions are not foreshortened (road_network.hpp): t moves along the horizontal
  // normal of the reference line and z by tan(roll) per metre.
  const double tt[3] = {-std::sin(heading), std::cos(heading), std::tan(roll)};
  n[0] = ts[1] * tt[2] - ts[2] * tt[1];
  n[1] = ts[2] * tt[0] - ts[0] * tt[2];
  n[2] = ts[0] * tt[1] - ts[1] * tt[0];
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (int i = 0; i < 3; ++i)
    n[i] /= len;
}

Placement on_surface(double x, double y, double z, double yaw, double heading, double pitch,
                     double roll) {
  double n[3];
  surface_normal(heading, pitch, roll, n);
  Placement p{x, y, z, yaw, 0.0, 0.0};
  orientation_on(n[0], n[1], n[2], yaw, p.pitch, p.roll);
  return p;
}

}  // namespace

void orientation_on(double nx, double ny, double nz, double yaw, double& pitch, double& roll) {
  // Forward: the horizontal direction of yaw projected onto the surface; left = n x forward.
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double dot = c * nx + s * ny;
  double f[3] = {c - dot * nx, s - dot * ny, -dot * nz};
  const double fl = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
  for (double& v : f)
    v /= fl;
  const double lz = nx * f[1] - ny * f[0];
  // ZYX angles of the rotation whose columns are forward, left, normal.
  pitch = -std::asin(std::clamp(f[2], -1.0, 1.0));
  roll = std::atan2(lz, nz);
}

ScenarioMap::ScenarioMap(std::shared_ptr<const odr::RoadNetwork> network,
                         std::optional<geodesy::Geodetic> origin)
    : network_(std::move(network)) {
  if (network_ == nullptr)
    throw std::invalid_argument("ScenarioMap: no road network");
  flat_ = is_flat(*network_);
  if (!network_->header.geo_reference.empty()) {
    odr::GeoReference g(network_->header.geo_reference, network_->source);
    notes_ = g.notes();
    origin_ = {"geoReference", g.to_wgs84(0.0, 0.0, 0.0)};
    if (origin) {
      notes_.push_back(
          "the scenario's origin is not used: the map's geoReference places the "
          "frame");
    }
    geo_ = std::make_unique<ProjGeoreferencing>(std::move(g));
  } else if (origin) {
    geo_ = std::make_unique<geodesy::LocalFrame>(*origin);
    origin_ = {"scenario origin", origin};
  } else {
    origin_ = {"none", std::nullopt};
  }
}

ScenarioMap::ScenarioMap(const scenario::MapSpec& builtin, std::optional<geodesy::Geodetic> origin)
    : ScenarioMap(std::make_shared<const odr::RoadNetwork>(generate_network(builtin)), origin) {
  builtin_ = builtin;
}

ScenarioMap::ScenarioMap(const scenario::Scenario& scenario)
    : ScenarioMap(scenario.network != nullptr || scenario.map.type == scenario::MapType::kOpenDrive
                      ? scenario.network
                      : std::make_shared<const odr::RoadNetwork>(generate_network(scenario.map)),
                  scenario.origin) {
  if (scenario.map.type != scenario::MapType::kOpenDrive)
    builtin_ = scenario.map;
  if (!placed()) {
    throw odr::MapError(network_->source, "header/geoReference",
                        "the map has no geoReference and the scenario gives no origin: nothing "
                        "places the frame on the Earth");
  }
}

ScenarioMap::~ScenarioMap() = default;

const odr::LaneLocator& ScenarioMap::locator() const {
  std::call_once(locator_once_,
                 [this] { locator_ = std::make_unique<odr::LaneLocator>(*network_); });
  return *locator_;
}

const odr::LaneGraph& ScenarioMap::graph() const {
  std::call_once(graph_once_, [this] { graph_ = std::make_unique<odr::LaneGraph>(*network_); });
  return *graph_;
}

const odr::SignalLayout& ScenarioMap::signals() const {
  std::call_once(signals_once_,
                 [this] { signals_ = std::make_unique<odr::SignalLayout>(*network_); });
  return *signals_;
}

const geodesy::Georeferencing& ScenarioMap::georeferencing() const {
  if (geo_ == nullptr) {
    throw odr::MapError(network_->source, "header/geoReference",
                        "the map is not placed on the Earth (no geoReference, no origin)");
  }
  return *geo_;
}

geodesy::Geodetic ScenarioMap::to_wgs84(double x, double y, double z) const {
  return georeferencing().to_geodetic({x, y, z});
}

scenario::RoadSpawn ScenarioMap::network_spawn(const scenario::LaneSpawn& l) const {
  if (!builtin_)
    throw std::invalid_argument("a built-in lane spawn on a map that is not a built-in layout");
  const scenario::MapSpec& spec = *builtin_;
  scenario::RoadSpawn r;
  r.road = std::to_string(l.road);
  r.lane = opendrive_lane_id(spec, l.lane);
  r.against = l.against;
  const bool oncoming = l.lane >= spec.lanes - spec.oncoming_lanes;
  switch (spec.type) {
    case scenario::MapType::kStraight:
    case scenario::MapType::kCrossing: {
      // Built-in s runs along the lane's direction of travel (road_map.hpp), OpenDRIVE s along
      // the reference line; both clamp to the road.
      const double len =
          spec.type == scenario::MapType::kStraight ? spec.length : 2.0 * spec.arm_length;
      const double s = std::clamp(l.s, 0.0, len);
      r.s = oncoming ? len - s : s;
      break;
    }
    case scenario::MapType::kRing: {
      // A lane's circle has its own radius; the angle from the easternmost point is what both
      // numberings share.
      const double offset = -spec.lanes * spec.lane_width / 2.0 + (l.lane + 0.5) * spec.lane_width;
      const double angle = l.s / (spec.radius - offset);
      double a = std::fmod(oncoming ? -angle : angle, kTwoPi);
      if (a < 0.0)
        a += kTwoPi;
      r.s = std::min(a * spec.radius, network_->roads.front().length);
      break;
    }
    case scenario::MapType::kOpenDrive:
      throw std::invalid_argument("a built-in lane spawn on an OpenDRIVE map");
  }
  return r;
}

Placement ScenarioMap::place(const scenario::RoadSpawn& spawn) const {
  odr::SurfacePose p = odr::spawn_pose(*network_, {spawn.road, spawn.lane, spawn.s, spawn.offset});
  if (spawn.against) {
    p.heading = std::remainder(p.heading + std::numbers::pi, kTwoPi);
    p.pitch = -p.pitch;
    p.roll = -p.roll;
  }
  return on_surface(p.x, p.y, p.z, p.heading, p.heading, p.pitch, p.roll);
}

Placement ScenarioMap::place(const scenario::Spawn& spawn) const {
  if (const auto* l = std::get_if<scenario::LaneSpawn>(&spawn.where))
    return place(network_spawn(*l));
  if (const auto* r = std::get_if<scenario::RoadSpawn>(&spawn.where))
    return place(*r);
  const auto& pose = std::get<scenario::PoseSpawn>(spawn.where);
  const double yaw = geodesy::heading_deg_to_yaw(pose.heading_deg);
  if (flat_)
    return {pose.x, pose.y, 0.0, yaw, 0.0, 0.0};
  const auto at = locator().locate(pose.x, pose.y);
  if (!at)
    return {pose.x, pose.y, 0.0, yaw, 0.0, 0.0};
  const odr::Road& road = network_->roads[static_cast<std::size_t>(at->ref.road)];
  const odr::SurfacePose sp = road.surface(at->s, at->t);
  return on_surface(pose.x, pose.y, sp.z, yaw, sp.heading, sp.pitch, sp.roll);
}

}  // namespace tb::map
