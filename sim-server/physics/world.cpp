#include "sim-server/physics/world.hpp"

#include <btBulletDynamicsCommon.h>

#include <BulletDynamics/Vehicle/btRaycastVehicle.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "common/geodesy/local_frame.hpp"
#include "sim-server/physics/ground.hpp"
#include "sim-server/physics/powertrain.hpp"

namespace tb::server::physics {
namespace {

constexpr double kGravity = 9.81;
constexpr double kAirDensity = 1.2041;  // kg/m³ at 20 °C, sea level
/// Share of the weight on the front axle: a front-engined compact car carries about 60 %.
constexpr double kFrontWeightShare = 0.60;
/// Front overhang as a share of both overhangs (the engine sits ahead of the front axle).
constexpr double kFrontOverhangShare = 0.53;
constexpr double kGroundClearance = 0.14;       // m
constexpr double kSuspensionRestLength = 0.30;  // m, strut length without load
/// Share of the brake force on the front axle, as a brake-force distribution valve sets it.
constexpr double kFrontBrakeShare = 0.70;
/// btRaycastVehicle turns the chassis' roll torque from tyre forces down by this factor; a
/// rigid chassis on ray wheels rolls over far more easily than a real car on anti-roll bars.
constexpr double kRollInfluence = 0.2;
/// Below this speed rolling resistance fades out, so that a parked car does not jitter.
constexpr double kRollingFadeSpeed = 0.5;
constexpr double kBrakeLightThreshold = 0.02;

btVector3 to_bt(double x, double y, double z) {
  return btVector3(static_cast<btScalar>(x), static_cast<btScalar>(y), static_cast<btScalar>(z));
}

/// Model geometry derived once per vehicle; body frame: origin at the centre of mass, x
/// forward, y left, z up.
struct Geometry {
  double a = 0;      ///< centre of mass to front axle, m
  double b = 0;      ///< centre of mass to rear axle, m
  double box_x = 0;  ///< centre of the bounding box along x
  double com_h = 0;  ///< centre of mass above the ground
  btVector3 half{};  ///< chassis box half extents
  btVector3 box_centre{};
  std::array<btVector3, 4> wheel_at{};  ///< strut tops FL, FR, RL, RR
};

Geometry geometry(const scenario::VehicleModel& m) {
  Geometry g;
  g.a = m.wheelbase_m * (1.0 - kFrontWeightShare);
  g.b = m.wheelbase_m - g.a;
  const double front_overhang = (m.length_m - m.wheelbase_m) * kFrontOverhangShare;
  g.box_x = g.a + front_overhang - m.length_m / 2.0;
  g.com_h = m.centre_of_mass_height_m;
  const double box_h = m.height_m - kGroundClearance;
  g.half = to_bt(m.length_m / 2.0, m.width_m / 2.0, box_h / 2.0);
  g.box_centre = to_bt(g.box_x, 0.0, kGroundClearance + box_h / 2.0 - g.com_h);
  // Strut tops sit where the loaded suspension carries the body at its centre-of-mass height:
  // static compression = load per wheel / (stiffness × mass) (Bullet's stiffness is per unit
  // chassis mass).
  const double k = m.suspension_stiffness;
  const double comp_front = kGravity * kFrontWeightShare / 2.0 / k;
  const double comp_rear = kGravity * (1.0 - kFrontWeightShare) / 2.0 / k;
  const double zf = m.wheel_radius_m + kSuspensionRestLength - comp_front - g.com_h;
  const double zr = m.wheel_radius_m + kSuspensionRestLength - comp_rear - g.com_h;
  const double t = m.track_m / 2.0;
  g.wheel_at = {to_bt(g.a, t, zf), to_bt(g.a, -t, zf), to_bt(-g.b, t, zr), to_bt(-g.b, -t, zr)};
  return g;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

/// Wheels find the road through this instead of Bullet's broadphase: the only thing they can
/// stand on is the ground, so nothing else needs testing.
class GroundCaster final : public btVehicleRaycaster {
 public:
  GroundCaster(const Ground& ground, btRigidBody* body) : ground_(ground), body_(body) {}

  void* castRay(const btVector3& from, const btVector3& to,
                btVehicleRaycasterResult& result) override {
    const auto hit = ground_.cast({from.x(), from.y(), from.z()}, {to.x(), to.y(), to.z()});
    if (!hit)
      return nullptr;
    result.m_hitPointInWorld = to_bt(hit->point.x, hit->point.y, hit->point.z);
    result.m_hitNormalInWorld = to_bt(hit->normal.x, hit->normal.y, hit->normal.z);
    result.m_distFraction = static_cast<btScalar>(hit->fraction);
    return body_;
  }

 private:
  const Ground& ground_;
  btRigidBody* body_;
};

struct World::Bullet {
  explicit Bullet(const map::ScenarioMap& map, double margin, bool mesh)
      : ground(map, margin, mesh) {}
  Ground ground;
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
  btTriangleMesh mesh;
  std::unique_ptr<btBvhTriangleMeshShape> ground_shape;
  std::unique_ptr<btRigidBody> ground_body;
  std::unique_ptr<GroundCaster> caster;
};

struct World::Car {
  scenario::VehicleModel model;
  Geometry geo;
  Powertrain powertrain;
  btBoxShape box;
  btCompoundShape shape;
  std::unique_ptr<btRigidBody> body;
  std::unique_ptr<btRaycastVehicle> vehicle;
  wire::Controls controls;
  std::uint16_t driver_lights = 0;
  DriveForces forces;
  btVector3 last_velocity{0, 0, 0};
  std::array<double, 4> steer{};  ///< per wheel, rad, positive left

  Car(const scenario::VehicleModel& m)
      : model(m), geo(geometry(m)), powertrain(model), box(geo.half), shape(false, 1) {}
};

SpawnPose spawn_pose(const map::ScenarioMap& map, const scenario::Spawn& spawn) {
  const map::Placement p = map.place(spawn);
  return {p.x, p.y, p.yaw, spawn.speed, p.z, p.pitch, p.roll};
}

namespace {
bool wants_mesh(const map::ScenarioMap& map, const WorldOptions& o) {
  if (!o.ground_cast)
    return !map.flat();
  if (*o.ground_cast == GroundCast::kFlat && !map.flat()) {
    throw std::invalid_argument(
        "the flat ground cast needs a flat map (this one has elevation or superelevation)");
  }
  return *o.ground_cast == GroundCast::kMesh;
}
}  // namespace

World::World(std::shared_ptr<const map::ScenarioMap> map, WorldOptions options)
    : options_(options),
      map_(std::move(map)),
      bt_(std::make_unique<Bullet>(*map_, options_.ground_margin_m, wants_mesh(*map_, options_))),
      off_road_(*map_) {
  if (!(options_.step_s > 0.0))
    throw std::invalid_argument("physics step must be positive");
  bt_->world.setGravity(btVector3(0, 0, static_cast<btScalar>(-kGravity)));
  const Ground& g = bt_->ground;
  for (std::size_t t = 0; t < g.triangles(); ++t) {
    const auto& a = g.vertices()[g.indices()[3 * t]];
    const auto& b = g.vertices()[g.indices()[3 * t + 1]];
    const auto& c = g.vertices()[g.indices()[3 * t + 2]];
    bt_->mesh.addTriangle(btVector3(a[0], a[1], a[2]), btVector3(b[0], b[1], b[2]),
                          btVector3(c[0], c[1], c[2]));
  }
  bt_->ground_shape = std::make_unique<btBvhTriangleMeshShape>(&bt_->mesh, true);
  btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, bt_->ground_shape.get());
  info.m_friction = 0.8f;
  bt_->ground_body = std::make_unique<btRigidBody>(info);
  bt_->world.addRigidBody(bt_->ground_body.get());
  bt_->caster = std::make_unique<GroundCaster>(bt_->ground, bt_->ground_body.get());
}

World::World(const scenario::MapSpec& map_spec, WorldOptions options)
    : World(std::make_shared<const map::ScenarioMap>(map_spec, std::nullopt), options) {}

World::World(const scenario::Scenario& scenario, std::shared_ptr<const map::ScenarioMap> map,
             WorldOptions options)
    : World(std::move(map), options) {
  for (const auto& v : scenario.vehicles)
    add_vehicle(v.model, v.station_id, spawn_pose(*map_, v.spawn));
}

World::World(const scenario::Scenario& scenario, WorldOptions options)
    : World(scenario, std::make_shared<const map::ScenarioMap>(scenario), options) {}

World::~World() {
  for (auto& car : cars_) {
    bt_->world.removeAction(car->vehicle.get());
    bt_->world.removeRigidBody(car->body.get());
  }
  bt_->world.removeRigidBody(bt_->ground_body.get());
}

bool World::mesh_cast() const {
  return !bt_->ground.flat();
}

std::size_t World::ground_triangles() const {
  return bt_->ground.triangles();
}

std::size_t World::size() const {
  return cars_.size();
}

std::int64_t World::sim_time_ns() const {
  return static_cast<std::int64_t>(tick_) * std::llround(options_.step_s * 1e9);
}

std::size_t World::add_vehicle(const scenario::VehicleModel& model, std::uint32_t station_id,
                               const SpawnPose& pose) {
  auto car = std::make_unique<Car>(model);
  const Geometry& g = car->geo;
  btTransform child;
  child.setIdentity();
  child.setOrigin(g.box_centre);
  car->shape.addChildShape(child, &car->box);

  const double m = model.mass_kg;
  const double lx = model.length_m, ly = model.width_m, lz = model.height_m - kGroundClearance;
  // A solid box of the car's size overstates the inertia of a real body a little; fine for
  // handling at the limits a testbed needs.
  const btVector3 inertia = to_bt(m / 12.0 * (ly * ly + lz * lz), m / 12.0 * (lx * lx + lz * lz),
                                  m / 12.0 * (lx * lx + ly * ly));
  btRigidBody::btRigidBodyConstructionInfo info(static_cast<btScalar>(m), nullptr, &car->shape,
                                                inertia);
  info.m_friction = 0.5f;
  // Resting on the surface: the reference point (the ground under the bounding box's centre,
  // body (box_x, 0, -com_h)) on the spawn's ground point, the body turned by yaw, pitch, roll.
  btTransform start;
  start.setIdentity();
  btMatrix3x3 rot;
  rot.setEulerZYX(static_cast<btScalar>(pose.roll), static_cast<btScalar>(pose.pitch),
                  static_cast<btScalar>(pose.yaw));
  start.setBasis(rot);
  const Vec3& o = bt_->ground.origin();
  const btVector3 ref_in_body = to_bt(g.box_x, 0.0, -g.com_h);
  start.setOrigin(to_bt(pose.x - o.x, pose.y - o.y, pose.z - o.z) - rot * ref_in_body);
  info.m_startWorldTransform = start;
  car->body = std::make_unique<btRigidBody>(info);
  car->body->setActivationState(DISABLE_DEACTIVATION);
  car->body->setLinearVelocity(rot.getColumn(0) * static_cast<btScalar>(pose.speed));
  car->last_velocity = car->body->getLinearVelocity();
  bt_->world.addRigidBody(car->body.get());

  btRaycastVehicle::btVehicleTuning tuning;
  tuning.m_suspensionStiffness = static_cast<btScalar>(model.suspension_stiffness);
  tuning.m_suspensionCompression = static_cast<btScalar>(model.suspension_damping);
  tuning.m_suspensionDamping = static_cast<btScalar>(model.suspension_damping);
  tuning.m_maxSuspensionTravelCm = static_cast<btScalar>(model.suspension_travel_m * 100.0);
  tuning.m_frictionSlip = static_cast<btScalar>(model.tyre_friction);
  // Bump stops: a strut may carry several times its static load over a kerb.
  tuning.m_maxSuspensionForce = static_cast<btScalar>(m * kGravity * 2.0);
  car->vehicle = std::make_unique<btRaycastVehicle>(tuning, car->body.get(), bt_->caster.get());
  car->vehicle->setCoordinateSystem(1, 2, 0);
  const btVector3 down(0, 0, -1), axle(0, -1, 0);
  for (int w = 0; w < 4; ++w) {
    btWheelInfo& wi = car->vehicle->addWheel(
        g.wheel_at[w], down, axle, static_cast<btScalar>(kSuspensionRestLength),
        static_cast<btScalar>(model.wheel_radius_m), tuning, w < 2);
    wi.m_rollInfluence = static_cast<btScalar>(kRollInfluence);
    // btWheelInfo leaves the contact state and the strut force uninitialised until the first
    // step, yet the grip limit and the spawn state read them.
    wi.m_raycastInfo.m_isInContact = false;
    wi.m_raycastInfo.m_contactPointWS = start(g.wheel_at[w]);
    wi.m_raycastInfo.m_contactNormalWS = rot.getColumn(2);
    wi.m_raycastInfo.m_hardPointWS = start(g.wheel_at[w]);
    wi.m_raycastInfo.m_wheelDirectionWS = rot * down;
    wi.m_raycastInfo.m_wheelAxleWS = start.getBasis() * axle;
    wi.m_raycastInfo.m_suspensionLength = static_cast<btScalar>(kSuspensionRestLength);
    wi.m_raycastInfo.m_groundObject = nullptr;
    wi.m_wheelsSuspensionForce = 0;
    wi.m_skidInfo = 1;
    wi.m_clippedInvContactDotSuspension = 1;
    wi.m_suspensionRelativeVelocity = 0;
  }
  bt_->world.addAction(car->vehicle.get());

  const std::size_t index = cars_.size();
  cars_.push_back(std::move(car));
  states_.emplace_back();
  states_.back().station_id = station_id;
  // Parked until someone drives it.
  cars_[index]->controls.brake = pose.speed > 0 ? 0.0f : 1.0f;
  update_state(index, 0);
  return index;
}

void World::set_controls(std::size_t vehicle, const wire::Controls& c,
                         std::uint16_t driver_lights) {
  auto& car = *cars_.at(vehicle);
  car.controls = c;
  car.driver_lights = driver_lights;
}

const wire::Controls& World::controls(std::size_t vehicle) const {
  return cars_.at(vehicle)->controls;
}

void World::step(std::int64_t step_wall_ns) {
  const double dt = options_.step_s;
  for (auto& cp : cars_) {
    Car& car = *cp;
    btRigidBody& body = *car.body;
    const btVector3 fwd = body.getWorldTransform().getBasis().getColumn(0);
    const btVector3 v = body.getLinearVelocity();
    const double speed = v.dot(fwd);
    car.forces = car.powertrain.update(car.controls, speed, dt);

    // Road-wheel angles with Ackermann geometry: the inner wheel turns more, so that both front
    // wheels roll about the rear axle's turning centre.
    const double mean = -car.controls.steer * car.model.max_steer_deg * std::numbers::pi / 180.0;
    double left = mean, right = mean;
    if (std::abs(mean) > 1e-6) {
      const double L = car.model.wheelbase_m, t = car.model.track_m / 2.0;
      const double r = L / std::tan(std::abs(mean));
      const double inner = std::atan(L / (r - t)), outer = std::atan(L / (r + t));
      left = mean > 0 ? inner : -outer;
      right = mean > 0 ? outer : -inner;
    }
    car.steer = {left, right, 0.0, 0.0};
    btRaycastVehicle& veh = *car.vehicle;
    veh.setSteeringValue(static_cast<btScalar>(left), 0);
    veh.setSteeringValue(static_cast<btScalar>(right), 1);

    const bool braking = car.forces.brake_n > 0.0 || car.forces.handbrake_n > 0.0;
    // Brakes override the throttle, as a brake-override system does.
    const double drive = braking ? 0.0 : car.forces.traction_n / 2.0;
    const double front_brake = car.forces.brake_n * kFrontBrakeShare / 2.0;
    const double rear_brake =
        (car.forces.brake_n * (1.0 - kFrontBrakeShare) + car.forces.handbrake_n) / 2.0;
    for (int w = 0; w < 4; ++w) {
      // btRaycastVehicle lets a wheel's forward impulse reach twice its grip before it slides
      // (it halves the forward part in its friction check), so longitudinal forces are held to
      // the tyre's grip under the wheel's load here, as ABS and traction control do.
      const double grip = car.model.tyre_friction * veh.getWheelInfo(w).m_wheelsSuspensionForce;
      const double engine = w < 2 ? std::clamp(drive, -grip, grip) : 0.0;
      const double brake = std::min(w < 2 ? front_brake : rear_brake, grip);
      veh.applyEngineForce(static_cast<btScalar>(engine), w);
      // btRaycastVehicle takes the brake as the largest impulse per step.
      veh.setBrake(static_cast<btScalar>(brake * dt), w);
    }

    // Aerodynamic drag and rolling resistance at the centre of mass.
    const double vn = v.length();
    if (vn > 1e-6) {
      const double drag =
          0.5 * kAirDensity * car.model.drag_coefficient * car.model.frontal_area_m2 * vn * vn;
      const double rolling = car.model.rolling_resistance * car.model.mass_kg * kGravity *
                             std::min(1.0, vn / kRollingFadeSpeed);
      body.applyCentralForce(-v / static_cast<btScalar>(vn) *
                             static_cast<btScalar>(drag + rolling));
    }
  }
  bt_->world.stepSimulation(static_cast<btScalar>(dt), 1, static_cast<btScalar>(dt));
  ++tick_;
  for (std::size_t i = 0; i < cars_.size(); ++i)
    update_state(i, step_wall_ns);
  off_road_.update(tick_, states_);
}

void World::update_state(std::size_t i, std::int64_t step_wall_ns) {
  Car& car = *cars_[i];
  wire::VehicleState& s = states_[i];
  const btRigidBody& body = *car.body;
  const btTransform& tf = body.getWorldTransform();
  const btMatrix3x3& rot = tf.getBasis();
  const btVector3 ref = tf(to_bt(car.geo.box_x, 0, -car.geo.com_h));
  const btVector3 v = body.getLinearVelocity();
  const btVector3 w = body.getAngularVelocity();
  const double dt = options_.step_s;

  s.tick = tick_;
  s.sim_time_ns = sim_time_ns();
  s.step_wall_ns = step_wall_ns;
  const Vec3& o = bt_->ground.origin();
  s.position = {ref.x() + o.x, ref.y() + o.y, ref.z() + o.z};
  btScalar yaw, pitch, roll;
  rot.getEulerZYX(yaw, pitch, roll);
  s.roll = roll;
  s.pitch = pitch;
  s.yaw = yaw;
  s.velocity = {v.x(), v.y(), v.z()};
  s.angular_velocity = {w.x(), w.y(), w.z()};
  const btVector3 acc_world = tick_ == 0 ? btVector3(0, 0, 0) : (v - car.last_velocity) / dt;
  const btVector3 acc_body = rot.transpose() * acc_world;
  s.acceleration = {acc_body.x(), acc_body.y(), acc_body.z()};
  car.last_velocity = v;
  const btVector3 fwd = rot.getColumn(0);
  s.speed = v.dot(fwd);
  s.yaw_rate = w.z();
  s.steering_angle = static_cast<float>((car.steer[0] + car.steer[1]) / 2.0);
  for (int k = 0; k < 4 && k < car.vehicle->getNumWheels(); ++k) {
    const btWheelInfo& wi = car.vehicle->getWheelInfo(k);
    const btVector3 contact = wi.m_raycastInfo.m_isInContact ? wi.m_raycastInfo.m_contactPointWS
                                                             : tf(wi.m_chassisConnectionPointCS);
    const double a = yaw + car.steer[k];
    const btVector3 dir = to_bt(std::cos(a), std::sin(a), 0);
    s.wheel_speeds[k] = body.getVelocityInLocalPoint(contact - tf.getOrigin()).dot(dir);
  }
  s.controls = car.controls;
  s.gear = car.forces.gear;
  s.engine_rpm = static_cast<float>(car.forces.engine_rpm);
  std::uint16_t lights = car.driver_lights & ~(wire::kBrakeLights | wire::kReverseLight);
  if (car.controls.brake > kBrakeLightThreshold)
    lights |= wire::kBrakeLights;
  if (car.forces.gear < 0)
    lights |= wire::kReverseLight;
  s.lights = lights;
}

std::array<bool, 4> World::wheels_in_contact(std::size_t vehicle) const {
  const Car& car = *cars_.at(vehicle);
  std::array<bool, 4> out{};
  for (int k = 0; k < 4; ++k)
    out[k] = car.vehicle->getWheelInfo(k).m_raycastInfo.m_isInContact;
  return out;
}

std::array<std::array<double, 3>, 4> World::wheel_contacts(std::size_t vehicle) const {
  const Car& car = *cars_.at(vehicle);
  std::array<std::array<double, 3>, 4> out{};
  const Vec3& o = bt_->ground.origin();
  for (int k = 0; k < 4; ++k) {
    const auto& ri = car.vehicle->getWheelInfo(k).m_raycastInfo;
    out[k] = {ri.m_contactPointWS.x() + o.x, ri.m_contactPointWS.y() + o.y,
              ri.m_contactPointWS.z() + o.z};
  }
  return out;
}

}  // namespace tb::server::physics
