#pragma once
/// @file The map of a scenario as every program uses it: the road network (an OpenDRIVE file or
/// a built-in layout generated into the same model), its lane locator and lane graph, where
/// its frame lies on the Earth, and where vehicles spawn on it.
///
/// The testbed's local frame *is* the network's inertial frame (x east, y north, z up): every
/// position the programs exchange is an OpenDRIVE x, y, z. WGS84 comes from the file's
/// geoReference through PROJ; without one, the scenario's `origin` places (0, 0, 0) and the
/// frame is the exact ellipsoidal East-North-Up frame there (geodesy::LocalFrame), as it
/// always was for the built-in layouts.

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "common/geodesy/georeferencing.hpp"
#include "common/map/opendrive/lane_graph.hpp"
#include "common/map/opendrive/queries.hpp"
#include "common/map/opendrive/signal_layout.hpp"
#include "common/scenario/scenario.hpp"

namespace tb::map {

/// Where the local frame's geographic origin comes from.
struct OriginSource {
  std::string source;                       ///< "geoReference", "scenario origin", or "none"
  std::optional<geodesy::Geodetic> origin;  ///< WGS84 of (0, 0, 0), when placed
};

/// Where a vehicle starts: the ground point under its reference point (the centre of its
/// bounding box) and its orientation resting on the road surface, as ZYX angles of the body
/// frame (x forward, y left, z up), the convention of wire::VehicleState.
struct Placement {
  double x = 0.0, y = 0.0, z = 0.0;
  double yaw = 0.0;    ///< rad, counter-clockwise from east
  double pitch = 0.0;  ///< rad, ZYX: positive lowers the nose
  double roll = 0.0;   ///< rad, ZYX: positive raises the left side
};

class ScenarioMap {
 public:
  /// The map of a loaded scenario (its network, placed by the geoReference or the origin).
  /// @throws odr::MapError for a geoReference PROJ cannot read, or a map placed by neither.
  explicit ScenarioMap(const scenario::Scenario& scenario);
  /// @p network placed by its geoReference, else by @p origin; neither is allowed here (tests,
  /// tools): georeferencing() then throws.
  ScenarioMap(std::shared_ptr<const odr::RoadNetwork> network,
              std::optional<geodesy::Geodetic> origin);
  /// A built-in layout, generated. @throws std::invalid_argument for a spec no layout can be
  /// built from.
  ScenarioMap(const scenario::MapSpec& builtin, std::optional<geodesy::Geodetic> origin);
  ~ScenarioMap();
  ScenarioMap(const ScenarioMap&) = delete;
  ScenarioMap& operator=(const ScenarioMap&) = delete;

  const odr::RoadNetwork& network() const { return *network_; }
  const std::shared_ptr<const odr::RoadNetwork>& shared_network() const { return network_; }
  /// Built on first use (a station that only needs the origin never pays for them);
  /// thread-safe.
  const odr::LaneLocator& locator() const;
  const odr::LaneGraph& graph() const;
  /// The traffic lights: signal groups, signalised junctions and the lanes they govern. Built
  /// on first use; thread-safe. @throws odr::MapError for lights the index refuses (the
  /// scenario loader builds it for every map with controllers, so a loaded scenario's map
  /// does not throw here).
  const odr::SignalLayout& signals() const;
  /// No elevation and no superelevation anywhere: the road surface is the plane z = 0.
  bool flat() const { return flat_; }

  /// Whether the frame lies somewhere on the Earth (a geoReference or an origin).
  bool placed() const { return geo_ != nullptr; }
  /// Local frame <-> WGS84. Not thread-safe on PROJ maps (one PROJ context per map).
  /// @throws odr::MapError when the map is not placed.
  const geodesy::Georeferencing& georeferencing() const;
  geodesy::Geodetic to_wgs84(double x, double y, double z) const;
  const OriginSource& origin() const { return origin_; }
  /// One line each for the log: PROJ adjustments, an origin the geoReference overrides.
  const std::vector<std::string>& notes() const { return notes_; }

  /// Where a vehicle spawned at @p spawn stands. A lane spawn stands on its lane facing its
  /// direction of travel (turned round for `against`); a pose spawn on the surface under it
  /// (the plane z = 0 where no lane is).
  /// @throws odr::MapError for a lane position that does not exist or is not drivable.
  Placement place(const scenario::Spawn& spawn) const;
  /// The same for a lane of the network.
  Placement place(const scenario::RoadSpawn& spawn) const;

  /// The built-in lane spawn in the generated network's terms. @throws std::invalid_argument
  /// on a map that is not a built-in layout.
  scenario::RoadSpawn network_spawn(const scenario::LaneSpawn& lane) const;

 private:
  std::shared_ptr<const odr::RoadNetwork> network_;
  std::optional<scenario::MapSpec> builtin_;  ///< the layout, for built-in lane spawns
  bool flat_ = true;
  std::unique_ptr<geodesy::Georeferencing> geo_;
  OriginSource origin_;
  std::vector<std::string> notes_;
  mutable std::once_flag locator_once_, graph_once_, signals_once_;
  mutable std::unique_ptr<odr::LaneLocator> locator_;
  mutable std::unique_ptr<odr::LaneGraph> graph_;
  mutable std::unique_ptr<odr::SignalLayout> signals_;
};

/// Orientation of a body standing on a surface of normal (@p nx, @p ny, @p nz) whose heading,
/// seen from above, is @p yaw: its ZYX pitch and roll.
void orientation_on(double nx, double ny, double nz, double yaw, double& pitch, double& roll);

}  // namespace tb::map
