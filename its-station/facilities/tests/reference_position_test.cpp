#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <string>

#include "common/can/checksum.hpp"
#include "common/can/dbc.hpp"
#include "common/geodesy/local_frame.hpp"
#include "its-station/facilities/ca_service.hpp"
#include "its-station/facilities/can_vehicle_data.hpp"
#include "its-station/facilities/gpsd_report.hpp"
#include "its-station/facilities/reference_position.hpp"

namespace tb::its::facilities {
namespace {

using namespace std::chrono_literals;

const geodesy::LocalFrame& frame() {
  static const geodesy::LocalFrame f({48.0, 11.0, 500.0});
  return f;
}

/// What gpsd reports for an antenna at (east, north) moving at @p speed towards @p track.
GpsdReport tpv(double east, double north, double speed, double track) {
  const auto g = frame().to_geodetic({east, north, 0.0});
  GpsdReport r;
  r.mode = GpsdMode::k3D;
  r.time = clock::WallTime{std::chrono::seconds{1'700'000'000}};
  r.latitude_deg = g.latitude_deg;
  r.longitude_deg = g.longitude_deg;
  r.altitude_hae_m = g.altitude_m;
  r.speed_mps = speed;
  r.track_deg = track;
  r.hdop = 1.0;
  return r;
}

/// The VehicleSpeed frame as the CAN feeder encodes it (DrivingDirection 0 stand, 1 fwd, 2 rev).
can::CanFrame speed_frame(double kmh, int direction, int counter) {
  static const can::Database db = [] {
    auto d = can::Database::load(TESTBED_VEHICLE_DBC);
    if (!d)
      throw std::runtime_error(d.error().message());
    return *d;
  }();
  const auto* m = db.find_message("VehicleSpeed");
  can::CanFrame f;
  f.can_id = m->id;
  f.len = static_cast<std::uint8_t>(m->dlc);
  auto data = f.payload();
  m->find_signal("VehicleSpeed")->encode(kmh, data);
  m->find_signal("DrivingDirection")->encode(direction, data);
  m->find_signal("AliveCounter")->insert_raw(counter % 16, data);
  const auto* cs = m->find_signal("Checksum");
  std::vector<std::uint8_t> rest;
  for (unsigned i = 0; i < m->dlc; ++i)
    if (i != cs->start_bit / 8)
      rest.push_back(data[i]);
  cs->insert_raw(can::crc8_sae_j1850(rest), data);
  return f;
}

/// The station's chain below the CA service: gpsd reports through the FixAssembler, CAN frames
/// through the decoder, both into a ReferencePositionProvider.
struct Chain {
  explicit Chain(AntennaGeometry g) : reference(gnss, &vehicle, g) {
    static const can::Database db = [] {
      auto d = can::Database::load(TESTBED_VEHICLE_DBC);
      if (!d)
        throw std::runtime_error(d.error().message());
      return *d;
    }();
    auto d = CanVehicleDecoder::create(db);
    EXPECT_TRUE(d);
    decoder.emplace(std::move(*d));
    reference.on_fix([this](const PositionFix& f) { last = f; });
  }
  void can(double kmh, int direction) {
    ASSERT_EQ(decoder->apply(speed_frame(kmh, direction, counter++), clock::SteadyTime{1s}),
              CanFrameResult::kAccepted);
    vehicle.inject(decoder->state());
  }
  const PositionFix& gps(const GpsdReport& r) {
    PositionFix f;
    EXPECT_EQ(assembler.on_report(r, clock::SteadyTime{1s}, f), FixAssembler::Outcome::kFix);
    gnss.inject(f);
    EXPECT_TRUE(last);
    return *last;
  }
  geodesy::Enu where(const PositionFix& f) const {
    return frame().to_enu({f.latitude_deg, f.longitude_deg, 0.0});
  }

  FixAssembler assembler;
  InjectedPositionProvider gnss;
  InjectedVehicleDataProvider vehicle;
  std::optional<CanVehicleDecoder> decoder;
  ReferencePositionProvider reference;
  std::optional<PositionFix> last;
  int counter = 0;
};

TEST(OrientationFromCourse, ReversingTurnsTheCourseIntoTheOrientation) {
  Chain c({4.0, 0.0, 0.0});
  // Nose north, reversing at 3 m/s: the receiver's course is south, CAN says reverse.
  c.can(3.0 * 3.6, 2);
  const PositionFix& f = c.gps(tpv(0.0, 0.0, 3.0, 180.0));
  EXPECT_NEAR(*f.course_deg, 180.0, 1e-9);
  EXPECT_NEAR(*f.heading_deg, 0.0, 1e-9);
  ASSERT_TRUE(f.backward);
  EXPECT_TRUE(*f.backward);
  // The CAM says so: heading north (CDD 0.1°), driving backward.
  CaConfig cfg;
  const auto cam = build_cam(cfg, f, &*c.vehicle.current(), nullptr);
  const auto& hf = (*messages::vehicle_hf(cam.cam.camParameters));
  EXPECT_EQ(hf.heading.headingValue, 0);
  EXPECT_EQ(hf.driveDirection, messages::DriveDirection::backward);
  // The reference point (front centre) is 2 m north of the centre antenna, not 2 m south.
  EXPECT_NEAR(c.where(f).north, 2.0, 0.005);
  EXPECT_NEAR(c.where(f).east, 0.0, 0.005);
}

TEST(OrientationFromCourse, ForwardKeepsTheCourseAndAStopKeepsTheLastOrientation) {
  Chain c({4.0, 0.0, 0.0});
  c.can(36.0, 1);
  EXPECT_NEAR(*c.gps(tpv(0.0, 0.0, 10.0, 90.0)).heading_deg, 90.0, 1e-9);
  EXPECT_FALSE(*c.last->backward);
  // Stopped after reversing (nose west): gpsd's course is the held reverse course (east) or
  // nothing; the orientation stays west either way, also after the gear goes to neutral.
  c.can(5.0, 2);
  EXPECT_NEAR(*c.gps(tpv(0.0, 0.0, 1.5, 90.0)).heading_deg, 270.0, 1e-9);
  c.can(0.0, 0);
  EXPECT_NEAR(*c.gps(tpv(0.0, 0.0, 0.0, 90.0)).heading_deg, 270.0, 1e-9);
  EXPECT_NEAR(*c.gps(tpv(0.0, 0.0, 0.0, kNaN)).heading_deg, 270.0, 1e-9);
  // Standing in reverse gear says backward (the next motion's direction).
  c.can(0.0, 2);
  c.gps(tpv(0.0, 0.0, 0.0, kNaN));
  EXPECT_TRUE(*c.last->backward);
}

TEST(OrientationFromCourse, WheelSpeedSignBeatsTheGear) {
  VehicleData rolling_back;
  rolling_back.speed_mps = -1.0;  // rolling back on a slope in first gear
  rolling_back.reversing = false;
  EXPECT_EQ(OrientationFromCourse::moving_backward(&rolling_back), true);
  VehicleData standing_in_reverse;
  standing_in_reverse.speed_mps = 0.0;
  standing_in_reverse.reversing = true;
  EXPECT_EQ(OrientationFromCourse::moving_backward(&standing_in_reverse), true);
  EXPECT_EQ(OrientationFromCourse::moving_backward(nullptr), std::nullopt);
}

TEST(OrientationFromCourse, WithoutVehicleDataTheCourseIsTheOrientation) {
  InjectedPositionProvider gnss;
  ReferencePositionProvider reference(gnss, nullptr, {4.0, 0.0, 0.0});
  FixAssembler a;
  PositionFix f;
  ASSERT_EQ(a.on_report(tpv(0.0, 0.0, 3.0, 180.0), clock::SteadyTime{1s}, f),
            FixAssembler::Outcome::kFix);
  const PositionFix out = reference.convert(f);
  EXPECT_NEAR(*out.heading_deg, 180.0, 1e-9);
  EXPECT_FALSE(out.backward);
}

TEST(AntennaToReferencePoint, MovesAlongTheOrientationByTheLeverArm) {
  // Hand-worked: antenna 1 m behind the centre and 0.5 m left of it, car 4.6 m long. The front
  // centre is 2.3 + 1 = 3.3 m ahead of the antenna and 0.5 m to its right.
  const AntennaGeometry g{4.6, -1.0, 0.5};
  PositionFix at;
  const auto origin = frame().to_geodetic({100.0, 200.0, 0.0});
  at.latitude_deg = origin.latitude_deg;
  at.longitude_deg = origin.longitude_deg;
  at.altitude_m = origin.altitude_m;
  struct Case {
    double heading, east, north;
  };
  // heading 0 (north): ahead = +north, right = +east; 90 (east): ahead = +east, right = -north;
  // 225 (south-west): ahead = (-s, -s), right = (-s, +s) with s = 1/sqrt(2).
  const double s = std::sqrt(0.5);
  for (const Case c : {Case{0.0, 0.5, 3.3}, Case{90.0, 3.3, -0.5},
                       Case{225.0, -3.3 * s - 0.5 * s, -3.3 * s + 0.5 * s}}) {
    const PositionFix ref = antenna_to_reference_point(at, c.heading, g);
    const auto p = frame().to_enu({ref.latitude_deg, ref.longitude_deg, origin.altitude_m});
    EXPECT_NEAR(p.east - 100.0, c.east, 0.002) << "heading " << c.heading;
    EXPECT_NEAR(p.north - 200.0, c.north, 0.002) << "heading " << c.heading;
  }
  // A fix taken at the reference point already stays where it is.
  const PositionFix same = antenna_to_reference_point(at, 45.0, {4.0, 2.0, 0.0});
  EXPECT_DOUBLE_EQ(same.latitude_deg, at.latitude_deg);
  EXPECT_DOUBLE_EQ(same.longitude_deg, at.longitude_deg);
}

TEST(ReferencePositionProvider, PassesLossOn) {
  InjectedPositionProvider gnss;
  ReferencePositionProvider reference(gnss, nullptr, {});
  std::vector<bool> availability;
  reference.on_availability([&](bool a) { availability.push_back(a); });
  PositionFix f;
  f.course_deg = 10.0;
  f.speed_mps = 5.0;
  gnss.inject(f);
  gnss.lose_fix();
  EXPECT_EQ(availability, (std::vector<bool>{true, false}));
  EXPECT_FALSE(reference.current());
}

}  // namespace
}  // namespace tb::its::facilities
