#include <gtest/gtest.h>

#include <fstream>

#include <map>
#include <span>
#include <string>
#include <vector>

#include "common/can/checksum.hpp"
#include "common/can/dbc.hpp"
#include "its-station/facilities/can_vehicle_data.hpp"

namespace tb::its::facilities {
namespace {

const can::Database& database() {
  static const can::Database db = [] {
    auto d = can::Database::load(TESTBED_VEHICLE_DBC);
    if (!d)
      throw std::runtime_error(d.error().message());
    return *d;
  }();
  return db;
}

/// Encodes a frame of @p message as the CAN feeder does: signals, alive counter, CRC.
can::CanFrame frame(const std::string& message, const std::map<std::string, double>& values,
                    int counter, const can::Database& db = database()) {
  const auto* m = db.find_message(message);
  can::CanFrame f;
  f.can_id = m->id;
  f.len = static_cast<std::uint8_t>(m->dlc);
  auto data = f.payload();
  for (const auto& [name, v] : values)
    m->find_signal(name)->encode(v, data);
  m->find_signal("AliveCounter")->insert_raw(counter % 16, data);
  const auto* cs = m->find_signal("Checksum");
  std::vector<std::uint8_t> rest;
  for (unsigned i = 0; i < m->dlc; ++i)
    if (i != cs->start_bit / 8)
      rest.push_back(data[i]);
  cs->insert_raw(can::crc8_sae_j1850(rest), data);
  return f;
}

CanVehicleDecoder decoder() {
  auto d = CanVehicleDecoder::create(database());
  EXPECT_TRUE(d) << (d ? "" : d.error().detail);
  return std::move(*d);
}

TEST(CanVehicleDecoder, DecodesEverySignalTheCamNeeds) {
  auto d = decoder();
  const clock::SteadyTime t{std::chrono::seconds{3}};
  EXPECT_EQ(d.apply(frame("VehicleSpeed", {{"VehicleSpeed", 54.0}, {"DrivingDirection", 1}}, 0), t),
            CanFrameResult::kAccepted);
  EXPECT_EQ(d.apply(frame("Dynamics",
                          {{"YawRate", -3.5},
                           {"LongitudinalAcceleration", -2.25},
                           {"LateralAcceleration", 0.75}},
                          0),
                    t),
            CanFrameResult::kAccepted);
  EXPECT_EQ(d.apply(frame("Steering", {{"SteeringWheelAngle", 45.5}}, 0), t),
            CanFrameResult::kAccepted);
  EXPECT_EQ(d.apply(frame("Powertrain", {{"ThrottlePedal", 0.0}, {"BrakePedal", 40.0}}, 0), t),
            CanFrameResult::kAccepted);
  EXPECT_EQ(d.apply(frame("Lights", {{"LowBeam", 1}, {"IndicatorLeft", 1}, {"FogLight", 1}}, 0), t),
            CanFrameResult::kAccepted);
  const auto& s = d.state();
  EXPECT_EQ(s.received, t);
  EXPECT_NEAR(*s.speed_mps, 15.0, 1e-9);
  EXPECT_FALSE(*s.reversing);
  EXPECT_NEAR(*s.yaw_rate_dps, -3.5, 1e-9);
  EXPECT_NEAR(*s.longitudinal_acceleration_mps2, -2.25, 1e-9);
  EXPECT_NEAR(*s.lateral_acceleration_mps2, 0.75, 1e-9);
  EXPECT_NEAR(*s.steering_wheel_angle_deg, 45.5, 1e-9);
  EXPECT_TRUE(*s.brake_pedal);
  EXPECT_FALSE(*s.gas_pedal);
  EXPECT_EQ(*s.exterior_lights, lights::kLowBeam | lights::kLeftTurnSignal | lights::kFog);
}

TEST(CanVehicleDecoder, ReverseAndHazard) {
  auto d = decoder();
  d.apply(frame("VehicleSpeed", {{"VehicleSpeed", 7.2}, {"DrivingDirection", 2}}, 5), {});
  d.apply(frame("Lights", {{"HazardLights", 1}}, 5), {});
  EXPECT_NEAR(*d.state().speed_mps, -2.0, 1e-9);
  EXPECT_TRUE(*d.state().reversing);
  EXPECT_EQ(*d.state().exterior_lights, lights::kLeftTurnSignal | lights::kRightTurnSignal);
}

TEST(CanVehicleDecoder, LightBarAndSirenWhereTheDbcHasThem) {
  auto d = decoder();
  d.apply(frame("Lights", {{"LightBar", 1}, {"Siren", 0}, {"LowBeam", 1}}, 1), {});
  EXPECT_TRUE(*d.state().light_bar);
  EXPECT_FALSE(*d.state().siren);
  d.apply(frame("Lights", {{"Siren", 1}}, 2), {});
  EXPECT_FALSE(*d.state().light_bar);
  EXPECT_TRUE(*d.state().siren);

  // A DBC of a car without them (vehicle.dbc less the two signals): decoded, and unknown.
  std::ifstream in(TESTBED_VEHICLE_DBC);
  std::string text, line;
  while (std::getline(in, line))
    if (line.find("LightBar") == std::string::npos && line.find("Siren") == std::string::npos)
      text += line + "\n";
  auto db = can::Database::parse(text, "no-light-bar.dbc");
  ASSERT_TRUE(db) << db.error().message();
  auto plain = CanVehicleDecoder::create(*db);
  ASSERT_TRUE(plain);
  EXPECT_EQ(plain->apply(frame("Lights", {{"LowBeam", 1}}, 3, *db), {}), CanFrameResult::kAccepted);
  EXPECT_EQ(*plain->state().exterior_lights, lights::kLowBeam);
  EXPECT_FALSE(plain->state().light_bar);
  EXPECT_FALSE(plain->state().siren);
}

TEST(CanVehicleDecoder, BadChecksumIsCountedAndDropped) {
  auto d = decoder();
  auto f = frame("VehicleSpeed", {{"VehicleSpeed", 50.0}}, 1);
  f.data[0] ^= 0x01;  // a bit flipped on the wire
  EXPECT_EQ(d.apply(f, {}), CanFrameResult::kBadChecksum);
  EXPECT_FALSE(d.state().speed_mps);
  EXPECT_EQ(d.counters().bad_checksum, 1u);
}

TEST(CanVehicleDecoder, AliveCounterChecks) {
  auto d = decoder();
  auto speed = [](double kmh, int c) { return frame("VehicleSpeed", {{"VehicleSpeed", kmh}}, c); };
  EXPECT_EQ(d.apply(speed(10, 14), {}), CanFrameResult::kAccepted);
  EXPECT_EQ(d.apply(speed(11, 15), {}), CanFrameResult::kAccepted);
  EXPECT_EQ(d.apply(speed(12, 0), {}), CanFrameResult::kAccepted);  // wraps mod 16
  EXPECT_EQ(d.apply(speed(99, 0), {}), CanFrameResult::kRepeatedCounter);
  EXPECT_NEAR(*d.state().speed_mps, 12 / 3.6, 1e-9);
  EXPECT_EQ(d.apply(speed(13, 3), {}), CanFrameResult::kAccepted);  // two frames lost
  EXPECT_EQ(d.counters().lost, 2u);
  EXPECT_EQ(d.apply(speed(14, 10), {}), CanFrameResult::kCounterJump);
  EXPECT_NEAR(*d.state().speed_mps, 13 / 3.6, 1e-9);
  EXPECT_EQ(d.apply(speed(15, 11), {}), CanFrameResult::kAccepted);  // resynchronised
  EXPECT_EQ(d.counters().bad_counter, 2u);
  // Counters are per message: another message starts its own sequence.
  EXPECT_EQ(d.apply(frame("Steering", {{"SteeringWheelAngle", 1}}, 11), {}),
            CanFrameResult::kAccepted);
}

TEST(CanVehicleDecoder, WrongLengthAndUnknownIds) {
  auto d = decoder();
  auto f = frame("Dynamics", {{"YawRate", 1}}, 0);
  f.len = 7;
  EXPECT_EQ(d.apply(f, {}), CanFrameResult::kWrongLength);
  can::CanFrame other;
  other.can_id = 0x7ff;
  other.len = 8;
  EXPECT_EQ(d.apply(other, {}), CanFrameResult::kUnknownId);
  EXPECT_EQ(d.counters().bad_length, 1u);
  EXPECT_EQ(d.counters().unknown, 1u);
  EXPECT_EQ(d.counters().accepted, 0u);
}

TEST(CanVehicleDecoder, MissingSignalsInTheDbcAreNamed) {
  auto db = can::Database::parse(
      "BO_ 256 VehicleSpeed: 8 EMULATOR\n"
      " SG_ VehicleSpeed : 0|16@1+ (0.01,0) [0|655.35] \"km/h\" STATION\n",
      "small.dbc");
  ASSERT_TRUE(db) << db.error().message();
  auto d = CanVehicleDecoder::create(*db);
  ASSERT_FALSE(d);
  EXPECT_NE(d.error().detail.find("VehicleSpeed"), std::string::npos) << d.error().detail;
}

/// A bus whose frames wait until poll(), as a socket read on demand; or, with push set, one
/// that can only deliver at arrival (the CanBus default).
class QueueBus final : public can::CanBus {
 public:
  explicit QueueBus(bool push = false) : push_(push) {}
  std::string_view kind() const override { return "test"; }
  std::error_code send(std::span<const can::CanFrame>) override { return {}; }
  void start_receive(FrameHandler handler) override { handler_ = std::move(handler); }
  void start_on_demand(FrameHandler handler, std::chrono::milliseconds backstop) override {
    if (push_) {
      CanBus::start_on_demand(std::move(handler), backstop);
      return;
    }
    handler_ = std::move(handler);
    backstop_ = backstop;
  }
  std::size_t poll() override {
    ++polls;
    const std::size_t n = queued_.size();
    for (const auto& f : queued_)
      handler_(f, 0);
    queued_.clear();
    return n;
  }
  /// A frame arrives: queued, or handed over at once on a push bus.
  void arrive(const can::CanFrame& f) {
    if (push_)
      handler_(f, 0);
    else
      queued_.push_back(f);
  }
  std::chrono::milliseconds backstop_{};
  int polls = 0;

 private:
  bool push_;
  FrameHandler handler_;
  std::vector<can::CanFrame> queued_;
};

can::CanFrame speed_frame(double kmh, int counter) {
  return frame("VehicleSpeed", {{"VehicleSpeed", kmh}, {"DrivingDirection", 1}}, counter);
}

TEST(CanVehicleDataProvider, ReadsTheBusWhenAskedNotAtEachFrame) {
  QueueBus bus;
  clock::ManualClock clock;
  CanVehicleDataProvider provider(bus, decoder(), clock);
  int updates = 0;
  provider.on_update([&](const VehicleData&) { ++updates; });
  provider.start();
  EXPECT_EQ(bus.backstop_, CanVehicleDataProvider::kBackstop);
  bus.arrive(speed_frame(36.0, 0));
  bus.arrive(speed_frame(54.0, 1));
  EXPECT_EQ(updates, 0) << "a frame is taken in when asked for, not at arrival";
  const auto& now = provider.current();
  ASSERT_TRUE(now && now->speed_mps);
  EXPECT_NEAR(*now->speed_mps, 15.0, 0.01) << "the newest frame";
  EXPECT_EQ(updates, 2);
  EXPECT_EQ(provider.polls(), 1u);
  EXPECT_EQ(provider.decoder().counters().lost, 0u) << "queued frames are not lost frames";
}

TEST(CanVehicleDataProvider, ReadsAtMostOncePerPollInterval) {
  QueueBus bus;
  clock::ManualClock clock;
  CanVehicleDataProvider provider(bus, decoder(), clock);
  provider.start();
  bus.arrive(speed_frame(36.0, 0));
  ASSERT_TRUE(provider.current());
  bus.arrive(speed_frame(72.0, 1));
  clock.advance(CanVehicleDataProvider::kPollInterval / 2);
  EXPECT_NEAR(*provider.current()->speed_mps, 10.0, 0.01) << "asked again within the interval";
  EXPECT_EQ(bus.polls, 1);
  clock.advance(CanVehicleDataProvider::kPollInterval / 2);
  EXPECT_NEAR(*provider.current()->speed_mps, 20.0, 0.01);
  EXPECT_EQ(bus.polls, 2);
}

TEST(CanVehicleDataProvider, AListenerAskingForCurrentDoesNotReadAgain) {
  QueueBus bus;
  clock::ManualClock clock;
  CanVehicleDataProvider provider(bus, decoder(), clock);
  std::vector<double> seen;
  provider.on_update([&](const VehicleData&) {
    clock.advance(CanVehicleDataProvider::kPollInterval);
    seen.push_back(*provider.current()->speed_mps);
  });
  provider.start();
  bus.arrive(speed_frame(36.0, 0));
  bus.arrive(speed_frame(72.0, 1));
  ASSERT_TRUE(provider.current());
  EXPECT_EQ(bus.polls, 1);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_NEAR(seen[0], 10.0, 0.01);
  EXPECT_NEAR(seen[1], 20.0, 0.01);
}

TEST(CanVehicleDataProvider, ABusThatDeliversAtArrivalStillWorks) {
  QueueBus bus(/*push=*/true);
  clock::ManualClock clock;
  CanVehicleDataProvider provider(bus, decoder(), clock);
  int updates = 0;
  provider.on_update([&](const VehicleData&) { ++updates; });
  provider.start();
  bus.arrive(speed_frame(36.0, 0));
  EXPECT_EQ(updates, 1);
  EXPECT_NEAR(*provider.current()->speed_mps, 10.0, 0.01);
}

}  // namespace
}  // namespace tb::its::facilities
