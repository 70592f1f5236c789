// Processing cost of the facilities on the paths of the latency budget: a new fix → CAM bytes
// handed to the network (p3 in docs/tracing.md), and a received CAM → LDM.

#include <benchmark/benchmark.h>

#include <array>

#include "common/geodesy/local_frame.hpp"
#include "its-station/facilities/ca_service.hpp"
#include "its-station/facilities/cam_rules.hpp"

namespace {

using namespace std::chrono_literals;
namespace fac = tb::its::facilities;

class NullSender final : public fac::MessageSender {
 public:
  fac::SendResult send_single_hop(std::uint16_t, std::span<const std::uint8_t> p) override {
    last.assign(p.begin(), p.end());
    return fac::SendResult::kSent;
  }
  fac::SendResult send_geobroadcast(std::uint16_t, const fac::GeoArea&,
                                    std::span<const std::uint8_t>, std::uint32_t,
                                    std::uint8_t) override {
    return fac::SendResult::kSent;
  }
  std::vector<std::uint8_t> last;
};

const tb::geodesy::LocalFrame kFrame{{48.0, 11.0, 500.0}};

fac::PositionFix fix_at(tb::clock::ManualRuntime& rt, double east) {
  fac::PositionFix f;
  const auto g = kFrame.to_geodetic({east, 0.0, 0.0});
  f.time = rt.wall_now();
  f.received = rt.steady_now();
  f.latitude_deg = g.latitude_deg;
  f.longitude_deg = g.longitude_deg;
  f.altitude_m = 520.0;
  f.speed_mps = 50.0;
  f.heading_deg = 90.0;
  f.position_confidence = fac::PositionFix::Ellipse{2.0, 1.0, 0.0};
  f.speed_confidence_mps = 0.1;
  f.heading_confidence_deg = 0.5;
  return f;
}

void BM_CamRulesCheck(benchmark::State& state) {
  tb::clock::ManualRuntime rt;
  fac::CamRules rules({}, {});
  const auto f = fix_at(rt, 0.0);
  rules.generated(rt.steady_now(), f, fac::CamTrigger::kFirst);
  const auto g = fix_at(rt, 3.0);
  const auto t = rt.steady_now() + 200ms;
  for (auto _ : state)
    benchmark::DoNotOptimize(rules.check(t, g));
}
BENCHMARK(BM_CamRulesCheck);

/// A fix that triggers a CAM (5 m further each time, fixes 100 ms apart) through the whole CA
/// service: rules, CAM with vehicle data (and the LF container with path history every
/// 500 ms), UPER encoding, hand-over to the sender.
void BM_FixToCamBytes(benchmark::State& state) {
  tb::clock::ManualRuntime rt;
  fac::InjectedPositionProvider position;
  fac::InjectedVehicleDataProvider vehicle;
  NullSender sender;
  fac::Ldm ldm(rt);
  fac::CaConfig cfg;
  cfg.station_id = 1001;
  cfg.vehicle_length_m = 4.3;
  cfg.vehicle_width_m = 1.8;
  fac::CaService ca(rt, position, &vehicle, sender, ldm, cfg);
  vehicle.inject({.received = {},
                  .speed_mps = 50.0,
                  .yaw_rate_dps = 1.0,
                  .longitudinal_acceleration_mps2 = 0.5,
                  .lateral_acceleration_mps2 = 0.1,
                  .steering_wheel_angle_deg = 3.0,
                  .brake_pedal = false,
                  .gas_pedal = true,
                  .reversing = false,
                  .exterior_lights = fac::lights::kLowBeam,
                  .light_bar = std::nullopt,
                  .siren = std::nullopt});
  double x = 0.0;
  position.inject(fix_at(rt, x));
  ca.start();
  for (auto _ : state) {
    rt.advance(100ms);
    x += 5.0;
    position.inject(fix_at(rt, x));
  }
  state.counters["cams"] = static_cast<double>(ca.counters().sent);
  state.counters["bytes"] = static_cast<double>(sender.last.size());
}
BENCHMARK(BM_FixToCamBytes);

/// A received CAM: UPER decoding, checks, LDM update with history.
void BM_CamToLdm(benchmark::State& state) {
  tb::clock::ManualRuntime rt;
  fac::InjectedPositionProvider position;
  NullSender sender;
  fac::Ldm ldm(rt);
  fac::CaConfig cfg;
  cfg.station_id = 1001;
  fac::CaService tx(rt, position, nullptr, sender, ldm, cfg);
  position.inject(fix_at(rt, 0.0));
  tx.start();
  const auto bytes = sender.last;
  fac::Ldm rx_ldm(rt);
  cfg.station_id = 2002;
  fac::InjectedPositionProvider rx_position;
  fac::CaService rx(rt, rx_position, nullptr, sender, rx_ldm, cfg);
  for (auto _ : state)
    rx.receive(bytes, rt.wall_now());
  state.counters["neighbours"] = static_cast<double>(rx_ldm.neighbours().size());
}
BENCHMARK(BM_CamToLdm);

}  // namespace

BENCHMARK_MAIN();
