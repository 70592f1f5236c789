// A GPS agent feeding the real gpsd (Debian 12: 3.22), read back through libgps as the
// station reads it: the fix gpsd reports must be the fix the agent meant.

#include <arpa/inet.h>
#include <gps.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <map>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "network-emulator/gnss/gps_agent.hpp"
#include "network-emulator/gnss/sky.hpp"

extern char** environ;

namespace tb::emu::gnss {
namespace {

using namespace std::chrono_literals;

int free_port(int type) {
  const int fd = ::socket(AF_INET, type, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  ::close(fd);
  return ntohs(a.sin_port);
}

/// gpsd reading NMEA from a UDP port, serving clients on a TCP port; killed on destruction.
class Gpsd {
 public:
  Gpsd() : nmea_port_(free_port(SOCK_DGRAM)), client_port_(free_port(SOCK_STREAM)) {
    const std::string port = std::to_string(client_port_);
    const std::string source = "udp://127.0.0.1:" + std::to_string(nmea_port_);
    std::vector<std::string> args{"gpsd", "-N", "-n", "-b", "-S", port, source};
    std::vector<char*> argv;
    for (auto& a : args)
      argv.push_back(a.data());
    argv.push_back(nullptr);
    if (::posix_spawnp(&pid_, "gpsd", nullptr, nullptr, argv.data(), environ) != 0)
      pid_ = -1;
  }
  ~Gpsd() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  bool started() const { return pid_ > 0; }
  int nmea_port() const { return nmea_port_; }
  int client_port() const { return client_port_; }

 private:
  int nmea_port_, client_port_;
  pid_t pid_ = -1;
};

class GpsdFeed : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(gpsd_.started()) << "cannot start gpsd (package gpsd)";
    const std::string port = std::to_string(gpsd_.client_port());
    bool open = false;
    for (int i = 0; i < 100 && !open; ++i) {  // gpsd needs a moment to listen
      open = gps_open("127.0.0.1", port.c_str(), &data_) == 0;
      if (!open)
        std::this_thread::sleep_for(50ms);
    }
    ASSERT_TRUE(open) << "gpsd does not accept clients on port " << port;
    opened_ = true;
    gps_stream(&data_, WATCH_ENABLE | WATCH_JSON, nullptr);
    udp_ = ::socket(AF_INET, SOCK_DGRAM, 0);
    to_.sin_family = AF_INET;
    to_.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    to_.sin_port = htons(static_cast<std::uint16_t>(gpsd_.nmea_port()));
  }
  void TearDown() override {
    if (opened_) {
      gps_stream(&data_, WATCH_DISABLE, nullptr);
      gps_close(&data_);
    }
    if (udp_ >= 0)
      ::close(udp_);
  }

  void send(std::string_view datagram) {
    ::sendto(udp_, datagram.data(), datagram.size(), 0, reinterpret_cast<sockaddr*>(&to_),
             sizeof to_);
  }

  /// Reads reports for up to @p wait and returns the TPVs (by fix time, ns) with mode ≥ 1.
  std::map<std::int64_t, gps_fix_t> read_fixes(std::chrono::milliseconds wait) {
    std::map<std::int64_t, gps_fix_t> out;
    const auto deadline = std::chrono::steady_clock::now() + wait;
    while (std::chrono::steady_clock::now() < deadline) {
      if (!gps_waiting(&data_, 50'000))
        continue;
      if (gps_read(&data_, nullptr, 0) < 0)
        break;
      if ((data_.set & MODE_SET) && (data_.set & TIME_SET) && data_.fix.mode >= MODE_NO_FIX) {
        const std::int64_t t =
            std::int64_t{data_.fix.time.tv_sec} * 1'000'000'000 + data_.fix.time.tv_nsec;
        out[t] = data_.fix;
      }
    }
    return out;
  }

  Gpsd gpsd_;
  gps_data_t data_{};
  bool opened_ = false;
  int udp_ = -1;
  sockaddr_in to_{};
};

const geodesy::LocalFrame& frame() {
  static const geodesy::LocalFrame f({48.137, 11.575, 520.0});
  return f;
}

AgentConfig agent_config() {
  AgentConfig c;
  c.station_id = 7;
  c.rate_hz = 10.0;
  c.start_time = std::chrono::system_clock::time_point{std::chrono::seconds{1735732800}};
  return c;
}

struct Truth {
  geodesy::Geodetic position;
  double speed, track;
};

TEST_F(GpsdFeed, IdealFixComesBackExactly) {
  GpsAgent agent(agent_config(), frame());
  std::map<std::int64_t, Truth> truth;
  wire::VehicleState s;
  s.station_id = 7;
  const double speed = 13.7, heading = 37.0;  // m/s, degrees clockwise from north
  const double yaw = (90.0 - heading) * M_PI / 180.0;
  s.velocity = {static_cast<float>(speed * std::cos(yaw)),
                static_cast<float>(speed * std::sin(yaw)), 0.0f};
  for (int i = 0; i < 30; ++i) {
    s.sim_time_ns = std::int64_t{i} * 100'000'000 + 5'000'000'000;
    const double t = static_cast<double>(i) * 0.1;
    s.position = {200.0 + speed * std::cos(yaw) * t, -80.0 + speed * std::sin(yaw) * t, 2.0};
    const auto out = agent.on_state(s);
    ASSERT_TRUE(out);
    const auto epoch_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                              agent.last_fix().time.time_since_epoch())
                              .count();
    truth[epoch_ns] = {frame().to_geodetic({s.position[0], s.position[1], s.position[2]}), speed,
                       heading};
    send(*out);
    std::this_thread::sleep_for(10ms);  // gpsd reads one datagram per cycle
  }
  const auto fixes = read_fixes(1500ms);
  int checked = 0;
  for (const auto& [t, fix] : fixes) {
    if (fix.mode != MODE_3D)
      continue;
    const auto it = truth.find(t);
    ASSERT_NE(it, truth.end()) << "gpsd reports a fix time the agent never sent: " << t;
    const auto enu = frame().to_enu({fix.latitude, fix.longitude, it->second.position.altitude_m});
    const auto want = frame().to_enu(it->second.position);
    EXPECT_LT(std::hypot(enu.east - want.east, enu.north - want.north), 0.1);
    ASSERT_TRUE(std::isfinite(fix.speed));
    EXPECT_NEAR(fix.speed, it->second.speed, 0.05);
    ASSERT_TRUE(std::isfinite(fix.track));
    EXPECT_NEAR(fix.track, it->second.track, 0.5);
    ASSERT_TRUE(std::isfinite(fix.altHAE));
    EXPECT_NEAR(fix.altHAE, it->second.position.altitude_m, 0.01);
    ++checked;
  }
  EXPECT_GE(checked, 20) << "gpsd reported " << fixes.size() << " fixes";
}

TEST_F(GpsdFeed, ErrorEstimatesFollowTheConfiguredModel) {
  AgentConfig c = agent_config();
  c.errors.ideal = false;
  c.errors.white_noise_m = 2.0;
  c.errors.bias_walk_m = 0.0;
  c.errors.vertical_noise_m = 3.0;
  c.errors.hdop = 1.6;
  c.errors.vdop = 2.2;
  c.errors.satellites = 8;
  GpsAgent agent(c, frame());
  wire::VehicleState s;
  s.station_id = 7;
  for (int i = 0; i < 20; ++i) {
    s.sim_time_ns = std::int64_t{i} * 100'000'000;
    s.position = {10.0, 10.0, 0.0};
    send(*agent.on_state(s));
    std::this_thread::sleep_for(10ms);
  }
  const auto fixes = read_fixes(1500ms);
  const auto dop = compute_dop(agent.last_fix().sky);
  ASSERT_TRUE(dop.has_value());
  int checked = 0, seen = 0;
  for (const auto& [t, fix] : fixes) {
    // gpsd learns which sentence ends a cycle during the first epochs and may report them
    // before it has read their GSV; a receiver's first fixes lack epx/epy the same way.
    if (fix.mode != MODE_3D || ++seen <= 2)
      continue;
    ASSERT_TRUE(std::isfinite(fix.eph));
    ASSERT_TRUE(std::isfinite(fix.epx));
    ASSERT_TRUE(std::isfinite(fix.epy));
    ASSERT_TRUE(std::isfinite(fix.epv));
    // gpsd 3.22 scales the DOPs by its UERE figures (gpsd.h): eph = HDOP × 19 m and
    // epv = VDOP × 23 m from the reported DOPs; epx/epy = xdop/ydop × 15 m from the
    // satellites' geometry, which the agent built to have the configured HDOP.
    EXPECT_NEAR(fix.eph, 19.0 * c.errors.hdop, 0.01 * 19.0 * c.errors.hdop);
    EXPECT_NEAR(fix.epv, 23.0 * c.errors.vdop, 0.01 * 23.0 * c.errors.vdop);
    EXPECT_NEAR(fix.epx, 15.0 * dop->xdop, 0.03 * 15.0 * dop->xdop);
    EXPECT_NEAR(fix.epy, 15.0 * dop->ydop, 0.03 * 15.0 * dop->ydop);
    EXPECT_NEAR(std::hypot(fix.epx, fix.epy) / 15.0, c.errors.hdop, 0.03 * c.errors.hdop);
    ++checked;
  }
  EXPECT_GE(checked, 10);
}

TEST_F(GpsdFeed, FixLossWindowIsReportedAsNoFix) {
  AgentConfig c = agent_config();
  c.errors.fix_loss = {{1.0, 1.5}};
  GpsAgent agent(c, frame());
  wire::VehicleState s;
  s.station_id = 7;
  s.position = {0.0, 0.0, 0.0};
  for (int i = 0; i < 25; ++i) {
    s.sim_time_ns = std::int64_t{i} * 100'000'000;
    send(*agent.on_state(s));
    std::this_thread::sleep_for(10ms);
  }
  const auto fixes = read_fixes(1500ms);
  const auto start_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(c.start_time.time_since_epoch()).count();
  int lost = 0, regained = 0;
  for (const auto& [t, fix] : fixes) {
    const double sim_s = static_cast<double>(t - start_ns) * 1e-9;
    if (sim_s >= 1.0 && sim_s < 1.45) {
      EXPECT_LE(fix.mode, MODE_NO_FIX) << "at " << sim_s << " s";
      ++lost;
    } else if (sim_s >= 1.65) {
      EXPECT_EQ(fix.mode, MODE_3D) << "at " << sim_s << " s";
      ++regained;
    }
  }
  EXPECT_GE(lost, 3);
  EXPECT_GE(regained, 5);
}

}  // namespace
}  // namespace tb::emu::gnss
