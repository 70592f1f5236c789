// An RSU as the emulator sees it (issue 34): a GNSS receiver standing at its site, fed at the
// scenario's rate from the vehicles' state stream; no CAN bus; its junction's signal feed.
// Graded against the map (the site's WGS84 through the map's frame) and the standard NMEA
// fields, with injected datagrams and fake sinks.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>

#include "common/map/rsu_site.hpp"
#include "common/scenario/loader.hpp"
#include "network-emulator/app/emulator.hpp"
#include "network-emulator/gnss/tests/nmea_parse.hpp"

namespace tb::emu {
namespace {

namespace fs = std::filesystem;
namespace sim = wire::sim;

fs::path root() {
  const char* r = std::getenv("TESTBED_ROOT");
  return r != nullptr ? fs::path(r) : fs::current_path();
}

const char* kScenario = R"({
  "name": "emu-rsu",
  "map": {"type": "opendrive", "file": "maps/four_way_junction.xodr"},
  "origin": {"lat": 48.137, "lon": 11.575, "alt": 520},
  "start_time": "2026-01-01T12:00:00Z",
  "rsus": [{"id": "rsu-100", "station_id": 5001, "junction": "100",
            "position": {"x": 14.0, "y": 14.0}, "height": 5.0}],
  "vehicles": [{"id": "a", "station_id": 1001, "spawn": {"road": "1", "lane": 1, "s": 55}}]
})";

struct Outbox {
  std::vector<std::string> nmea;
  std::vector<std::vector<std::uint8_t>> signals;
  std::vector<tb::can::CanFrame> frames;
};

class Capture final : public DatagramSink {
 public:
  explicit Capture(std::vector<std::string>& out) : text_(&out) {}
  explicit Capture(std::vector<std::vector<std::uint8_t>>& out) : bytes_(&out) {}
  std::error_code send(std::span<const std::uint8_t> d) override {
    if (text_)
      text_->emplace_back(reinterpret_cast<const char*>(d.data()), d.size());
    else
      bytes_->emplace_back(d.begin(), d.end());
    return {};
  }

 private:
  std::vector<std::string>* text_ = nullptr;
  std::vector<std::vector<std::uint8_t>>* bytes_ = nullptr;
};

class Bus final : public tb::can::CanBus {
 public:
  explicit Bus(Outbox& o) : o_(o) {}
  std::string_view kind() const override { return "fake"; }
  std::error_code send(std::span<const tb::can::CanFrame> f) override {
    o_.frames.insert(o_.frames.end(), f.begin(), f.end());
    return {};
  }
  void start_receive(FrameHandler) override {}

 private:
  Outbox& o_;
};

class RsuStationTest : public ::testing::Test {
 protected:
  RsuStationTest()
      : scenario_(scenario::parse(kScenario, (root() / "scenarios" / "emu-rsu.json").string())),
        dbc_(*tb::can::Database::load(TESTBED_VEHICLE_DBC)) {}

  std::unique_ptr<Emulator> make() {
    return std::make_unique<Emulator>(
        scenario_, dbc_, default_stations(scenario_),
        [this](const StationEndpoints& e) {
          Outbox& o = out_[e.station_id];
          rsu_flag_[e.station_id] = e.rsu;
          StationIo io;
          io.gnss = std::make_unique<Capture>(o.nmea);
          // As the program's factory: CAN for a vehicle, the signal feed for an RSU.
          if (e.rsu)
            io.signals = std::make_unique<Capture>(o.signals);
          else
            io.can = std::make_unique<Bus>(o);
          return io;
        },
        clock_, no_trace_);
  }

  static std::vector<std::uint8_t> state(std::uint32_t station, std::int64_t sim_ms, double x,
                                         double y) {
    wire::VehicleState s;
    s.station_id = station;
    s.tick = static_cast<std::uint64_t>(sim_ms / 10);
    s.sim_time_ns = sim_ms * 1'000'000;
    s.position = {x, y, 0.0};
    s.velocity = {10.0f, 0.0f, 0.0f};
    s.speed = 10.0f;
    return wire::encode_batch({&s, 1});
  }

  scenario::Scenario scenario_;
  tb::can::Database dbc_;
  clock::ManualClock clock_;
  trace::Tracer no_trace_;
  std::map<std::uint32_t, Outbox> out_;
  std::map<std::uint32_t, bool> rsu_flag_;
};

TEST_F(RsuStationTest, TheRsusReceiverReportsItsSiteStandingStillAtTheGnssRate) {
  auto emu = make();
  EXPECT_EQ(emu->station_count(), 2u);
  EXPECT_EQ(emu->rsu_count(), 1u);
  EXPECT_TRUE(rsu_flag_.at(5001));
  EXPECT_FALSE(rsu_flag_.at(1001));
  // One second of the vehicle's states at 100 Hz: the RSU's receiver makes 10 epochs, as the
  // vehicle's does (rates.gnss_hz 10).
  for (std::int64_t ms = 0; ms < 1000; ms += 10)
    emu->handle_datagram(state(1001, ms, 20.0 + ms / 100.0, 1.75));
  ASSERT_EQ(out_[5001].nmea.size(), 10u);
  EXPECT_EQ(out_[1001].nmea.size(), 10u);
  EXPECT_EQ(emu->counters().rsu_states, 100u);

  const map::ScenarioMap m(scenario_);
  const map::RsuSite site = map::rsu_sites(scenario_.rsus, m)[0];
  const geodesy::Geodetic truth = m.to_wgs84(14.0, 14.0, site.antenna_z);
  for (std::size_t k = 0; k < out_[5001].nmea.size(); ++k) {
    const auto s = gnss::testing::parse_datagram(out_[5001].nmea[k]);
    ASSERT_GE(s.size(), 3u);
    const auto& rmc = s[0].fields;
    // Epochs at whole 100 ms of sim time, dated start_time + sim time.
    EXPECT_EQ(rmc[0], fmt::format("1200{:02}.{}00", 0, k)) << k;
    EXPECT_EQ(rmc[1], "A");  // valid
    const double lat = gnss::testing::nmea_degrees(rmc[2], rmc[3], 2);
    const double lon = gnss::testing::nmea_degrees(rmc[4], rmc[5], 3);
    // 1e-7 degrees of latitude are 1.1 cm.
    EXPECT_NEAR(lat, truth.latitude_deg, 2e-7);
    EXPECT_NEAR(lon, truth.longitude_deg, 3e-7);
    EXPECT_NEAR(std::stod(rmc[6]), 0.0, 1e-9);  // speed over ground, knots
    const auto& gga = s[2].fields;
    EXPECT_EQ(gga[5], "1");  // GPS fix
    EXPECT_NEAR(std::stod(gga[8]), truth.altitude_m, 0.01);
  }
  // The antenna is 5 m above the ground at the junction's corner.
  EXPECT_NEAR(truth.altitude_m - m.to_wgs84(14.0, 14.0, site.ground_z).altitude_m, 5.0, 1e-6);
}

TEST_F(RsuStationTest, AnRsuHasNoCanFeed) {
  auto emu = make();
  for (std::int64_t ms = 0; ms < 500; ms += 10)
    emu->handle_datagram(state(1001, ms, 20.0, 1.75));
  EXPECT_TRUE(out_[5001].frames.empty());
  EXPECT_FALSE(out_[1001].frames.empty());
  EXPECT_EQ(emu->counters().can_failed, 0u);
}

TEST_F(RsuStationTest, StatesInTheStreamUnderTheRsusIdDoNotMoveIt) {
  auto emu = make();
  for (std::int64_t ms = 0; ms < 200; ms += 10) {
    emu->handle_datagram(state(5001, ms, 500.0, 500.0));
    emu->handle_datagram(state(1001, ms, 20.0, 1.75));
  }
  const map::ScenarioMap m(scenario_);
  const auto s = gnss::testing::parse_datagram(out_[5001].nmea.back());
  const double lat = gnss::testing::nmea_degrees(s[0].fields[2], s[0].fields[3], 2);
  EXPECT_NEAR(lat, m.to_wgs84(14.0, 14.0, 0.0).latitude_deg, 2e-7);
}

TEST_F(RsuStationTest, TheRsuGetsItsJunctionsSignalStates) {
  auto emu = make();
  const std::int64_t t = 1'767'268'800'000;
  const sim::SignalStates all{
      t,
      {{100, 1, sim::MovementPhaseState::kProtectedMovementAllowed, t + 3000, t + 3000},
       {100, 2, sim::MovementPhaseState::kStopAndRemain, t + 28000, t + 28000},
       {200, 1, sim::MovementPhaseState::kStopAndRemain, 0, 0}}};
  EXPECT_TRUE(emu->handle_signal_datagram(sim::encode(all)));
  EXPECT_FALSE(emu->handle_signal_datagram(sim::encode(all)));  // a second client's copy
  ASSERT_EQ(out_[5001].signals.size(), 1u);
  const auto got = wire::decode_signal_feed(out_[5001].signals[0]);
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->world_time_ms, t);
  ASSERT_EQ(got->groups.size(), 2u);
  EXPECT_EQ(got->groups[0], all.groups[0]);
  EXPECT_EQ(got->groups[1], all.groups[1]);
  EXPECT_EQ(emu->signal_counters().duplicates, 1u);
  const std::uint8_t junk[] = {0, 1, 2};
  EXPECT_FALSE(emu->handle_signal_datagram(junk));
  const std::string status = emu->status_line();
  EXPECT_NE(status.find("signals 3 (malformed 1, duplicates 1) to 1 RSUs: sent 1"),
            std::string::npos)
      << status;
}

TEST_F(RsuStationTest, StationsFilesNameRsusAndRefuseCanForThem) {
  const auto list = parse_stations(
      R"({"stations": [{"station_id": 1001, "address": "10.20.0.2"},
                       {"station_id": 5001, "address": "10.20.0.9", "signal_port": 4730,
                        "netns": "tb-rsu-100"}]})",
      "st.json", scenario_);
  ASSERT_EQ(list.size(), 2u);
  EXPECT_FALSE(list[0].rsu);
  EXPECT_TRUE(list[1].rsu);
  EXPECT_EQ(list[1].signal_port, 4730);
  EXPECT_EQ(parse_stations(R"({"stations": [{"station_id": 5001}]})", "st.json", scenario_)[0]
                .signal_port,
            wire::kRsuSignalPort);
  try {
    parse_stations(R"({"stations": [{"station_id": 5001, "can_port": 20001}]})", "st.json",
                   scenario_);
    ADD_FAILURE() << "accepted a CAN port for an RSU";
  } catch (const StationsConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("st.json: /stations/0/can_port: station 5001 is an RSU"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(parse_stations(R"({"stations": [{"station_id": 1001, "signal_port": 4720}]})",
                              "st.json", scenario_),
               StationsConfigError);
  EXPECT_THROW(parse_stations(R"({"stations": [{"station_id": 5002}]})", "st.json", scenario_),
               StationsConfigError);
  // One host: the RSU after the vehicles, its own GNSS port, signal port 4720.
  const auto d = default_stations(scenario_);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_TRUE(d[1].rsu);
  EXPECT_EQ(d[1].station_id, 5001u);
  EXPECT_EQ(d[1].gnss_port, 10111);
  EXPECT_EQ(d[1].signal_port, 4720);
}

}  // namespace
}  // namespace tb::emu
