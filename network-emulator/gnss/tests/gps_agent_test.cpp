#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "network-emulator/gnss/gps_agent.hpp"
#include "network-emulator/gnss/tests/nmea_parse.hpp"

namespace tb::emu::gnss {
namespace {

using testing::nmea_degrees;
using testing::parse_datagram;

const geodesy::LocalFrame& frame() {
  static const geodesy::LocalFrame f({48.0, 11.0, 500.0});
  return f;
}

AgentConfig config(bool ideal = true) {
  AgentConfig c;
  c.station_id = 1001;
  c.rate_hz = 10.0;
  c.start_time = std::chrono::system_clock::time_point{std::chrono::seconds{1735732800}};
  c.errors.ideal = ideal;
  if (!ideal) {
    c.errors.white_noise_m = 1.0;
    c.errors.bias_walk_m = 0.0;
    c.errors.vertical_noise_m = 2.0;
  }
  return c;
}

wire::VehicleState state(std::int64_t sim_ms, double x = 100.0, double y = -50.0) {
  wire::VehicleState s;
  s.station_id = 1001;
  s.tick = static_cast<std::uint64_t>(sim_ms / 10);
  s.sim_time_ns = sim_ms * 1'000'000;
  s.position = {x, y, 1.5};
  s.velocity = {0.0f, 10.0f, 0.0f};  // due north
  s.yaw = static_cast<float>(std::numbers::pi / 2);
  return s;
}

TEST(GpsAgent, EmitsOneEpochPerPeriodOfSimTime) {
  GpsAgent agent(config(), frame());
  std::vector<std::int64_t> epoch_ms;
  for (std::int64_t ms = 0; ms <= 1000; ms += 10)  // 100 Hz physics
    if (agent.on_state(state(ms)))
      epoch_ms.push_back(ms);
  EXPECT_EQ(epoch_ms,
            (std::vector<std::int64_t>{0, 100, 200, 300, 400, 500, 600, 700, 800, 900, 1000}));
  // States that skip an epoch boundary (a late or lost datagram) do not create a burst.
  GpsAgent sparse(config(), frame());
  int n = 0;
  for (std::int64_t ms : {0, 30, 250, 260, 390, 400})
    n += sparse.on_state(state(ms)) ? 1 : 0;
  EXPECT_EQ(n, 4);  // 0, 250 (covers 100 and 200), 390 (covers 300), 400
}

TEST(GpsAgent, AnEpochOffsetMovesTheGridNotThePeriod) {
  AgentConfig c = config();
  c.epoch_offset = std::chrono::milliseconds{37};
  GpsAgent agent(c, frame());
  std::vector<std::int64_t> epoch_ms;
  for (std::int64_t ms = 0; ms <= 500; ms += 10)
    if (agent.on_state(state(ms)))
      epoch_ms.push_back(ms);
  // The first state makes an epoch; then the first state at or after 37, 137, 237 … ms.
  EXPECT_EQ(epoch_ms, (std::vector<std::int64_t>{0, 40, 140, 240, 340, 440}));
  // The fix is stamped with the time of the state it describes, not with the grid point.
  EXPECT_EQ(agent.last_fix().time, c.start_time + std::chrono::milliseconds{440});
}

TEST(GpsAgent, RejectsAnEpochOffsetOutsideThePeriod) {
  AgentConfig c = config();
  c.epoch_offset = std::chrono::milliseconds{100};
  EXPECT_THROW(GpsAgent(c, frame()), std::invalid_argument);
  c.epoch_offset = std::chrono::milliseconds{-1};
  EXPECT_THROW(GpsAgent(c, frame()), std::invalid_argument);
}

TEST(GpsAgent, WithoutSentencesMakesTheSameFixesAndNoText) {
  AgentConfig quiet_config = config(false);
  quiet_config.write_sentences = false;
  GpsAgent quiet(quiet_config, frame());
  GpsAgent talking(config(false), frame());
  int epochs = 0;
  for (std::int64_t ms = 0; ms <= 1000; ms += 10) {
    const auto a = quiet.on_state(state(ms, 100.0 + ms * 0.01));
    const auto b = talking.on_state(state(ms, 100.0 + ms * 0.01));
    ASSERT_EQ(a.has_value(), b.has_value()) << ms;
    if (!a)
      continue;
    ++epochs;
    EXPECT_TRUE(a->empty());
    EXPECT_FALSE(b->empty());
    // The same error model and seed: the same fix, noise included.
    EXPECT_EQ(quiet.last_fix().time, talking.last_fix().time);
    EXPECT_EQ(quiet.last_fix().position.latitude_deg, talking.last_fix().position.latitude_deg);
    EXPECT_EQ(quiet.last_fix().position.longitude_deg, talking.last_fix().position.longitude_deg);
    EXPECT_EQ(quiet.last_fix().valid, talking.last_fix().valid);
  }
  EXPECT_EQ(epochs, 11);
  EXPECT_EQ(quiet.epochs(), 11u);
}

TEST(GpsAgent, FixDescribesTheStateItCameFrom) {
  GpsAgent agent(config(), frame());
  const auto out = agent.on_state(state(12'340, 100.0, -50.0));
  ASSERT_TRUE(out);
  const auto s = parse_datagram(*out);
  ASSERT_FALSE(s.empty());
  const auto& rmc = s[0].fields;
  // start 12:00:00Z + 12.34 s of sim time
  EXPECT_EQ(rmc[0], "120012.340");
  const auto truth = frame().to_geodetic({100.0, -50.0, 1.5});
  const double lat = nmea_degrees(rmc[2], rmc[3], 2), lon = nmea_degrees(rmc[4], rmc[5], 3);
  const auto back = frame().to_enu({lat, lon, truth.altitude_m});
  EXPECT_NEAR(back.east, 100.0, 0.01);
  EXPECT_NEAR(back.north, -50.0, 0.01);
  EXPECT_NEAR(std::stod(rmc[6]) / kKnotsPerMps, 10.0, 0.001);
  EXPECT_NEAR(std::stod(rmc[7]), 0.0, 0.01);  // north
  EXPECT_NEAR(std::stod(s[2].fields[8]), truth.altitude_m, 0.001);
}

TEST(GpsAgent, CourseIsClockwiseFromNorth) {
  GpsAgent agent(config(), frame());
  auto st = state(0);
  st.velocity = {-5.0f, 0.0f, 0.0f};  // west
  const auto s = parse_datagram(*agent.on_state(st));
  EXPECT_NEAR(std::stod(s[0].fields[7]), 270.0, 0.01);
  st = state(100);
  st.velocity = {3.0f, -3.0f, 0.0f};  // south-east
  EXPECT_NEAR(std::stod(parse_datagram(*agent.on_state(st))[1].fields[0]), 135.0, 0.01);
  // Standing still keeps the last course instead of jumping to 0.
  st = state(200);
  st.velocity = {0.0f, 0.0f, 0.0f};
  EXPECT_NEAR(std::stod(parse_datagram(*agent.on_state(st))[0].fields[7]), 135.0, 0.01);
}

TEST(GpsAgent, ReversingReportsTheCourseOfMotionNotTheOrientation) {
  GpsAgent agent(config(), frame());
  auto st = state(0);
  st.yaw = static_cast<float>(std::numbers::pi / 2);  // nose north
  st.velocity = {0.0f, -3.0f, 0.0f};                  // rolling south, tail first
  const auto s = parse_datagram(*agent.on_state(st));
  EXPECT_NEAR(std::stod(s[0].fields[7]), 180.0, 0.01);
}

TEST(GpsAgent, ReportsTheAntennaPositionOnTheVehicle) {
  auto c = config();
  c.antenna.forward_m = -1.0;  // 1 m behind the centre, 0.5 m to the left
  c.antenna.left_m = 0.5;
  GpsAgent agent(c, frame());
  auto st = state(0, 100.0, -50.0);
  st.yaw = 0.0f;  // nose east: behind is west (-x), left is north (+y)
  const auto rmc = parse_datagram(*agent.on_state(st))[0].fields;
  const double lat = nmea_degrees(rmc[2], rmc[3], 2), lon = nmea_degrees(rmc[4], rmc[5], 3);
  const auto back = frame().to_enu({lat, lon, frame().to_geodetic({100.0, -50.0, 1.5}).altitude_m});
  EXPECT_NEAR(back.east, 99.0, 0.01);
  EXPECT_NEAR(back.north, -49.5, 0.01);
}

TEST(GpsAgent, NoiseHasTheConfiguredSpreadAndIsReproducible) {
  GpsAgent a(config(false), frame()), b(config(false), frame());
  double sum_e = 0, sum_e2 = 0, sum_u2 = 0;
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    a.on_state(state(i * 100, 0.0, 0.0));
    b.on_state(state(i * 100, 0.0, 0.0));
    ASSERT_EQ(a.last_fix().position.latitude_deg, b.last_fix().position.latitude_deg);
    const auto enu = frame().to_enu(a.last_fix().position);
    sum_e += enu.east;
    sum_e2 += enu.east * enu.east;
    sum_u2 += (enu.up - 1.5) * (enu.up - 1.5);
  }
  const double mean = sum_e / n;
  EXPECT_NEAR(mean, 0.0, 0.1);
  EXPECT_NEAR(std::sqrt(sum_e2 / n - mean * mean), 1.0, 0.05);
  EXPECT_NEAR(std::sqrt(sum_u2 / n), 2.0, 0.1);
  EXPECT_DOUBLE_EQ(a.last_fix().sigma_lat_m, 1.0);
  EXPECT_DOUBLE_EQ(a.last_fix().sigma_alt_m, 2.0);

  AgentConfig other = config(false);
  other.station_id = 1002;  // another station draws other numbers
  GpsAgent c(other, frame());
  c.on_state(state(0, 0.0, 0.0));
  GpsAgent d(config(false), frame());
  d.on_state(state(0, 0.0, 0.0));
  EXPECT_NE(c.last_fix().position.latitude_deg, d.last_fix().position.latitude_deg);
}

TEST(ErrorModel, BiasWalkGrowsLikeTheSquareRootOfTime) {
  // Many independent receivers; after 100 s a pure random walk of 0.1 m/√s has σ = 1 m.
  scenario::GnssErrors e;
  e.ideal = false;
  e.bias_walk_m = 0.1;
  double sum2 = 0;
  const int receivers = 1000;
  for (int r = 0; r < receivers; ++r) {
    ErrorModel model(e, mix_seed(1, static_cast<std::uint64_t>(r)));
    ErrorSample last;
    for (int i = 0; i <= 1000; ++i)
      last = model.sample(std::int64_t{i} * 100'000'000);
    sum2 += last.offset.north * last.offset.north;
    if (r == 0) {
      EXPECT_NEAR(last.sigma_north, 1.0, 1e-9);
    }
  }
  EXPECT_NEAR(std::sqrt(sum2 / receivers), 1.0, 0.07);
}

TEST(GpsAgent, FixLossWindowsDropTheFix) {
  AgentConfig c = config();
  c.errors.fix_loss = {{1.0, 1.5}};
  GpsAgent agent(c, frame());
  std::vector<std::string> status;
  for (std::int64_t ms = 800; ms <= 1700; ms += 100)
    status.push_back(parse_datagram(*agent.on_state(state(ms)))[0].fields[1]);
  EXPECT_EQ(status, (std::vector<std::string>{"A", "A", "V", "V", "V", "V", "V", "A", "A", "A"}));
}

TEST(GpsAgent, RejectsAZeroRate) {
  AgentConfig c = config();
  c.rate_hz = 0;
  EXPECT_THROW(GpsAgent(c, frame()), std::invalid_argument);
}

}  // namespace
}  // namespace tb::emu::gnss
