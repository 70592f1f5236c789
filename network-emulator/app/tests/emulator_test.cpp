#include <cstdio>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "common/clock/clock.hpp"
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
}

}  // namespace
}  // namespace tb::emu
