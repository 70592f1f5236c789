// Lane followers among other vehicles, with an injected state stream (no sockets, no server):
// every car is a kinematic bicycle (plant.hpp) driven by its LaneFollowDriver, and each step all
// drivers see the same Traffic, located by DriveMap as the client does for a state frame. On
// the shared OpenDRIVE maps and generated built-ins: no collisions, no wheel off the drivable
// lanes, junction priority, following, curves, routes and merges.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <sstream>
#include <string>

#include "common/map/builtin_network.hpp"
#include "common/map/opendrive/reader.hpp"
#include "common/map/opendrive/tests/shared_maps.hpp"
#include "sim-client/driver/scripted_driver.hpp"
#include "sim-client/driver/tests/plant.hpp"

namespace tb::client {
namespace {

namespace odr = map::odr;
using Kind = scenario::DriveRoute::Kind;
using test::Plant;

constexpr double kDt = 0.01;  // s, the physics step of the default scenario

std::shared_ptr<const odr::RoadNetwork> shared_map(const char* name) {
  return std::make_shared<const odr::RoadNetwork>(
      odr::load_opendrive((odr::test::shared_maps() / name).string()));
}

scenario::LaneFollowDriver lane_follow(double speed, Kind kind = Kind::kRandom) {
  scenario::LaneFollowDriver d;
  d.profile = {{0.0, speed}};
  d.route.kind = kind;
  d.yield_to_traffic = true;
  return d;
}

// The corners of a car's footprint.
std::array<std::array<double, 2>, 4> corners(const wire::VehicleState& s, double length,
                                             double width) {
  const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
  std::array<std::array<double, 2>, 4> out{};
  const double lx[4] = {length / 2, length / 2, -length / 2, -length / 2};
  const double ly[4] = {width / 2, -width / 2, -width / 2, width / 2};
  for (int i = 0; i < 4; ++i)
    out[i] = {s.position[0] + lx[i] * c - ly[i] * sn, s.position[1] + lx[i] * sn + ly[i] * c};
  return out;
}

// Separating-axis test of two footprints.
bool overlap(const wire::VehicleState& a, const wire::VehicleState& b, double length,
             double width) {
  const auto ca = corners(a, length, width), cb = corners(b, length, width);
  for (const auto* poly : {&ca, &cb}) {
    for (int i = 0; i < 4; ++i) {
      const auto& p = (*poly)[i];
      const auto& q = (*poly)[(i + 1) % 4];
      const double nx = q[1] - p[1], ny = p[0] - q[0];
      double amin = 1e300, amax = -1e300, bmin = 1e300, bmax = -1e300;
      for (const auto& v : ca) {
        amin = std::min(amin, v[0] * nx + v[1] * ny);
        amax = std::max(amax, v[0] * nx + v[1] * ny);
      }
      for (const auto& v : cb) {
        bmin = std::min(bmin, v[0] * nx + v[1] * ny);
        bmax = std::max(bmax, v[0] * nx + v[1] * ny);
      }
      if (amax < bmin || bmax < amin)
        return false;
    }
  }
  return true;
}

// Cars on one map, driven step by step; records what the tests check.
class Traffic {
 public:
  explicit Traffic(std::shared_ptr<const odr::RoadNetwork> net)
      : map_(std::make_shared<const map::ScenarioMap>(std::move(net), std::nullopt)) {}

  /// A car on lane (road id, lane, s) facing its direction of travel.
  LaneFollowDriver& add(const std::string& road, int lane, double s, double speed,
                        scenario::LaneFollowDriver spec, std::uint64_t seed = 1) {
    const int r = map_.network().road_index(road);
    const odr::SurfacePose p = odr::spawn_pose(map_.network(), {road, lane, s, 0.0});
    const auto id = static_cast<std::uint32_t>(cars_.size() + 1);
    map::RoutePlan plan(map_.network(), map_.graph(), spec.route, {r, lane, s, false},
                        map::vehicle_seed(seed, id));
    cars_.push_back({Plant(p.x, p.y, p.heading, speed, id),
                     std::make_unique<LaneFollowDriver>(spec, model_, map_, std::move(plan))});
    sizes_.push_back({id, model_.length_m, model_.width_m});
    return *cars_.back().driver;
  }

  void run(double seconds) {
    for (int i = 0; i < static_cast<int>(seconds / kDt); ++i)
      step();
  }

  void step() {
    std::vector<wire::VehicleState> states;
    for (const Car& c : cars_)
      states.push_back(c.plant.state());
    const client::Traffic seen = map_.observe(states, sizes_);
    for (std::size_t i = 0; i < cars_.size(); ++i) {
      cars_[i].plant.step(cars_[i].driver->update(states[i], seen), kDt);
      const LaneFollowStatus& st = cars_[i].driver->status();
      limits_.insert(st.limit);
      if (st.road >= 0)
        roads_[i].insert(map_.network().roads[static_cast<std::size_t>(st.road)].id);
      const double v = cars_[i].plant.speed();
      max_lateral_accel_ = std::max(max_lateral_accel_, std::abs(v * states[i].yaw_rate));
      planned_lateral_accel_ = std::max(
          planned_lateral_accel_, st.reference_speed * st.reference_speed * std::abs(st.curvature));
      check_on_lanes(cars_[i].plant.state());
    }
    for (std::size_t i = 0; i < cars_.size(); ++i) {
      for (std::size_t j = i + 1; j < cars_.size(); ++j) {
        if (overlap(cars_[i].plant.state(), cars_[j].plant.state(), model_.length_m,
                    model_.width_m)) {
          if (collisions_++ == 0)
            report(i, j);
        }
      }
    }
  }

  void report(std::size_t i, std::size_t j) {
    std::ostringstream out;
    for (std::size_t k : {i, j}) {
      const auto s = cars_[k].plant.state();
      const auto& st = cars_[k].driver->status();
      out << "\n  car " << k << " at t = " << s.sim_time_ns * 1e-9 << " s: (" << s.position[0]
          << ", " << s.position[1] << ") yaw " << s.yaw << " speed " << s.speed << " road "
          << st.road << " lane " << st.lane << " limit " << static_cast<int>(st.limit) << " gap "
          << st.leader_gap << " target " << st.target_speed;
    }
    first_collision_ = out.str();
  }

  // Every wheel on a drivable lane (the body may overhang the lane's edge in a tight turn, as a
  // real car's does).
  void check_on_lanes(const wire::VehicleState& s) {
    for (const auto& c : corners(s, model_.wheelbase_m, model_.track_m)) {
      bool drivable = false;
      for (const odr::LanePosition& f : map_.locator().locate_all(c[0], c[1])) {
        const odr::Lane* l =
            map_.network().roads[static_cast<std::size_t>(f.ref.road)].sections[f.section].lane(
                f.ref.lane);
        drivable = drivable || (l != nullptr && l->drivable);
      }
      if (!drivable && off_lane_++ == 0) {
        std::ostringstream out;
        out << "\n  first at t = " << s.sim_time_ns * 1e-9 << " s: car " << s.station_id << " at ("
            << s.position[0] << ", " << s.position[1] << ") yaw " << s.yaw << ", wheel (" << c[0]
            << ", " << c[1] << ")";
        first_off_lane_ = out.str();
      }
    }
  }

  const Plant& car(std::size_t i) const { return cars_[i].plant; }
  const LaneFollowDriver& driver(std::size_t i) const { return *cars_[i].driver; }
  std::size_t size() const { return cars_.size(); }
  int collisions() const { return collisions_; }
  int off_lane() const { return off_lane_; }
  const std::string& first_collision() const { return first_collision_; }
  const std::string& first_off_lane() const { return first_off_lane_; }
  double max_lateral_accel() const { return max_lateral_accel_; }
  double planned_lateral_accel() const { return planned_lateral_accel_; }
  bool saw(SpeedLimit l) const { return limits_.count(l) > 0; }
  const std::set<std::string>& roads(std::size_t i) { return roads_[i]; }
  const DriveMap& map() const { return map_; }

 private:
  struct Car {
    Plant plant;
    std::unique_ptr<LaneFollowDriver> driver;
  };
  DriveMap map_;
  scenario::VehicleModel model_;
  std::vector<Car> cars_;
  std::vector<VehicleSize> sizes_;
  std::set<SpeedLimit> limits_;
  std::map<std::size_t, std::set<std::string>> roads_;
  int collisions_ = 0;
  int off_lane_ = 0;
  std::string first_collision_, first_off_lane_;
  double max_lateral_accel_ = 0.0;
  double planned_lateral_accel_ = 0.0;
};

TEST(TrafficIndex, FindsAndNearsAsTheScanDoes) {
  // 400 vehicles scattered over 3 km, some on cell borders and below zero, two sharing a
  // station id: the index gives what the scan of every vehicle gives.
  using Frame = ::tb::client::Traffic;  // this file's Traffic is the simulation
  Frame t;
  std::srand(7);
  for (std::uint32_t i = 0; i < 400; ++i) {
    Observed o;
    o.state.station_id = i == 399 ? 17 : 1000 + i;
    o.state.position = {std::rand() % 3000 - 1500.0, std::rand() % 3000 - 1500.0, 0.0};
    if (i % 50 == 0)
      o.state.position = {Frame::kCell * (static_cast<double>(i) / 50 - 4), -Frame::kCell, 0.0};
    o.length = i % 7 == 0 ? 12.0 : 4.5;
    t.vehicles.push_back(o);
  }
  t.vehicles[3].state.station_id = 17;
  const Frame scan = t;  // not indexed
  t.index();
  EXPECT_EQ(t.max_length(), 12.0);
  EXPECT_EQ(t.find(17), &t.vehicles[3]);  // the first of two, as the scan finds it
  EXPECT_EQ(scan.find(17), &scan.vehicles[3]);
  EXPECT_EQ(t.find(1005), &t.vehicles[5]);
  EXPECT_EQ(t.find(99), nullptr);
  for (const auto& o : scan.vehicles) {
    for (const double r : {0.0, 10.0, 49.9, 50.0, 180.0}) {
      const double x = o.state.position[0] + 3.0, y = o.state.position[1] - 2.0;
      std::vector<std::size_t> want, got;
      for (std::size_t i = 0; i < scan.vehicles.size(); ++i) {
        const auto& p = scan.vehicles[i].state.position;
        if (std::hypot(p[0] - x, p[1] - y) <= r)
          want.push_back(i);
      }
      for (const Observed* n : t.near(x, y, r)) {
        const auto i = static_cast<std::size_t>(n - t.vehicles.data());
        const auto& p = n->state.position;
        if (std::hypot(p[0] - x, p[1] - y) <= r)
          got.push_back(i);
      }
      EXPECT_EQ(got, want) << "around " << x << ", " << y << " within " << r;
      EXPECT_LT(t.near(x, y, r).size(), scan.vehicles.size() / 2);
    }
  }
  // A hand-built Traffic, or one changed since index(), is scanned whole.
  EXPECT_EQ(scan.near(0, 0, 1).size(), scan.vehicles.size());
  t.vehicles.push_back(Observed{});
  EXPECT_EQ(t.near(0, 0, 1).size(), t.vehicles.size());
  EXPECT_EQ(t.find(17), &t.vehicles[3]);
}

TEST(LaneFollowTraffic, RandomRoutesThroughTheFourWayJunction) {
  // Two cars on each arm's inbound lane, 10 m/s, random routes: they meet at the junction,
  // give way, queue on the arms they leave by and stop before the arms' open ends.
  Traffic t(shared_map("simple_4way_intersection.xodr"));
  for (const char* road : {"0", "1", "2", "3"}) {
    const odr::Road& r =
        t.map().network().roads[static_cast<std::size_t>(t.map().network().road_index(road))];
    // Road 0 reaches the junction at its end (lane -1), the others at their start (lane 1).
    const bool at_end = std::string(road) == "0";
    for (double from_junction : {15.0, 45.0})
      t.add(road, at_end ? -1 : 1, at_end ? r.length - from_junction : from_junction, 10.0,
            lane_follow(10.0));
  }
  t.run(60.0);
  EXPECT_EQ(t.collisions(), 0) << t.first_collision();
  EXPECT_EQ(t.off_lane(), 0) << t.first_off_lane();
  EXPECT_TRUE(t.saw(SpeedLimit::kJunction)) << "nobody had to give way";
  EXPECT_TRUE(t.saw(SpeedLimit::kLeader)) << "nobody followed anybody";
  std::size_t through = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    through += t.roads(i).size() >= 3;  // its arm, a connecting road, another arm
    EXPECT_NEAR(t.car(i).speed(), 0.0, 0.05) << "car " << i << " still moving after 60 s";
  }
  EXPECT_EQ(through, t.size());
  // The driver plans at most 3 m/s²; the plant, slower to brake than the driver's model, lags.
  EXPECT_LT(t.planned_lateral_accel(), 3.0 * 1.02);
  EXPECT_LT(t.max_lateral_accel(), 3.0 * 1.5);
}

scenario::LaneFollowDriver to(double speed, const std::string& road, int lane, double s) {
  scenario::LaneFollowDriver d = lane_follow(speed, Kind::kTo);
  d.route.to = {road, lane, s};
  return d;
}

// Where the car is, in road coordinates (the locator preferring lane ids in @p lanes).
odr::LanePosition where(const Traffic& t, std::size_t car) {
  const auto s = t.car(car).state();
  const auto at = t.map().locator().locate(s.position[0], s.position[1]);
  EXPECT_TRUE(at);
  return at.value_or(odr::LanePosition{});
}

TEST(LaneFollowTraffic, CrossingTrafficGivesWayByTheCommonRule) {
  // Two cars reach the junction at the same moment on crossing straight paths: the lower
  // station id goes first, the other stops at the entry and goes after it.
  Traffic t(shared_map("simple_4way_intersection.xodr"));
  t.add("0", -1, 70.0, 10.0, to(10.0, "2", -1, 60.0));  // west → east
  t.add("1", 1, 30.0, 10.0, to(10.0, "3", -1, 60.0));   // south → north
  double first_out = 0.0, second_out = 0.0;
  bool second_stopped = false;
  for (int i = 0; i < 3000; ++i) {
    t.step();
    const double now = i * kDt;
    if (first_out == 0.0 && t.roads(0).count("2"))
      first_out = now;
    if (second_out == 0.0 && t.roads(1).count("3"))
      second_out = now;
    second_stopped = second_stopped || (t.car(1).speed() < 0.1 && second_out == 0.0);
  }
  EXPECT_EQ(t.collisions(), 0) << t.first_collision();
  EXPECT_EQ(t.off_lane(), 0) << t.first_off_lane();
  ASSERT_GT(first_out, 0.0);
  ASSERT_GT(second_out, 0.0);
  EXPECT_LT(first_out, second_out);
  EXPECT_TRUE(second_stopped) << "the second car did not wait at the entry";
  // Both stop at their goals.
  for (std::size_t car : {0u, 1u}) {
    EXPECT_NEAR(t.car(car).speed(), 0.0, 0.05);
    // (The plant brakes more weakly than the driver's model expects: it overshoots a little.)
    EXPECT_NEAR(where(t, car).s, 60.0, 2.5) << "car " << car;
  }
}

TEST(LaneFollowTraffic, ARouteOfRoadsIsDrivenInOrder) {
  Traffic t(shared_map("simple_4way_intersection.xodr"));
  scenario::LaneFollowDriver d = lane_follow(10.0, Kind::kRoads);
  d.route.roads = {"0", "3"};
  t.add("0", -1, 40.0, 0.0, d);
  t.run(30.0);
  const auto& roads = t.roads(0);
  EXPECT_TRUE(roads.count("0") && roads.count("3"));
  EXPECT_EQ(roads.size(), 3u);  // 0, the connecting road, 3
  EXPECT_EQ(t.map().network().roads[static_cast<std::size_t>(where(t, 0).ref.road)].id, "3");
  EXPECT_NEAR(t.car(0).speed(), 0.0, 0.05);  // stopped before road 3's open end
  EXPECT_EQ(t.off_lane(), 0) << t.first_off_lane();
}

TEST(LaneFollowTraffic, FollowsTheCarAheadAtATimeGap) {
  // A built-in straight road: a car at 15 m/s catches up with one at 8 m/s and follows it.
  scenario::MapSpec spec;
  spec.length = 2000.0;
  Traffic t(std::make_shared<const odr::RoadNetwork>(map::generate_network(spec)));
  t.add("0", -1, 100.0, 8.0, lane_follow(8.0, Kind::kLane));
  t.add("0", -1, 20.0, 15.0, lane_follow(15.0, Kind::kLane));
  double min_gap = 1e9;
  for (int i = 0; i < 6000; ++i) {
    t.step();
    min_gap = std::min(min_gap, t.driver(1).status().leader_gap);
  }
  EXPECT_EQ(t.collisions(), 0) << t.first_collision();
  EXPECT_GT(min_gap, 2.0);
  EXPECT_NEAR(t.car(1).speed(), 8.0, 0.3);
  // Settled at kMinGap + kTimeGap x speed: 2.5 + 1.2 x 8 m.
  EXPECT_NEAR(t.driver(1).status().leader_gap, 2.5 + 1.2 * 8.0, 1.5);
}

TEST(LaneFollowTraffic, IgnoringTrafficDrivesTheProfileRegardless) {
  // "traffic": "ignore" (the LCRW cases' scripted near misses): no slowing for the car ahead.
  scenario::MapSpec spec;
  spec.length = 2000.0;
  Traffic t(std::make_shared<const odr::RoadNetwork>(map::generate_network(spec)));
  scenario::LaneFollowDriver slow = lane_follow(8.0, Kind::kLane);
  slow.yield_to_traffic = false;
  t.add("0", -1, 100.0, 8.0, slow);
  scenario::LaneFollowDriver reckless = lane_follow(15.0, Kind::kLane);
  reckless.yield_to_traffic = false;
  t.add("0", -1, 20.0, 15.0, reckless);
  t.run(15.0);
  EXPECT_GT(t.collisions(), 0);
  EXPECT_FALSE(t.saw(SpeedLimit::kLeader));
}

TEST(LaneFollowTraffic, RingTrafficAtMixedSpeedsNeverCollides) {
  scenario::MapSpec spec;
  spec.type = scenario::MapType::kRing;
  spec.lanes = 2;
  spec.oncoming_lanes = 0;
  spec.radius = 100.0;
  Traffic t(std::make_shared<const odr::RoadNetwork>(map::generate_network(spec)));
  const double speeds[] = {9.0, 14.0, 11.0, 16.0, 10.0, 13.0};
  for (int i = 0; i < 6; ++i)
    t.add("0", i % 2 == 0 ? -1 : -2, 90.0 * i + 10.0, speeds[i],
          lane_follow(speeds[i], Kind::kLane));
  t.run(120.0);
  EXPECT_EQ(t.collisions(), 0) << t.first_collision();
  EXPECT_EQ(t.off_lane(), 0) << t.first_off_lane();
  EXPECT_TRUE(t.saw(SpeedLimit::kLeader));
}

TEST(LaneFollowTraffic, MotorwayMergeOfTheSharedMap) {
  // highway_merge.xodr: a one-lane ramp joins a two-lane motorway through a junction as its
  // third lane; motorway and ramp traffic at 20 m/s, random routes, until all stand at the
  // motorway's end.
  Traffic t(shared_map("highway_merge.xodr"));
  t.add("0", -1, 10.0, 20.0, lane_follow(20.0));
  t.add("0", -2, 30.0, 20.0, lane_follow(20.0));
  t.add("0", -1, 50.0, 20.0, lane_follow(20.0));
  t.add("1", -1, 20.0, 15.0, lane_follow(20.0));
  t.add("1", -1, 50.0, 15.0, lane_follow(20.0));
  t.run(40.0);
  EXPECT_EQ(t.collisions(), 0) << t.first_collision();
  EXPECT_EQ(t.off_lane(), 0) << t.first_off_lane();
  for (std::size_t i = 0; i < t.size(); ++i) {
    EXPECT_TRUE(t.roads(i).count("2")) << "car " << i;
    EXPECT_NEAR(t.car(i).speed(), 0.0, 0.05) << "car " << i;
  }
  EXPECT_LT(t.planned_lateral_accel(), 3.0 * 1.02);
}

// One road: two lanes along s, the outer one (an acceleration lane) ending after 150 m.
constexpr const char* kLaneEnds = R"(<?xml version="1.0"?>
<OpenDRIVE><header revMajor="1" revMinor="6"/>
<road id="m" junction="-1" length="600"><planView>
<geometry s="0" x="0" y="0" hdg="0" length="600"><line/></geometry></planView>
<lanes>
<laneSection s="0"><center><lane id="0" type="none"/></center><right>
<lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane>
<lane id="-2" type="entry"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane>
</right></laneSection>
<laneSection s="150"><center><lane id="0" type="none"/></center><right>
<lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane>
</right></laneSection>
</lanes></road></OpenDRIVE>)";

TEST(LaneFollowTraffic, AnEndingLaneMergesIntoAGap) {
  // A car on the ending lane, a queue of three beside it at the same speed: it waits at the
  // start of its lane change for a gap, merges behind them and drives on.
  Traffic t(std::make_shared<const odr::RoadNetwork>(odr::parse_opendrive(kLaneEnds, "lane-ends")));
  t.add("m", -2, 20.0, 10.0, lane_follow(10.0));
  for (double s : {12.0, 30.0, 48.0})
    t.add("m", -1, s, 10.0, lane_follow(10.0));
  t.run(60.0);
  EXPECT_EQ(t.collisions(), 0) << t.first_collision();
  EXPECT_EQ(t.off_lane(), 0) << t.first_off_lane();
  EXPECT_TRUE(t.saw(SpeedLimit::kLaneChange));
  const odr::LanePosition merged = where(t, 0);
  EXPECT_EQ(merged.ref.lane, -1);
  EXPECT_GT(merged.s, 150.0);
  for (std::size_t other : {1u, 2u, 3u})
    EXPECT_LT(t.car(0).state().position[0], t.car(other).state().position[0]);
}

TEST(LaneFollowTraffic, SlowsForTheCurvesOfASharedMap) {
  Traffic t(shared_map("curves.xodr"));
  const odr::Road& r = t.map().network().roads.front();
  const int lane = r.sections.front().right.empty() ? 1 : -1;
  t.add(r.id, lane, lane < 0 ? 5.0 : r.length - 5.0, 20.0, lane_follow(20.0, Kind::kLane));
  double slowest = 1e9;
  for (int i = 0; i < 4000; ++i) {
    t.step();
    if (t.driver(0).status().limit == SpeedLimit::kCurve)
      slowest = std::min(slowest, t.car(0).speed());
  }
  EXPECT_LT(slowest, 19.0) << "never slowed for a curve";
  EXPECT_LT(t.planned_lateral_accel(), 3.0 * 1.02);
  EXPECT_EQ(t.off_lane(), 0) << t.first_off_lane();
}

std::shared_ptr<const odr::RoadNetwork> shipped_map(const char* name) {
  const char* root = std::getenv("TESTBED_ROOT");
  const std::filesystem::path dir =
      std::filesystem::path(root != nullptr ? root : ".") / "scenarios" / "maps";
  return std::make_shared<const odr::RoadNetwork>(odr::load_opendrive((dir / name).string()));
}

TEST(LaneFollowTraffic, RandomRoutesRoundTheShippedFourWayJunction) {
  // A closed network: random routes never end. Ten cars, two minutes.
  Traffic t(shipped_map("four_way_junction.xodr"));
  int n = 0;
  for (const char* road : {"1", "2", "3", "4", "10", "11"}) {
    for (int lane : {-1, 1}) {
      if (n++ >= 10)
        break;
      const odr::Road& r =
          t.map().network().roads[static_cast<std::size_t>(t.map().network().road_index(road))];
      t.add(road, lane, r.length / 2, 8.0, lane_follow(12.0), 7);
    }
  }
  t.run(120.0);
  EXPECT_EQ(t.collisions(), 0) << t.first_collision();
  EXPECT_EQ(t.off_lane(), 0) << t.first_off_lane();
  EXPECT_TRUE(t.saw(SpeedLimit::kJunction));
  EXPECT_LT(t.planned_lateral_accel(), 3.0 * 1.02);
  // Still driving: no dead ends, no gridlock.
  int moving = 0;
  for (std::size_t i = 0; i < t.size(); ++i)
    moving += t.car(i).speed() > 1.0;
  EXPECT_GE(moving, 5);
}

TEST(LaneFollowTraffic, MotorwayTrafficLeavesAndMergesBack) {
  // The shipped motorway: eastbound cars in both lanes at 25 m/s, random routes take some off
  // at the exit; they come back along the ramp into the acceleration lane and merge.
  Traffic t(shipped_map("motorway_merge.xodr"));
  const double s_left[] = {20.0, 80.0, 140.0, 200.0};
  for (int i = 0; i < 4; ++i)
    t.add("1", i % 2 == 0 ? -1 : -2, s_left[i], 20.0, lane_follow(25.0), 3);
  t.add("5", 1, 300.0, 20.0, lane_follow(25.0), 3);  // westbound
  t.add("7", -1, 50.0, 15.0, lane_follow(20.0), 3);  // on the ramp
  t.run(150.0);
  EXPECT_EQ(t.collisions(), 0) << t.first_collision();
  EXPECT_EQ(t.off_lane(), 0) << t.first_off_lane();
  EXPECT_LT(t.planned_lateral_accel(), 3.0 * 1.02);
  std::size_t merged = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    merged += t.roads(i).count("202") > 0 && t.roads(i).count("3") > 0;
    EXPECT_GT(t.car(i).speed(), 5.0) << "car " << i << " stuck";
  }
  EXPECT_GE(merged, 1u);
}

}  // namespace
}  // namespace tb::client
