// The project's vehicle database: every signal round-trips, and frames match bytes worked out
// by hand from the DBC text (with the CRC computed by an independent bitwise implementation).

#include <array>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "common/can/checksum.hpp"
#include "common/can/dbc.hpp"

namespace tb::can {
namespace {

const Database& vehicle_db() {
  static const Database db = [] {
    auto r = Database::load(TESTBED_VEHICLE_DBC);
    if (!r)
      throw std::runtime_error(r.error().message());
    return *r;
  }();
  return db;
}

TEST(VehicleDbc, HasTheMessagesTheFeederNeeds) {
  const Database& db = vehicle_db();
  for (const char* name :
       {"VehicleSpeed", "WheelSpeeds", "Dynamics", "Steering", "Powertrain", "Lights"}) {
    const Message* m = db.find_message(name);
    ASSERT_NE(m, nullptr) << name;
    ASSERT_TRUE(m->cycle_time_ms.has_value()) << name;
    EXPECT_NE(m->find_signal("AliveCounter"), nullptr) << name;
    const Signal* crc = m->find_signal("Checksum");
    ASSERT_NE(crc, nullptr) << name;
    EXPECT_EQ(crc->start_bit, (m->dlc - 1) * 8) << name << ": checksum is the last byte";
    EXPECT_EQ(crc->length, 8u);
  }
  EXPECT_EQ(db.find_message("Dynamics")->cycle_time_ms, 10u);
  EXPECT_EQ(db.find_message("Lights")->cycle_time_ms, 100u);
}

TEST(VehicleDbc, EverySignalRoundTrips) {
  std::mt19937_64 rng(42);
  for (const Message& m : vehicle_db().messages) {
    for (const Signal& s : m.signals) {
      const double lo = s.minimum < s.maximum ? s.minimum : s.to_physical(s.raw_min());
      const double hi = s.minimum < s.maximum ? s.maximum : s.to_physical(s.raw_max());
      std::uniform_real_distribution<double> value(lo, hi);
      for (int i = 0; i < 200; ++i) {
        const double v = i == 0 ? lo : i == 1 ? hi : value(rng);
        std::array<std::uint8_t, 8> data{};
        data.fill(static_cast<std::uint8_t>(rng()));
        const auto before = data;
        s.encode(v, std::span(data).first(m.dlc));
        EXPECT_NEAR(s.decode(std::span(data).first(m.dlc)), v, std::abs(s.factor) / 2 + 1e-9)
            << m.name << "." << s.name;
        // Bits outside the signal are untouched.
        std::array<std::uint8_t, 8> mask{};
        for (unsigned p : s.bit_positions())
          mask[p / 8] |= static_cast<std::uint8_t>(1u << (p % 8));
        for (std::size_t b = 0; b < 8; ++b)
          EXPECT_EQ(data[b] & ~mask[b], before[b] & ~mask[b]) << m.name << "." << s.name;
      }
    }
  }
}

TEST(VehicleDbc, Crc8SaeJ1850CheckValue) {
  const std::string check = "123456789";
  EXPECT_EQ(crc8_sae_j1850({reinterpret_cast<const std::uint8_t*>(check.data()), check.size()}),
            0x4B);
}

std::array<std::uint8_t, 8> encode_all(const Message& m,
                                       std::initializer_list<std::pair<const char*, double>> v) {
  std::array<std::uint8_t, 8> data{};
  for (const auto& [name, value] : v) {
    const Signal* s = m.find_signal(name);
    EXPECT_NE(s, nullptr) << name;
    if (s)
      s->encode(value, std::span(data).first(m.dlc));
  }
  const Signal* crc = m.find_signal("Checksum");
  crc->encode(crc8_sae_j1850(std::span(data).first(m.dlc - 1)), std::span(data).first(m.dlc));
  return data;
}

TEST(VehicleDbc, WheelSpeedsFrameByHand) {
  // Motorola 12-bit signals, 0.1 km/h per bit:
  //   FL 123.4 → 1234 = 0x4D2: byte 0 = 0x4D, byte 1 bits 7..4 = 0x2
  //   FR   0.5 →    5 = 0x005: byte 1 bits 3..0 = 0x0, byte 2 = 0x05
  //   RL 409.5 → 4095 = 0xFFF: byte 3 = 0xFF, byte 4 bits 7..4 = 0xF
  //   RR   1.6 →   16 = 0x010: byte 4 bits 3..0 = 0x0, byte 5 = 0x10
  //   AliveCounter 3 → byte 6 = 0x03
  //   CRC-8 SAE J1850 over 4D 20 05 FF F0 10 03 = 0x78
  const auto data = encode_all(*vehicle_db().find_message("WheelSpeeds"), {{"WheelSpeedFL", 123.4},
                                                                           {"WheelSpeedFR", 0.5},
                                                                           {"WheelSpeedRL", 409.5},
                                                                           {"WheelSpeedRR", 1.6},
                                                                           {"AliveCounter", 3}});
  EXPECT_EQ(data, (std::array<std::uint8_t, 8>{0x4D, 0x20, 0x05, 0xFF, 0xF0, 0x10, 0x03, 0x78}));
}

TEST(VehicleDbc, DynamicsFrameByHand) {
  // YawRate -10 deg/s → -1000 = 0xFC18, Intel: 18 FC
  // LongitudinalAcceleration 2 m/s² → 2000 = 0x07D0, Intel: D0 07
  // LateralAcceleration -1.5 m/s² → -1500 = 0xFA24, Motorola from byte 4: FA 24
  // AliveCounter 15 → 0x0F; CRC over 18 FC D0 07 FA 24 0F = 0x60
  const auto data =
      encode_all(*vehicle_db().find_message("Dynamics"), {{"YawRate", -10.0},
                                                          {"LongitudinalAcceleration", 2.0},
                                                          {"LateralAcceleration", -1.5},
                                                          {"AliveCounter", 15}});
  EXPECT_EQ(data, (std::array<std::uint8_t, 8>{0x18, 0xFC, 0xD0, 0x07, 0xFA, 0x24, 0x0F, 0x60}));
}

TEST(VehicleDbc, VehicleSpeedFrameByHand) {
  // 50 km/h → 5000 = 0x1388: 88 13; forward = 1 in byte 2; counter 0; CRC = 0xCD
  const auto data = encode_all(*vehicle_db().find_message("VehicleSpeed"),
                               {{"VehicleSpeed", 50.0}, {"DrivingDirection", 1}});
  EXPECT_EQ(data, (std::array<std::uint8_t, 8>{0x88, 0x13, 0x01, 0, 0, 0, 0, 0xCD}));
}

}  // namespace
}  // namespace tb::can
