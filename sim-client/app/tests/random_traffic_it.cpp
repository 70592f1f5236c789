// Scripted traffic with random routes for 10 minutes of sim time on every junction map (every
// map in ../shared/data/opendrive with a <junction>, found by reading the folder, and the
// shipped ones in scenarios/maps), through the real programs: sim-server
// --fast (lockstep with its drivers) with the map, one sim-client --scripted driving every car,
// and this test watching the state stream: no two cars' footprints overlap, no wheel leaves the
// drivable lanes, and the cars drive.

#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/time.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/write.hpp>
#include <nlohmann/json.hpp>

#include "common/map/builtin_network.hpp"
#include "common/map/opendrive/lane_graph.hpp"
#include "common/map/opendrive/reader.hpp"
#include "common/wire/sim_protocol.hpp"
#include "sim-client/app/tests/child_process.hpp"

namespace tb::client {
namespace {

namespace asio = boost::asio;
namespace fs = std::filesystem;
namespace odr = map::odr;
using namespace std::chrono_literals;
using testing::ChildProcess;

constexpr double kSimSeconds = 600.0;  // 10 minutes of sim time with every car driven
// sim-server --fast starts once the client has attached every car; the first steps until the
// cars move are not counted, so that the run is this much longer. On a loaded machine the
// first cars moved only 5.3 s in (the warm-up, then steps that gave up waiting for a slow
// driver): 15 s of sim time cost a tenth of a second.
constexpr double kStartSlack = 15.0;

fs::path root() {
  const char* r = std::getenv("TESTBED_ROOT");
  return r != nullptr ? fs::path(r) : fs::current_path();
}

fs::path bin() {
  const char* b = std::getenv("TESTBED_BIN");
  return b != nullptr ? fs::path(b) : root() / "build" / "bin";
}

struct MapCase {
  std::string name;
  fs::path file;  ///< an OpenDRIVE file; empty: the built-in layout in `builtin`
  std::string builtin;
  int cars = 10;
  double speed = 12.0;         ///< m/s, the drivers' target
  double min_distance = 50.0;  ///< m each car drives at least (maps with dead ends: less)
};

std::ostream& operator<<(std::ostream& o, const MapCase& c) {
  return o << c.name;
}

// Where the cars start: points every 25 m along the drivable lanes outside junctions (15 m
// from their ends), spread
// over the map (every k-th of them in a fixed order), at least 12 m apart.
std::vector<odr::LanePosition> spawn_points(const odr::RoadNetwork& net, int cars) {
  const odr::LaneGraph g(net);
  std::vector<odr::LanePosition> all;
  for (std::size_t i = 0; i < g.size(); ++i) {
    const odr::LaneNode& n = g.node(i);
    const odr::Road& r = net.roads[static_cast<std::size_t>(n.road)];
    if (!n.drivable || r.junction_index >= 0 || n.length < 20.0)
      continue;
    const odr::LaneSection& ls = r.sections[n.section];
    // 25 m from either end: a car that starts at standstill a few metres before a dead end
    // (the shared maps' roads end at the map's edge) has no room to gather speed and stop
    // kEndMargin short of it: it overran it once in nine runs at 8 m, and at 15 m twice in
    // about ten runs of 2026-11-27 (by 1.3 m, at 3.9 and 6.6 m/s), an open defect of the lane
    // follower's stop before a lane's end that this test is not about.
    for (double s = ls.s + 25.0; s < ls.s_end - 25.0; s += 25.0)
      all.push_back({{n.road, n.lane}, n.section, s, 0.0, 0.0});
  }
  std::vector<odr::LanePosition> out;
  const std::size_t step = std::max<std::size_t>(1, all.size() / static_cast<std::size_t>(cars));
  // Every step-th point, then the ones after those, and so on, until there are enough cars.
  for (std::size_t offset = 0; offset < step; ++offset) {
    for (std::size_t k = offset; k < all.size(); k += step) {
      if (out.size() == static_cast<std::size_t>(cars))
        return out;
      const auto p = odr::lane_pose(net, all[k].ref.road, all[k].ref.lane, all[k].s);
      const bool clear = std::all_of(out.begin(), out.end(), [&](const odr::LanePosition& o) {
        const auto q = odr::lane_pose(net, o.ref.road, o.ref.lane, o.s);
        return std::hypot(p.x - q.x, p.y - q.y) > 12.0;
      });
      if (clear)
        out.push_back(all[k]);
    }
  }
  return out;
}

// The scenario: every car a lane follower on a random route.
std::string scenario_for(const MapCase& c, const odr::RoadNetwork& net) {
  nlohmann::json sc;
  sc["name"] = "random-traffic-" + c.name;
  sc["map"] = c.file.empty() ? nlohmann::json::parse(c.builtin)
                             : nlohmann::json{{"type", "opendrive"}, {"file", c.file.string()}};
  sc["origin"] = {{"lat", 48.1}, {"lon", 11.5}, {"alt", 500}};
  sc["duration_s"] = kSimSeconds + kStartSlack;
  // 50 Hz: half the steps of the default, half the wall time; the drivers answer every one.
  sc["rates"] = {{"physics_hz", 50}};
  sc["seed"] = 17;
  int i = 0;
  for (const odr::LanePosition& p : spawn_points(net, c.cars)) {
    const odr::Road& r = net.roads[static_cast<std::size_t>(p.ref.road)];
    nlohmann::json v;
    v["id"] = "car" + std::to_string(i);
    v["station_id"] = 3000 + i;
    if (c.file.empty()) {
      // A built-in layout's lane index (0 = the right edge) of the OpenDRIVE lane, its s
      // (the ring's lanes are all one way here).
      v["spawn"] = {{"lane", static_cast<int>(r.sections[0].right.size()) + p.ref.lane},
                    {"s", p.s},
                    {"speed", 0}};
    } else {
      v["spawn"] = {{"road", r.id}, {"lane", p.ref.lane}, {"s", p.s}, {"speed", 0}};
    }
    v["driver"] = {{"type", "lane_follow"},
                   {"speed_profile", nlohmann::json::array({{{"t", 0}, {"speed", c.speed}}})},
                   {"route", "random"}};
    sc["vehicles"].push_back(v);
    ++i;
  }
  return sc.dump(1);
}

// The checks on every State frame.
class Checker {
 public:
  Checker(const odr::RoadNetwork& net, const std::vector<wire::sim::VehicleInfo>& cars)
      : net_(net), lanes_(net), cars_(cars), distance_(cars.size(), 0.0) {}

  void frame(const wire::sim::StateFrame& f) {
    ++frames_;
    last_sim_s_ = static_cast<double>(f.sim_time_ns) * 1e-9;
    const double dt = previous_ns_ > 0 ? (f.sim_time_ns - previous_ns_) * 1e-9 : 0.0;
    previous_ns_ = f.sim_time_ns;
    for (std::size_t i = 0; i < f.vehicles.size() && i < cars_.size(); ++i) {
      distance_[i] += std::abs(f.vehicles[i].speed) * dt;
      if (first_move_s_ < 0.0 && std::abs(f.vehicles[i].speed) > 0.5)
        first_move_s_ = last_sim_s_;
      for (const auto& w : box(f.vehicles[i], cars_[i].wheelbase_m, cars_[i].track_m)) {
        if (!on_drivable_lane(w[0], w[1]) && off_lane_++ == 0) {
          first_off_ = describe(f, i) + " wheel at (" + std::to_string(w[0]) + ", " +
                       std::to_string(w[1]) + ")";
        }
      }
      for (std::size_t j = i + 1; j < f.vehicles.size() && j < cars_.size(); ++j) {
        if (overlap(f.vehicles[i], cars_[i], f.vehicles[j], cars_[j]) && collisions_++ == 0)
          first_collision_ = describe(f, i) + " and " + describe(f, j);
      }
    }
  }

  std::uint64_t frames() const { return frames_; }
  double last_sim_s() const { return last_sim_s_; }
  /// When the first car moved (the client had attached); -1 if none did.
  double first_move_s() const { return first_move_s_; }
  std::size_t cars() const { return cars_.size(); }
  double min_distance() const { return *std::min_element(distance_.begin(), distance_.end()); }
  int collisions() const { return collisions_; }
  int off_lane() const { return off_lane_; }
  const std::string& first_collision() const { return first_collision_; }
  const std::string& first_off() const { return first_off_; }
  double distance() const {
    double d = 0.0;
    for (double x : distance_)
      d += x;
    return d;
  }

 private:
  using Corners = std::array<std::array<double, 2>, 4>;
  static Corners box(const wire::VehicleState& s, double length, double width) {
    const double c = std::cos(s.yaw), sn = std::sin(s.yaw);
    Corners out{};
    const double lx[4] = {length / 2, length / 2, -length / 2, -length / 2};
    const double ly[4] = {width / 2, -width / 2, -width / 2, width / 2};
    for (int i = 0; i < 4; ++i)
      out[i] = {s.position[0] + lx[i] * c - ly[i] * sn, s.position[1] + lx[i] * sn + ly[i] * c};
    return out;
  }
  static bool overlap(const wire::VehicleState& a, const wire::sim::VehicleInfo& ma,
                      const wire::VehicleState& b, const wire::sim::VehicleInfo& mb) {
    const Corners ca = box(a, ma.length_m, ma.width_m), cb = box(b, mb.length_m, mb.width_m);
    for (const Corners* poly : {&ca, &cb}) {
      for (int i = 0; i < 4; ++i) {
        const double nx = (*poly)[(i + 1) % 4][1] - (*poly)[i][1];
        const double ny = (*poly)[i][0] - (*poly)[(i + 1) % 4][0];
        double a0 = 1e300, a1 = -1e300, b0 = 1e300, b1 = -1e300;
        for (const auto& v : ca) {
          a0 = std::min(a0, v[0] * nx + v[1] * ny);
          a1 = std::max(a1, v[0] * nx + v[1] * ny);
        }
        for (const auto& v : cb) {
          b0 = std::min(b0, v[0] * nx + v[1] * ny);
          b1 = std::max(b1, v[0] * nx + v[1] * ny);
        }
        if (a1 < b0 || b1 < a0)
          return false;
      }
    }
    return true;
  }
  bool on_drivable_lane(double x, double y) const {
    for (const odr::LanePosition& f : lanes_.locate_all(x, y)) {
      const odr::Lane* l =
          net_.roads[static_cast<std::size_t>(f.ref.road)].sections[f.section].lane(f.ref.lane);
      if (l != nullptr && l->drivable)
        return true;
    }
    return false;
  }
  std::string describe(const wire::sim::StateFrame& f, std::size_t i) const {
    std::ostringstream o;
    o << cars_[i].id << " at t = " << f.sim_time_ns * 1e-9 << " s (" << f.vehicles[i].position[0]
      << ", " << f.vehicles[i].position[1] << ") yaw " << f.vehicles[i].yaw << " speed "
      << f.vehicles[i].speed;
    return o.str();
  }

  const odr::RoadNetwork& net_;
  odr::LaneLocator lanes_;
  std::vector<wire::sim::VehicleInfo> cars_;
  std::vector<double> distance_;
  std::uint64_t frames_ = 0;
  std::int64_t previous_ns_ = 0;
  double last_sim_s_ = 0.0;
  double first_move_s_ = -1.0;
  int collisions_ = 0, off_lane_ = 0;
  std::string first_collision_, first_off_;
};

class RandomTraffic : public ::testing::TestWithParam<MapCase> {};

TEST_P(RandomTraffic, TenMinutesWithoutCollisionsOrLeavingTheLanes) {
  const MapCase& c = GetParam();
  if (!fs::exists(bin() / "sim-server") || !fs::exists(bin() / "sim-client"))
    GTEST_SKIP() << "sim-server and sim-client are not in " << bin();
  const odr::RoadNetwork net = c.file.empty() ? map::generate_network([&] {
    scenario::MapSpec s;
    const auto j = nlohmann::json::parse(c.builtin);
    s.type = scenario::MapType::kRing;
    s.lanes = j.value("lanes", 2);
    s.oncoming_lanes = j.value("oncoming_lanes", 0);
    s.radius = j.value("radius", 150.0);
    return s;
  }())
                                              : odr::load_opendrive(c.file.string());
  const fs::path dir = fs::path(::testing::TempDir()) /
                       ("random_traffic_" + c.name + "_" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "scenario.json") << scenario_for(c, net);

  const auto started = std::chrono::steady_clock::now();
  ChildProcess server(
      {(bin() / "sim-server").string(), "--scenario", (dir / "scenario.json").string(), "--port",
       "0", "--bind", "127.0.0.1", "--fast", "--queue", "100000"},
      (dir / "server.log").string());
  const auto port = server.wait_for(std::regex(R"(listening on [^ ]*:(\d+))"), 10s);
  ASSERT_TRUE(port) << server.log();

  // The driving client at once (the server runs at full speed until it has attached), then
  // this test's watcher.
  ChildProcess client({(bin() / "sim-client").string(), "--server", "127.0.0.1:" + *port,
                       "--scripted", "--headless", "--no-forward"},
                      (dir / "client.log").string());
  asio::io_context io;
  asio::ip::tcp::socket sock(io);
  sock.connect(
      {asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(std::stoi(*port))});
  const timeval tv{1, 0};
  setsockopt(sock.native_handle(), SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  asio::write(sock, asio::buffer(wire::sim::encode(wire::sim::Hello{"random-traffic-it"})));

  wire::sim::FrameParser parser(wire::sim::Sender::kServer);
  std::optional<Checker> check;
  bool closed = false;
  std::array<std::uint8_t, 65536> buf{};
  const auto deadline = started + 240s;
  while (!closed && std::chrono::steady_clock::now() < deadline) {
    boost::system::error_code ec;
    const std::size_t n = sock.read_some(asio::buffer(buf), ec);
    if (ec == asio::error::would_block || ec == asio::error::try_again)
      continue;
    if (ec)
      break;
    std::span<const std::uint8_t> data(buf.data(), n);
    while (!data.empty()) {
      auto r = parser.parse(data);
      ASSERT_TRUE(r) << wire::sim::to_string(r.error());
      if (*r != wire::sim::FrameParser::Status::kFrame)
        continue;
      auto m = wire::sim::decode_server(parser.frame());
      ASSERT_TRUE(m) << wire::sim::to_string(m.error());
      if (const auto* w = std::get_if<wire::sim::Welcome>(&*m)) {
        check.emplace(net, w->vehicles);
        asio::write(
            sock, asio::buffer(wire::sim::encode(wire::sim::Attach{wire::sim::Role::kWatcher, 0})));
      } else if (const auto* f = std::get_if<wire::sim::StateFrame>(&*m)) {
        check->frame(*f);
      } else if (std::holds_alternative<wire::sim::Closing>(*m)) {
        closed = true;
      }
    }
  }
  const auto rc = server.wait(10s);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  ASSERT_TRUE(check) << server.log();
  RecordProperty("wall_s", std::to_string(wall));
  std::printf(
      "%s: %.0f s of sim time (cars driven from %.1f s) in %.1f s of wall time, %llu "
      "frames, %.0f m driven, at least %.0f m by each car\n",
      c.name.c_str(), check->last_sim_s(), check->first_move_s(), wall,
      static_cast<unsigned long long>(check->frames()), check->distance(), check->min_distance());
  EXPECT_TRUE(closed) << "no end of the run within 240 s; server log:\n" << server.log();
  ASSERT_TRUE(rc && *rc == 0) << server.log();
  ASSERT_GE(check->first_move_s(), 0.0) << "no car ever moved; client log:\n" << client.log();
  EXPECT_GE(check->last_sim_s() - check->first_move_s(), kSimSeconds)
      << "the client attached " << check->first_move_s() << " s into the run";
  EXPECT_EQ(check->collisions(), 0) << "first: " << check->first_collision();
  EXPECT_EQ(check->off_lane(), 0) << "first: " << check->first_off();
  // The drivers answered every step: none was waited for in vain.
  EXPECT_NE(server.log().find("0 fast step(s) that gave up waiting"), std::string::npos)
      << server.log();
  EXPECT_GT(check->min_distance(), c.min_distance) << "a car hardly drove";
  fs::remove_all(dir);
}

// Every shared map (TESTBED_OPENDRIVE_DIR, else ../shared/data/opendrive) that has a
// junction, found by reading the folder: a map added there is driven without a change here.
// Their roads end in dead ends: a car spawned a few metres before one stops there at once, so
// each car need drive only 2 m (the others drive on).
std::vector<MapCase> shared_junction_maps() {
  const char* env = std::getenv("TESTBED_OPENDRIVE_DIR");
  const fs::path shared = env != nullptr && *env != '\0'
                              ? fs::path(env)
                              : root() / ".." / "shared" / "data" / "opendrive";
  std::vector<MapCase> out;
  if (!fs::is_directory(shared))
    return out;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(shared)) {
    if (e.path().extension() == ".xodr")
      files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    if (odr::load_opendrive(f.string()).junctions.empty())
      continue;
    std::string name = "shared_" + f.stem().string();
    std::replace_if(
        name.begin(), name.end(),
        [](char ch) { return std::isalnum(static_cast<unsigned char>(ch)) == 0; }, '_');
    out.push_back({name, f, "", 6, 10.0, 2.0});
  }
  return out;
}

std::vector<MapCase> cases() {
  const fs::path shipped = root() / "scenarios" / "maps";
  std::vector<MapCase> out = {
      {"ring",
       {},
       R"({"type": "ring", "lanes": 2, "oncoming_lanes": 0, "radius": 100})",
       10,
       14.0,
       3000.0},
      // The project's own junction: every turn, looping arms, hills (scenarios/maps).
      {"four_way_junction", shipped / "four_way_junction.xodr", "", 10, 10.0, 500.0},
      // The motorway oval with its exit and the merge back.
      {"motorway_merge", shipped / "motorway_merge.xodr", "", 10, 20.0, 1000.0},
  };
  for (MapCase& c : shared_junction_maps())
    out.push_back(std::move(c));
  return out;
}

INSTANTIATE_TEST_SUITE_P(Maps, RandomTraffic, ::testing::ValuesIn(cases()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace tb::client
