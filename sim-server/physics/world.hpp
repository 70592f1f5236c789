#pragma once
/// @file The simulated world: the road surface of the scenario's map and every vehicle, stepped
/// at a fixed rate on Bullet.
///
/// Each vehicle is a btRaycastVehicle (a rigid chassis on four ray-cast suspension struts)
/// driven by a Powertrain. The wheels do not ray-cast through Bullet's broadphase: they ask the
/// Ground (ground.hpp) for the road surface only, which never tests the cars' own chassis and
/// is the bulk of the saving at 1000 cars (sim-server/README.md, Performance). The chassis
/// still collide with each other and with the ground mesh through the ordinary pipeline.
/// Positions in and out are the map's frame (common/map/scenario_map.hpp); inside, Bullet
/// computes in the Ground's physics frame.
///
/// The first WorldOptions::warmup_steps steps are the warm-up (run_up.hpp): sim time runs
/// negative and every vehicle is held on its run-up to its spawn pose.
///
/// Same scenario, same controls in the same steps ⇒ bit-identical states: the world is stepped
/// single-threaded, in a fixed order, and reads no clock.

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "common/map/scenario_map.hpp"
#include "common/scenario/scenario.hpp"
#include "common/wire/vehicle_state.hpp"
#include "sim-server/physics/off_road.hpp"
#include "sim-server/physics/run_up.hpp"

namespace tb::server::physics {

/// How wheels find the road.
enum class GroundCast {
  /// Flat maps (every built-in layout; z = 0 inside the ground's bounds): an exact ray–plane
  /// test. Refused on a map that is not flat.
  kFlat,
  /// A ray test against the road surface's triangles (and the terrain beside it), through a
  /// grid of their own: what maps with elevation or superelevation get.
  kMesh,
};

struct WorldOptions {
  double step_s = 0.01;
  /// Empty: kFlat on flat maps, kMesh on the others. kMesh on a flat map builds the road's
  /// triangles too (tests, benchmarks: `sim-server --mesh-raycast`).
  std::optional<GroundCast> ground_cast = std::nullopt;
  /// Ground beyond the roads' extent, so that a car leaving the road still has something to
  /// drive on, m.
  double ground_margin_m = 200.0;
  /// Steps of warm-up before the physics starts (scenario warmup_s × physics_hz): sim time
  /// starts at -warmup_steps × step_s and the first warmup_steps calls of step() hold every
  /// vehicle on its run-up (run_up.hpp) instead of stepping the physics.
  std::uint64_t warmup_steps = 0;
};

/// The scenario's spawn as a pose on the map, with its lane's curvature there for the run-up.
/// @throws map::odr::MapError for a lane that does not exist.
SpawnPose spawn_pose(const map::ScenarioMap& map, const scenario::Spawn& spawn);

class World {
 public:
  /// Builds the ground of @p map; vehicles are added with add_vehicle().
  World(std::shared_ptr<const map::ScenarioMap> map, WorldOptions options);
  /// A built-in layout (tests, benchmarks).
  World(const scenario::MapSpec& map_spec, WorldOptions options);
  /// Builds the scenario's map and spawns its vehicles in order.
  explicit World(const scenario::Scenario& scenario, WorldOptions options = {});
  /// The scenario's vehicles on a map already built from it.
  World(const scenario::Scenario& scenario, std::shared_ptr<const map::ScenarioMap> map,
        WorldOptions options);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// Adds a vehicle at rest on its wheels (suspension at its static compression). Returns its
  /// index.
  std::size_t add_vehicle(const scenario::VehicleModel& model, std::uint32_t station_id,
                          const SpawnPose& pose);
  std::size_t size() const;

  /// Controls for the coming steps (already clamped to their ranges) and the lights the driver
  /// switched on; brake and reverse lights are added by the world.
  void set_controls(std::size_t vehicle, const wire::Controls& c, std::uint16_t driver_lights);
  const wire::Controls& controls(std::size_t vehicle) const;

  /// Advances the world by one step; @p step_wall_ns is stamped into the states. During the
  /// warm-up (warming_up()) the physics stands still and the states follow the run-ups, with
  /// the controls each vehicle had at its spawn (the drivers' controls wait for sim time 0).
  void step(std::int64_t step_wall_ns = 0);
  /// True while the next step() is a warm-up step, not a physics step.
  bool warming_up() const { return tick_ < options_.warmup_steps; }

  std::uint64_t tick() const { return tick_; }
  std::int64_t sim_time_ns() const;
  double step_s() const { return options_.step_s; }
  std::span<const wire::VehicleState> states() const { return states_; }
  const map::ScenarioMap& map() const { return *map_; }
  /// Whether the wheels ray-test the road mesh (GroundCast::kMesh).
  bool mesh_cast() const;
  std::size_t ground_triangles() const;
  /// Vehicles that left every drivable lane (the server logs the events).
  OffRoadMonitor& off_road() { return off_road_; }
  const OffRoadMonitor& off_road() const { return off_road_; }

  /// Ground contact point of each wheel (FL, FR, RL, RR) in the map's frame, for tests and
  /// drawing; whether each is in contact.
  std::array<std::array<double, 3>, 4> wheel_contacts(std::size_t vehicle) const;
  std::array<bool, 4> wheels_in_contact(std::size_t vehicle) const;

 private:
  struct Bullet;
  struct Car;
  void update_state(std::size_t i, std::int64_t step_wall_ns);
  void hold_on_run_up(std::size_t i);

  WorldOptions options_;
  std::shared_ptr<const map::ScenarioMap> map_;
  std::unique_ptr<Bullet> bt_;
  OffRoadMonitor off_road_;
  std::vector<std::unique_ptr<Car>> cars_;
  std::vector<wire::VehicleState> states_;
  std::uint64_t tick_ = 0;
};

}  // namespace tb::server::physics
