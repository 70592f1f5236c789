#include <cmath>
#include <limits>
#include <map>
#include <random>

#include <gtest/gtest.h>

#include "common/can/checksum.hpp"
#include "network-emulator/can/can_feeder.hpp"

namespace tb::emu::can {
namespace {

using tb::can::CanFrame;
using tb::can::Database;

const Database& db() {
  static const Database d = [] {
    auto r = Database::load(TESTBED_VEHICLE_DBC);
    if (!r)
      throw std::runtime_error(r.error().message());
    return *r;
  }();
  return d;
}

CanFeeder feeder(FeederConfig c = {}) {
  auto f = CanFeeder::create(db(), c);
  if (!f)
    throw std::runtime_error(f.error().message());
  return std::move(*f);
}

wire::VehicleState state(std::int64_t sim_ms) {
  wire::VehicleState s;
  s.sim_time_ns = sim_ms * 1'000'000;
  s.speed = 50.0f / 3.6f;
  s.wheel_speeds = {13.0f, 14.0f, 13.5f, 13.6f};
  s.yaw_rate = 0.1f;  // rad/s, to the left
  s.acceleration = {1.5f, -0.8f, 0.0f};
  s.steering_angle = 0.05f;  // rad at the road wheels
  s.controls.throttle = 0.42f;
  s.controls.brake = 0.0f;
  s.gear = 3;
  s.engine_rpm = 2500.0f;
  s.lights = wire::kLowBeam | wire::kIndicatorLeft | wire::kLightBar;
  return s;
}

double value(const CanFrame& f, const char* message, const char* signal) {
  const auto* m = db().find_message(message);
  return m->find_signal(signal)->decode(f.payload());
}

/// The feeder's precomputed plan against the codec it was made from: every raw value and
/// every byte the same, for the vehicle database's signals and for awkward ones of both byte
/// orders (unaligned, signed, 64 bits, running past the end of the frame).
TEST(SignalPlan, EncodesExactlyAsTheCodec) {
  std::vector<std::pair<tb::can::Signal, std::size_t>> signals;  // signal, DLC
  for (const auto& m : db().messages)
    for (const auto& sig : m.signals)
      signals.emplace_back(sig, m.dlc);
  auto make = [](unsigned start, unsigned length, tb::can::ByteOrder order, bool is_signed,
                 double factor, double offset, double lo, double hi) {
    tb::can::Signal s;
    s.name = "X";
    s.start_bit = start;
    s.length = length;
    s.byte_order = order;
    s.is_signed = is_signed;
    s.factor = factor;
    s.offset = offset;
    s.minimum = lo;
    s.maximum = hi;
    return s;
  };
  using tb::can::ByteOrder;
  signals.emplace_back(make(3, 13, ByteOrder::kIntel, true, 0.5, -10, -100, 100), 8);
  signals.emplace_back(make(7, 12, ByteOrder::kMotorola, false, 0.1, 0, 0, 0), 8);
  signals.emplace_back(make(13, 20, ByteOrder::kMotorola, true, 0.01, 5, 0, 0), 8);
  signals.emplace_back(make(0, 64, ByteOrder::kIntel, true, 1, 0, 0, 0), 8);
  signals.emplace_back(make(60, 8, ByteOrder::kIntel, false, 1, 0, 0, 0), 8);  // 4 bits fit
  signals.emplace_back(make(1, 1, ByteOrder::kMotorola, false, 1, 0, 0, 0), 1);
  signals.emplace_back(make(30, 17, ByteOrder::kIntel, false, 0.25, 0, 0, 0), 12);  // FD
  std::mt19937_64 rng(7);
  for (const auto& [sig, dlc] : signals) {
    const SignalPlan plan(sig, dlc);
    const double span =
        std::max({1.0, std::abs(sig.maximum), std::abs(sig.minimum),
                  std::ldexp(std::abs(sig.factor), static_cast<int>(std::min(sig.length, 60u)))});
    std::uniform_real_distribution<double> physical(-1.5 * span, 1.5 * span);
    std::vector<double> values{0.0,
                               sig.minimum,
                               sig.maximum,
                               std::numeric_limits<double>::quiet_NaN(),
                               std::numeric_limits<double>::infinity(),
                               -std::numeric_limits<double>::infinity()};
    for (int i = 0; i < 2000; ++i)
      values.push_back(physical(rng));
    for (const double v : values) {
      ASSERT_EQ(plan.to_raw(v), sig.to_raw(v)) << sig.name << " " << v;
      // Over random bytes, so that clearing the signal's old bits is checked too.
      std::vector<std::uint8_t> want(dlc), got(dlc);
      for (auto& b : want)
        b = static_cast<std::uint8_t>(rng());
      got = want;
      sig.encode(v, want);
      plan.encode(v, got);
      ASSERT_EQ(got, want) << sig.name << " " << v;
    }
    EXPECT_EQ(plan.raw_max(), sig.raw_max());
  }
}

TEST(CanFeeder, SiblingsShareEncodingsButNotCountersOrDueTimes) {
  CanFeeder a = feeder();
  CanFeeder b = a.sibling({.steering_ratio = 2 * FeederConfig{}.steering_ratio});
  for (int i = 0; i < 3; ++i)
    a.on_state(state(10 * i));
  // b starts fresh: everything due at once, counters at 0, steering angle from its own ratio.
  const auto from_b_span = b.on_state(state(30));
  const std::vector<CanFrame> from_b(from_b_span.begin(), from_b_span.end());
  const auto from_a = a.on_state(state(30));
  ASSERT_EQ(from_b.size(), 6u);
  ASSERT_EQ(from_a.size(), 5u);  // dynamics only: Lights is due again at 100 ms
  for (const CanFrame& f : from_b) {
    const std::string name = db().find_message(f.id())->name;
    EXPECT_EQ(value(f, name.c_str(), "AliveCounter"), 0.0) << name;
    for (const CanFrame& g : from_a) {
      if (g.id() != f.id())
        continue;
      EXPECT_EQ(value(g, name.c_str(), "AliveCounter"), 3.0) << name;
      if (name == "Steering") {
        EXPECT_NEAR(value(f, "Steering", "SteeringWheelAngle"),
                    2 * value(g, "Steering", "SteeringWheelAngle"), 0.2);
      }
    }
  }
  EXPECT_THROW(a.sibling({.dynamics_hz = 50}), std::invalid_argument);
}

TEST(CanFeeder, EverySignalOfTheVehicleDatabaseHasASource) {
  auto f = CanFeeder::create(db(), {});
  ASSERT_TRUE(f.has_value()) << f.error().message();
}

TEST(CanFeeder, SendsEachMessageAtItsRate) {
  CanFeeder f = feeder();
  std::map<std::uint32_t, int> count;
  for (std::int64_t ms = 0; ms < 1000; ms += 10)
    for (const CanFrame& fr : f.on_state(state(ms)))
      ++count[fr.id()];
  EXPECT_EQ(count[256], 100);  // VehicleSpeed, 10 ms
  EXPECT_EQ(count[288], 100);  // Dynamics
  EXPECT_EQ(count[512], 10);   // Lights, 100 ms
  EXPECT_EQ(count.size(), 6u);

  // The scenario's rates replace the DBC's cycle times per group.
  CanFeeder slow = feeder({.dynamics_hz = 50.0, .body_hz = 5.0, .steering_ratio = 14.8});
  EXPECT_EQ(slow.period_ns("Dynamics"), 20'000'000);
  EXPECT_EQ(slow.period_ns("Lights"), 200'000'000);
  count.clear();
  for (std::int64_t ms = 0; ms < 1000; ms += 10)
    for (const CanFrame& fr : slow.on_state(state(ms)))
      ++count[fr.id()];
  EXPECT_EQ(count[288], 50);
  EXPECT_EQ(count[512], 5);
}

TEST(CanFeeder, FramesCarryTheStatesValues) {
  CanFeeder f = feeder();
  std::map<std::string, CanFrame> by_name;
  for (const CanFrame& fr : f.on_state(state(0)))
    by_name[db().find_message(fr.id())->name] = fr;
  ASSERT_EQ(by_name.size(), 6u);
  EXPECT_NEAR(value(by_name["VehicleSpeed"], "VehicleSpeed", "VehicleSpeed"), 50.0, 0.005);
  EXPECT_EQ(value(by_name["VehicleSpeed"], "VehicleSpeed", "DrivingDirection"), 1.0);
  EXPECT_NEAR(value(by_name["WheelSpeeds"], "WheelSpeeds", "WheelSpeedFR"), 14.0 * 3.6, 0.05);
  EXPECT_NEAR(value(by_name["Dynamics"], "Dynamics", "YawRate"), 5.73, 0.005);  // 0.1 rad/s
  EXPECT_NEAR(value(by_name["Dynamics"], "Dynamics", "LateralAcceleration"), -0.8, 0.0005);
  EXPECT_NEAR(value(by_name["Steering"], "Steering", "SteeringWheelAngle"), 42.4,
              0.05);  // 0.05·14.8 rad
  EXPECT_NEAR(value(by_name["Powertrain"], "Powertrain", "ThrottlePedal"), 42.0, 0.2);
  EXPECT_EQ(value(by_name["Powertrain"], "Powertrain", "Gear"), 3.0);
  EXPECT_EQ(value(by_name["Powertrain"], "Powertrain", "EngineSpeed"), 2500.0);
  EXPECT_EQ(value(by_name["Lights"], "Lights", "IndicatorLeft"), 1.0);
  EXPECT_EQ(value(by_name["Lights"], "Lights", "IndicatorRight"), 0.0);
  EXPECT_EQ(value(by_name["Lights"], "Lights", "LowBeam"), 1.0);
  EXPECT_EQ(value(by_name["Lights"], "Lights", "BrakeLights"), 0.0);
  EXPECT_EQ(value(by_name["Lights"], "Lights", "LightBar"), 1.0);
  EXPECT_EQ(value(by_name["Lights"], "Lights", "Siren"), 0.0);
  EXPECT_EQ(by_name["Steering"].len, 4);
  EXPECT_EQ(by_name["Lights"].len, 3);
}

TEST(CanFeeder, VehicleSpeedFrameMatchesHandComputedBytes) {
  // 50 km/h forward, first frame (alive counter 0): see common/can/tests/vehicle_dbc_test.cpp
  // for the working: 88 13 01 00 00 00 00, CRC-8 SAE J1850 = 0xCD.
  CanFeeder f = feeder();
  const auto frames = f.on_state(state(0));
  ASSERT_EQ(frames[0].id(), 256u);
  EXPECT_EQ(std::vector<std::uint8_t>(frames[0].payload().begin(), frames[0].payload().end()),
            (std::vector<std::uint8_t>{0x88, 0x13, 0x01, 0x00, 0x00, 0x00, 0x00, 0xCD}));
}

TEST(CanFeeder, AliveCounterWrapsAndChecksumsVerify) {
  CanFeeder f = feeder();
  std::vector<int> counters;
  for (std::int64_t ms = 0; ms < 200; ms += 10) {
    for (const CanFrame& fr : f.on_state(state(ms))) {
      const auto bytes = fr.payload();
      EXPECT_EQ(bytes.back(), tb::can::crc8_sae_j1850(bytes.first(bytes.size() - 1))) << fr.id();
      if (fr.id() == 288)
        counters.push_back(static_cast<int>(value(fr, "Dynamics", "AliveCounter")));
    }
  }
  ASSERT_EQ(counters.size(), 20u);
  for (std::size_t i = 0; i < counters.size(); ++i)
    EXPECT_EQ(counters[i], static_cast<int>(i % 16));
}

TEST(CanFeeder, ReverseAndHazards) {
  CanFeeder f = feeder();
  auto s = state(0);
  s.speed = -2.0f;
  s.gear = -1;
  s.lights = wire::kHazard | wire::kReverseLight | wire::kBrakeLights;
  for (const CanFrame& fr : f.on_state(s)) {
    if (fr.id() == 256) {
      EXPECT_NEAR(value(fr, "VehicleSpeed", "VehicleSpeed"), 7.2, 0.005);
      EXPECT_EQ(value(fr, "VehicleSpeed", "DrivingDirection"), 2.0);
    } else if (fr.id() == 320) {
      EXPECT_EQ(value(fr, "Powertrain", "Gear"), -1.0);
    } else if (fr.id() == 512) {
      EXPECT_EQ(value(fr, "Lights", "IndicatorLeft"), 1.0);
      EXPECT_EQ(value(fr, "Lights", "IndicatorRight"), 1.0);
      EXPECT_EQ(value(fr, "Lights", "HazardLights"), 1.0);
      EXPECT_EQ(value(fr, "Lights", "ReverseLight"), 1.0);
      EXPECT_EQ(value(fr, "Lights", "BrakeLights"), 1.0);
    }
  }
}

TEST(CanFeeder, RejectsDatabasesItCannotFill) {
  auto unknown = Database::parse(
      "BO_ 1 M: 8 X\n SG_ Mystery : 0|8@1+ (1,0) [0|0] \"\" X\nBA_ \"GenMsgCycleTime\" BO_ 1 10;\n",
      "u.dbc");
  ASSERT_TRUE(unknown.has_value());
  auto f = CanFeeder::create(*unknown, {});
  ASSERT_FALSE(f.has_value());
  EXPECT_EQ(f.error().code, FeederErrc::kUnknownSignal);
  EXPECT_NE(f.error().message().find("Mystery"), std::string::npos);

  auto no_cycle = Database::parse("BO_ 1 M: 8 X\n SG_ Gear : 0|8@1- (1,0) [0|0] \"\" X\n", "n.dbc");
  ASSERT_TRUE(no_cycle.has_value());
  EXPECT_EQ(CanFeeder::create(*no_cycle, {}).error().code, FeederErrc::kNoCycleTime);

  auto bad_crc = Database::parse(
      "BO_ 1 M: 8 X\n SG_ Checksum : 4|8@1+ (1,0) [0|0] \"\" X\nBA_ \"GenMsgCycleTime\" BO_ 1 "
      "10;\n",
      "c.dbc");
  ASSERT_TRUE(bad_crc.has_value());
  EXPECT_EQ(CanFeeder::create(*bad_crc, {}).error().code, FeederErrc::kBadChecksumSignal);
  EXPECT_EQ(CanFeeder::create(db(), {.dynamics_hz = 0}).error().code, FeederErrc::kBadRate);
}

}  // namespace
}  // namespace tb::emu::can
