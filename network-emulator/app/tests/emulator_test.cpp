#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/clock/clock.hpp"
#include "common/geodesy/local_frame.hpp"
#include "common/map/scenario_map.hpp"
#include "common/scenario/loader.hpp"
#include "network-emulator/app/emulator.hpp"
#include "network-emulator/app/tests/test_scenario.hpp"

namespace tb::emu {
namespace {

struct Outbox {
  std::vector<std::string> nmea;
  std::vector<tb::can::CanFrame> frames;
  std::error_code fail_with;  // what the fake sockets answer
};

class FakeSink final : public DatagramSink {
 public:
  explicit FakeSink(Outbox& o) : o_(o) {}
  std::error_code send(std::span<const std::uint8_t> d) override {
    if (o_.fail_with)
      return o_.fail_with;
    o_.nmea.emplace_back(reinterpret_cast<const char*>(d.data()), d.size());
    return {};
  }

 private:
  Outbox& o_;
};

class FakeBus final : public tb::can::CanBus {
 public:
  explicit FakeBus(Outbox& o) : o_(o) {}
  std::string_view kind() const override { return "fake"; }
  std::error_code send(std::span<const tb::can::CanFrame> f) override {
    if (o_.fail_with)
      return o_.fail_with;
    o_.frames.insert(o_.frames.end(), f.begin(), f.end());
    return {};
  }
  void start_receive(FrameHandler) override {}

 private:
  Outbox& o_;
};

class EmulatorTest : public ::testing::Test {
 protected:
  EmulatorTest()
      : scenario_(scenario::parse(testing::kTwoStations, "two.json")),
        dbc_(*tb::can::Database::load(TESTBED_VEHICLE_DBC)) {}

  Emulator make(trace::Tracer& tracer) {
    return Emulator(
        scenario_, dbc_, default_stations(scenario_),
        [this](const StationEndpoints& e) {
          Outbox& o = out_[e.station_id];
          return StationIo{std::make_unique<FakeSink>(o), std::make_unique<FakeBus>(o)};
        },
        clock_, tracer);
  }

  static wire::VehicleState vehicle(std::uint32_t station, std::int64_t sim_ms) {
    wire::VehicleState s;
    s.station_id = station;
    s.tick = static_cast<std::uint64_t>(sim_ms / 10);
    s.sim_time_ns = sim_ms * 1'000'000;
    s.position = {10.0, -1.75, 0.0};
    s.velocity = {10.0f, 0.0f, 0.0f};
    s.speed = 10.0f;
    return s;
  }
  /// A batch datagram of one state.
  static std::vector<std::uint8_t> state(std::uint32_t station, std::int64_t sim_ms) {
    const auto s = vehicle(station, sim_ms);
    return wire::encode_batch({&s, 1});
  }

  scenario::Scenario scenario_;
  tb::can::Database dbc_;
  clock::ManualClock clock_;
  trace::Tracer no_trace_;
  std::map<std::uint32_t, Outbox> out_;
};

TEST_F(EmulatorTest, FeedsEachStationItsOwnGnssAndCan) {
  Emulator emu = make(no_trace_);
  EXPECT_EQ(emu.station_count(), 2u);
  for (std::int64_t ms = 0; ms < 1000; ms += 10) {
    emu.handle_datagram(state(1001, ms));
    if (ms < 500)
      emu.handle_datagram(state(1002, ms));
  }
  EXPECT_EQ(out_[1001].nmea.size(), 10u);
  EXPECT_EQ(out_[1002].nmea.size(), 5u);
  EXPECT_EQ(out_[1001].frames.size(), 100u * 5 + 10);  // 5 dynamics messages + Lights
  EXPECT_EQ(out_[1002].frames.size(), 50u * 5 + 5);
  EXPECT_EQ(out_[1001].nmea[3].substr(0, 17), "$GPRMC,120000.300");
  EXPECT_EQ(emu.counters().states, 150u);
  EXPECT_EQ(emu.counters().nmea_sent, 15u);
}

TEST_F(EmulatorTest, CountsAndDropsBadDatagramsAndUnknownStations) {
  Emulator emu = make(no_trace_);
  const std::uint8_t junk[] = {1, 2, 3};
  emu.handle_datagram(junk);
  emu.handle_datagram(junk);
  auto wrong_magic = state(1001, 0);
  wrong_magic[0] ^= 0xFF;
  emu.handle_datagram(wrong_magic);
  emu.handle_datagram(state(4242, 0));
  emu.handle_datagram(state(1001, 0));
  const Counters& c = emu.counters();
  EXPECT_EQ(c.datagrams, 5u);
  EXPECT_EQ(c.malformed, 3u);
  EXPECT_EQ(c.malformed_by_error[static_cast<std::size_t>(wire::DecodeError::kWrongSize)], 2u);
  EXPECT_EQ(c.unknown_station, 1u);
  EXPECT_EQ(c.states, 1u);
  const std::string line = emu.status_line();
  EXPECT_NE(line.find("malformed 3"), std::string::npos) << line;
  EXPECT_NE(line.find("unknown station 1"), std::string::npos) << line;
}

TEST_F(EmulatorTest, ABatchFeedsEveryStationOfItInOrder) {
  Emulator emu = make(no_trace_);
  for (std::int64_t ms = 0; ms < 1000; ms += 10) {
    const wire::VehicleState tick[] = {vehicle(1001, ms), vehicle(1002, ms), vehicle(4242, ms)};
    EXPECT_TRUE(emu.handle_datagram(wire::encode_batch(tick)));
  }
  EXPECT_EQ(out_[1001].nmea.size(), 10u);
  EXPECT_EQ(out_[1002].nmea.size(), 10u);
  EXPECT_EQ(out_[1001].frames.size(), 100u * 5 + 10);
  EXPECT_EQ(out_[1002].frames.size(), 100u * 5 + 10);
  EXPECT_EQ(emu.counters().datagrams, 100u);
  EXPECT_EQ(emu.counters().states, 200u);
  EXPECT_EQ(emu.counters().unknown_station, 100u);
}

TEST_F(EmulatorTest, RefusesTheOldSingleStateDatagramByItsVersion) {
  Emulator emu = make(no_trace_);
  EXPECT_FALSE(emu.handle_datagram(wire::encode(vehicle(1001, 0))));
  const Counters& c = emu.counters();
  EXPECT_EQ(c.malformed, 1u);
  EXPECT_EQ(c.malformed_by_error[static_cast<std::size_t>(wire::DecodeError::kSingleStateVersion)],
            1u);
  EXPECT_EQ(c.states, 0u);
  EXPECT_TRUE(out_[1001].nmea.empty());
  EXPECT_TRUE(out_[1001].frames.empty());
}

TEST_F(EmulatorTest, AStationThatIsGoneIsPausedWithoutStallingOthers) {
  Emulator emu = make(no_trace_);
  out_[1002].fail_with = std::make_error_code(std::errc::connection_refused);
  std::int64_t ms = 0;
  auto run_for = [&](std::int64_t duration_ms) {
    for (const std::int64_t end = ms + duration_ms; ms < end; ms += 10) {
      emu.handle_datagram(state(1001, ms));
      emu.handle_datagram(state(1002, ms));
      clock_.advance(std::chrono::milliseconds(10));
    }
  };
  run_for(500);
  EXPECT_EQ(emu.paused_stations(), 1u);
  EXPECT_EQ(emu.counters().nmea_failed, 1u);  // one failure, then paused
  EXPECT_EQ(emu.counters().nmea_skipped, 4u);
  EXPECT_EQ(out_[1001].nmea.size(), 5u);  // the healthy station got everything
  EXPECT_EQ(out_[1001].frames.size(), 50u * 5 + 5);

  out_[1002].fail_with = {};  // the receiver comes back
  run_for(1000);
  EXPECT_EQ(emu.paused_stations(), 0u);
  EXPECT_FALSE(out_[1002].nmea.empty());
  EXPECT_FALSE(out_[1002].frames.empty());
}

TEST_F(EmulatorTest, TracesStateNmeaAndCanWithStationAndTick) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("emu_trace_" + std::to_string(::getpid()) + ".jsonl");
  std::filesystem::remove(path);
  {
    trace::Tracer tracer(path.string(), "network-emulator");
    Emulator emu = make(tracer);
    emu.handle_datagram(state(1001, 1230));
    tracer.flush();
  }
  std::ifstream in(path);
  std::map<std::string, int> events;
  for (std::string line; std::getline(in, line);) {
    const auto j = nlohmann::json::parse(line);
    ++events[j["ev"].get<std::string>()];
    if (j["ev"] == "emu.world_start") {  // once: the scenario's pinned 2025-01-01T12:00:00Z
      EXPECT_EQ(j["world_start_ns"], 1735732800000000000LL);
      continue;
    }
    EXPECT_EQ(j["station"], 1001);
    EXPECT_EQ(j["tick"], 123);
    if (j["ev"] == "emu.nmea") {
      EXPECT_EQ(j["fix_ms"], 1735732800000LL + 1230);
    }
    if (j["ev"] == "emu.can") {
      EXPECT_EQ(j["frames"], 6);  // the five dynamics messages and Lights, in one datagram
    }
  }
  std::filesystem::remove(path);
  EXPECT_EQ(events["emu.state"], 1);
  EXPECT_EQ(events["emu.nmea"], 1);
  EXPECT_EQ(events["emu.can"], 1);
  EXPECT_EQ(events["emu.world_start"], 1);
}

// One clock for the whole world (docs/time.md): sim-server's start time, carried by the states,
// dates the fixes, whatever the scenario file pins.
TEST_F(EmulatorTest, DatesFixesFromTheWorldStartTheStatesCarry) {
  Emulator emu = make(no_trace_);
  const auto s = vehicle(1001, 300);
  // 2026-11-26T21:00:00Z
  emu.handle_datagram(wire::encode_batch({&s, 1}, 1'795'726'800'000'000'000));
  ASSERT_EQ(out_[1001].nmea.size(), 1u);
  EXPECT_EQ(out_[1001].nmea[0].substr(0, 17), "$GPRMC,210000.300");
  EXPECT_NE(out_[1001].nmea[0].find(",261126,"), std::string::npos) << out_[1001].nmea[0];
  // A later batch without one (a tool's) keeps the world's start.
  const auto t = vehicle(1001, 400);
  emu.handle_datagram(wire::encode_batch({&t, 1}));
  ASSERT_EQ(out_[1001].nmea.size(), 2u);
  EXPECT_EQ(out_[1001].nmea[1].substr(0, 17), "$GPRMC,210000.400");
}

TEST_F(EmulatorTest, WithoutAStartTimeAnywhereTheHostClockStandsIn) {
  scenario_.start_time.reset();
  clock_ = clock::ManualClock(clock::WallTime{std::chrono::seconds{1'795'726'800}});
  clock_.advance(std::chrono::milliseconds{700});
  Emulator emu = make(no_trace_);
  emu.handle_datagram(state(1001, 500));  // sim time 0.5 s: the world started at 21:00:00.200
  ASSERT_EQ(out_[1001].nmea.size(), 1u);
  EXPECT_EQ(out_[1001].nmea[0].substr(0, 17), "$GPRMC,210000.700");
}

}  // namespace
/// Degrees from an NMEA "ddmm.mmmmmm" field.
double nmea_degrees(const std::string& field, int degree_digits) {
  return std::stod(field.substr(0, static_cast<std::size_t>(degree_digits))) +
         std::stod(field.substr(static_cast<std::size_t>(degree_digits))) / 60.0;
}

std::vector<std::string> fields_of(const std::string& epoch, const std::string& sentence) {
  const auto at = epoch.find(sentence);
  const std::string line = epoch.substr(at, epoch.find('*', at) - at);
  std::vector<std::string> out;
  std::size_t b = 0;
  for (std::size_t e; (e = line.find(',', b)) != std::string::npos; b = e + 1)
    out.push_back(line.substr(b, e - b));
  out.push_back(line.substr(b));
  return out;
}

TEST(EmulatorOnAnOpenDriveMap, FixesComeFromTheGeoReferenceAndFollowTheRoadsElevation) {
  // A UTM map (zone 32, 2 degrees east of its central meridian): positions are the map's x, y,
  // z; fixes are what PROJ says they are, heights are the road's elevation, and the course is
  // from true north (grid north is 1.5 degrees off here).
  const std::string map =
      R"(<OpenDRIVE><header revMajor="1" revMinor="6"><geoReference><![CDATA[+proj=utm +zone=32 +ellps=WGS84 +units=m]]></geoReference></header>
<road id="1" length="300" junction="-1"><planView><geometry s="0" x="650000" y="5330000" hdg="1.5707963267948966" length="300"><line/></geometry></planView>
<elevationProfile><elevation s="0" a="520" b="0.05" c="0" d="0"/></elevationProfile>
<lanes><laneSection s="0"><center><lane id="0" type="none"/></center><right><lane id="-1" type="driving"><width sOffset="0" a="3.5" b="0" c="0" d="0"/></lane></right></laneSection></lanes></road></OpenDRIVE>)";
  const scenario::Scenario sc = scenario::parse(R"({
    "name": "utm", "map": {"type": "opendrive", "file": "utm.xodr"},
    "start_time": "2025-01-01T12:00:00Z",
    "vehicles": [{"id": "a", "station_id": 1001, "spawn": {"road": "1", "lane": -1, "s": 100}}]
  })",
                                                "utm.json", map);
  ASSERT_FALSE(sc.origin);  // the geoReference places the map
  const map::ScenarioMap m(sc);
  const auto dbc = *tb::can::Database::load(TESTBED_VEHICLE_DBC);
  clock::ManualClock clock;
  trace::Tracer no_trace;
  Outbox out;
  Emulator emu(
      sc, dbc, default_stations(sc),
      [&](const StationEndpoints&) {
        return StationIo{std::make_unique<FakeSink>(out), std::make_unique<FakeBus>(out)};
      },
      clock, no_trace);
  // Driving north along the road, 100 m up it: z = 520 + 0.05 * 100 (+ the car's ground point).
  wire::VehicleState s;
  s.station_id = 1001;
  s.position = {650001.75, 5330100.0, 525.0};
  s.velocity = {0.0f, 10.0f, 0.5f};
  s.yaw = static_cast<float>(std::numbers::pi / 2);
  s.speed = 10.0f;
  emu.handle_datagram(wire::encode_batch({&s, 1}));
  ASSERT_EQ(out.nmea.size(), 1u);
  const auto gga = fields_of(out.nmea[0], "$GPGGA");
  const geodesy::Geodetic want = m.to_wgs84(s.position[0], s.position[1], s.position[2]);
  EXPECT_NEAR(nmea_degrees(gga[2], 2), want.latitude_deg, 1e-7);  // 1e-6 minute printed
  EXPECT_NEAR(nmea_degrees(gga[4], 3), want.longitude_deg, 1e-7);
  EXPECT_NEAR(std::stod(gga[9]), 525.0, 1e-3);
  const auto rmc = fields_of(out.nmea[0], "$GPRMC");
  const double course = std::stod(rmc[8]);
  EXPECT_NEAR(course, m.georeferencing().heading_deg({s.position[0], s.position[1], 0}, s.yaw),
              0.01);
  EXPECT_GT(std::abs(geodesy::heading_difference_deg(course, 0.0)), 1.0);  // not grid north
}

}  // namespace tb::emu
