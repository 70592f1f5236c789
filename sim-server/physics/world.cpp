#include "sim-server/physics/world.hpp"

#include <btBulletDynamicsCommon.h>

#include <BulletDynamics/Vehicle/btRaycastVehicle.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "common/geodesy/local_frame.hpp"
#include "sim-server/physics/powertrain.hpp"

namespace tb::server::physics {

static_assert(wire::kMinSimTimeNs <= -static_cast<std::int64_t>(scenario::kMaxWarmupS * 1e9),
              "a state of the longest warm-up must pass the wire decoders");

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

/// Where the ground is: the rectangle the road mesh covers.
struct GroundBounds {
  double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
  bool contains(double x, double y) const {
    return x >= min_x && x <= max_x && y >= min_y && y <= max_y;
  }
};

GroundBounds bounds_of(const map::RoadMap& m, double margin) {
  GroundBounds b{1e300, 1e300, -1e300, -1e300};
  auto add = [&b](double x, double y, double r) {
    b.min_x = std::min(b.min_x, x - r);
    b.min_y = std::min(b.min_y, y - r);
    b.max_x = std::max(b.max_x, x + r);
    b.max_y = std::max(b.max_y, y + r);
  };
  for (const auto& road : m.roads()) {
    std::visit(
        [&](const auto& line) {
          using T = std::decay_t<decltype(line)>;
          if constexpr (std::is_same_v<T, map::Segment>) {
            add(line.start.x, line.start.y, road.width);
            add(line.start.x + line.dir.x * line.length, line.start.y + line.dir.y * line.length,
                road.width);
          } else {
            add(line.centre.x, line.centre.y, line.radius + road.width);
          }
        },
        road.reference);
  }
  b.min_x -= margin;
  b.min_y -= margin;
  b.max_x += margin;
  b.max_y += margin;
  return b;
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
  GroundCaster(GroundCast mode, GroundBounds bounds, btRigidBody* ground)
      : mode_(mode), bounds_(bounds), ground_(ground) {}

  void* castRay(const btVector3& from, const btVector3& to,
                btVehicleRaycasterResult& result) override {
    if (mode_ == GroundCast::kFlat) {
      if (from.z() < 0 || to.z() > 0 || from.z() == to.z())
        return nullptr;
      const btScalar f = from.z() / (from.z() - to.z());
      const btVector3 hit = from.lerp(to, f);
      if (!bounds_.contains(hit.x(), hit.y()))
        return nullptr;
      result.m_hitPointInWorld = btVector3(hit.x(), hit.y(), 0);
      result.m_hitNormalInWorld = btVector3(0, 0, 1);
      result.m_distFraction = f;
      return ground_;
    }
    btCollisionWorld::ClosestRayResultCallback cb(from, to);
    btTransform tf_from, tf_to;
    tf_from.setIdentity();
    tf_to.setIdentity();
    tf_from.setOrigin(from);
    tf_to.setOrigin(to);
    btCollisionWorld::rayTestSingle(tf_from, tf_to, ground_, ground_->getCollisionShape(),
                                    ground_->getWorldTransform(), cb);
    if (!cb.hasHit())
      return nullptr;
    result.m_hitPointInWorld = cb.m_hitPointWorld;
    result.m_hitNormalInWorld = cb.m_hitNormalWorld.normalized();
    result.m_distFraction = cb.m_closestHitFraction;
    return ground_;
  }

 private:
  GroundCast mode_;
  GroundBounds bounds_;
  btRigidBody* ground_;
};

struct World::Bullet {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
  btTriangleMesh mesh;
  std::unique_ptr<btBvhTriangleMeshShape> ground_shape;
  std::unique_ptr<btRigidBody> ground;
  std::unique_ptr<GroundCaster> caster;
  GroundBounds bounds;
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
  SpawnPose spawn;                ///< where its run-up ends (warm-up)
  wire::Controls spawn_controls;  ///< what it shows during the warm-up

  Car(const scenario::VehicleModel& m)
      : model(m), geo(geometry(m)), powertrain(model), box(geo.half), shape(false, 1) {}
};

SpawnPose spawn_pose(const map::RoadMap& map, const scenario::Spawn& spawn) {
  SpawnPose p;
  p.speed = spawn.speed;
  if (const auto* lane = std::get_if<scenario::LaneSpawn>(&spawn.where)) {
    const map::Pose pose = map.lane_pose(lane->road, lane->lane, lane->s);
    p.x = pose.p.x;
    p.y = pose.p.y;
    p.yaw = lane->against ? pose.yaw + std::numbers::pi : pose.yaw;
    if (const auto* circle = std::get_if<map::Circle>(&map.lane(lane->road, lane->lane).centre)) {
      // A ring's lane turns left when run counter-clockwise; against it, the other way.
      p.curvature = (circle->ccw != lane->against ? 1.0 : -1.0) / circle->radius;
    }
  } else {
    const auto& pose = std::get<scenario::PoseSpawn>(spawn.where);
    p.x = pose.x;
    p.y = pose.y;
    p.yaw = geodesy::heading_deg_to_yaw(pose.heading_deg);
  }
  return p;
}

World::World(const scenario::MapSpec& map_spec, WorldOptions options)
    : options_(options), map_(map_spec), bt_(std::make_unique<Bullet>()) {
  if (!(options_.step_s > 0.0))
    throw std::invalid_argument("physics step must be positive");
  bt_->world.setGravity(btVector3(0, 0, static_cast<btScalar>(-kGravity)));
  // The road surface as a flat mesh over the map's extent, in cells small enough that the
  // BVH has something to cull with.
  bt_->bounds = bounds_of(map_, options_.ground_margin_m);
  const auto& b = bt_->bounds;
  constexpr double kCell = 50.0;
  const int nx = std::max(1, static_cast<int>(std::ceil((b.max_x - b.min_x) / kCell)));
  const int ny = std::max(1, static_cast<int>(std::ceil((b.max_y - b.min_y) / kCell)));
  const double dx = (b.max_x - b.min_x) / nx, dy = (b.max_y - b.min_y) / ny;
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      const double x0 = b.min_x + i * dx, y0 = b.min_y + j * dy;
      const btVector3 p00 = to_bt(x0, y0, 0), p10 = to_bt(x0 + dx, y0, 0),
                      p01 = to_bt(x0, y0 + dy, 0), p11 = to_bt(x0 + dx, y0 + dy, 0);
      bt_->mesh.addTriangle(p00, p10, p11);
      bt_->mesh.addTriangle(p00, p11, p01);
    }
  }
  bt_->ground_shape = std::make_unique<btBvhTriangleMeshShape>(&bt_->mesh, true);
  btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, bt_->ground_shape.get());
  info.m_friction = 0.8f;
  bt_->ground = std::make_unique<btRigidBody>(info);
  bt_->world.addRigidBody(bt_->ground.get());
  bt_->caster =
      std::make_unique<GroundCaster>(options_.ground_cast, bt_->bounds, bt_->ground.get());
}

World::World(const scenario::Scenario& scenario, WorldOptions options)
    : World(scenario.map, options) {
  for (const auto& v : scenario.vehicles)
    add_vehicle(v.model, v.station_id, spawn_pose(map_, v.spawn));
}

World::~World() {
  for (auto& car : cars_) {
    bt_->world.removeAction(car->vehicle.get());
    bt_->world.removeRigidBody(car->body.get());
  }
  bt_->world.removeRigidBody(bt_->ground.get());
}

std::size_t World::size() const {
  return cars_.size();
}

std::int64_t World::sim_time_ns() const {
  return (static_cast<std::int64_t>(tick_) - static_cast<std::int64_t>(options_.warmup_steps)) *
         std::llround(options_.step_s * 1e9);
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
  btTransform start;
  start.setIdentity();
  start.setRotation(btQuaternion(btVector3(0, 0, 1), static_cast<btScalar>(pose.yaw)));
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  start.setOrigin(to_bt(pose.x - c * g.box_x, pose.y - s * g.box_x, g.com_h));
  info.m_startWorldTransform = start;
  car->body = std::make_unique<btRigidBody>(info);
  car->body->setActivationState(DISABLE_DEACTIVATION);
  car->body->setLinearVelocity(to_bt(c * pose.speed, s * pose.speed, 0));
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
    wi.m_raycastInfo.m_contactNormalWS = btVector3(0, 0, 1);
    wi.m_raycastInfo.m_hardPointWS = start(g.wheel_at[w]);
    wi.m_raycastInfo.m_wheelDirectionWS = down;
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
  cars_[index]->spawn = pose;
  cars_[index]->spawn_controls = cars_[index]->controls;
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
  if (warming_up()) {
    ++tick_;
    for (std::size_t i = 0; i < cars_.size(); ++i)
      update_state(i, step_wall_ns);
    return;
  }
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
  s.position = {ref.x(), ref.y(), ref.z()};
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
  if (options_.warmup_steps > 0 && tick_ <= options_.warmup_steps)
    hold_on_run_up(i);
}

void World::hold_on_run_up(std::size_t i) {
  const Car& car = *cars_[i];
  wire::VehicleState& s = states_[i];
  const SpawnPose& sp = car.spawn;
  const RunUpPose p = run_up(sp, static_cast<double>(sim_time_ns()) * 1e-9);
  s.position[0] = p.x;
  s.position[1] = p.y;
  s.yaw = static_cast<float>(std::remainder(p.yaw, 2.0 * std::numbers::pi));
  const float v = static_cast<float>(sp.speed);
  s.velocity = {v * static_cast<float>(std::cos(p.yaw)), v * static_cast<float>(std::sin(p.yaw)),
                0.0f};
  s.angular_velocity = {0.0f, 0.0f, static_cast<float>(p.yaw_rate)};
  s.acceleration = {0.0f, static_cast<float>(p.lateral_accel), 0.0f};
  s.speed = v;
  s.yaw_rate = static_cast<float>(p.yaw_rate);
  // The road-wheel angle of that arc (bicycle model) and each wheel's speed on it.
  s.steering_angle = static_cast<float>(std::atan(car.model.wheelbase_m * sp.curvature));
  const double half_track = car.model.track_m / 2.0;
  for (int k = 0; k < 4; ++k) {
    const double side = k % 2 == 0 ? half_track : -half_track;  // FL, FR, RL, RR
    s.wheel_speeds[k] = static_cast<float>(sp.speed * (1.0 - sp.curvature * side));
  }
  // The drivers' controls are held back until sim time 0: show the spawn's.
  s.controls = car.spawn_controls;
  s.lights = static_cast<std::uint16_t>(
      (s.lights & ~(wire::kBrakeLights | wire::kReverseLight)) |
      (car.spawn_controls.brake > kBrakeLightThreshold ? wire::kBrakeLights : 0));
}

std::array<std::array<double, 3>, 4> World::wheel_contacts(std::size_t vehicle) const {
  const Car& car = *cars_.at(vehicle);
  std::array<std::array<double, 3>, 4> out{};
  for (int k = 0; k < 4; ++k) {
    const auto& ri = car.vehicle->getWheelInfo(k).m_raycastInfo;
    out[k] = {ri.m_contactPointWS.x(), ri.m_contactPointWS.y(), ri.m_contactPointWS.z()};
  }
  return out;
}

}  // namespace tb::server::physics
