// A station's receive path per CAM, as at 49 neighbours: a frame from the link through the GN
// router (parse, checks, location table), BTP dispatch to the CAM port, UPER decoding, the CA
// service's checks and the LDM update with its history. What a full station spends per
// received CAM besides the wake-up that brought it, the MQTT mirror and LCRW (issue 33,
// docs/latency.md); steadier before/after figures than whole-testbed runs on a busy machine.

#include <benchmark/benchmark.h>

#include <vector>

#include "common/geodesy/local_frame.hpp"
#include "its-station/btp/dispatcher.hpp"
#include "its-station/facilities/ca_service.hpp"
#include "its-station/geonet/tests/router_fixture.hpp"
#include "its-station/link/test_link.hpp"

namespace {

using namespace std::chrono_literals;
namespace fac = tb::its::facilities;
namespace gn = tb::its::geonet;
namespace link = tb::its::link;

constexpr int kNeighbours = 49;

class CapturingSender final : public fac::MessageSender {
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

const tb::geodesy::LocalFrame kFrame{{gn::testing::kOriginLat, gn::testing::kOriginLon, 0.0}};

fac::PositionFix fix_at(tb::clock::ManualRuntime& rt, double east, double north) {
  fac::PositionFix f;
  const auto g = kFrame.to_geodetic({east, north, 0.0});
  f.time = rt.wall_now();
  f.received = rt.steady_now();
  f.latitude_deg = g.latitude_deg;
  f.longitude_deg = g.longitude_deg;
  f.altitude_m = 20.0;
  f.speed_mps = 13.9;
  f.heading_deg = 90.0;
  f.position_confidence = fac::PositionFix::Ellipse{2.0, 1.0, 0.0};
  f.speed_confidence_mps = 0.1;
  f.heading_confidence_deg = 0.5;
  return f;
}

/// The BTP-B payload (a CAM as a CA service makes it, high-frequency container and all) of
/// neighbour @p i.
std::vector<std::uint8_t> cam_of(tb::clock::ManualRuntime& rt, int i) {
  fac::InjectedPositionProvider position;
  CapturingSender sender;
  fac::Ldm ldm(rt);
  fac::CaConfig cfg;
  cfg.station_id = 2000 + static_cast<std::uint32_t>(i);
  cfg.vehicle_length_m = 4.5;
  cfg.vehicle_width_m = 1.8;
  fac::CaService ca(rt, position, nullptr, sender, ldm, cfg);
  position.inject(fix_at(rt, 10.0 * i, 5.0));
  ca.start();
  ca.stop();
  return sender.last;
}

void BM_CamFrameToLdm(benchmark::State& state) {
  tb::clock::ManualRuntime rt;
  link::TestLink link{gn::testing::mac(1)};
  gn::StaticPositionProvider own;
  own.set({rt.wall_now(), gn::testing::kOriginLat, gn::testing::kOriginLon, 10.0, 90.0, true});
  gn::Router router{rt, link, own};
  tb::its::btp::Dispatcher btp{router};
  fac::InjectedPositionProvider position;
  CapturingSender sender;
  fac::Ldm ldm(rt);
  fac::CaConfig cfg;
  cfg.station_id = 1001;
  fac::CaService ca(rt, position, nullptr, sender, ldm, cfg);
  btp.register_port(fac::kBtpPortCam, [&](const tb::its::btp::Indication& ind,
                                          std::span<const std::uint8_t> payload) {
    ca.receive(payload, ind.gn ? ind.gn->rx_time : rt.wall_now());
  });

  std::vector<std::vector<std::uint8_t>> frames;
  const gn::Timestamp tst0 = gn::to_timestamp(rt.wall_now());
  for (int i = 0; i < kNeighbours; ++i) {
    gn::testing::PacketSpec s;
    s.source = gn::testing::remote_pv(static_cast<std::uint8_t>(i + 2),
                                      gn::testing::at(10.0 * i, 5), tst0);
    s.payload = {0x07, 0xd1, 0, 0};  // BTP-B to port 2001
    const auto cam = cam_of(rt, i);
    s.payload.insert(s.payload.end(), cam.begin(), cam.end());
    frames.push_back(gn::testing::make_packet(s));
  }
  constexpr std::size_t kTstAt = 20;  // the SHB's source LPV TST, after basic + common + GN_ADDR
  std::uint32_t counter = 0;
  for (auto _ : state) {
    const int i = static_cast<int>(counter % kNeighbours);
    auto& f = frames[static_cast<std::size_t>(i)];
    ++counter;
    // A newer TST each time, so that every packet updates the location table as in real
    // traffic.
    const std::uint32_t tst = tst0 + counter;
    f[kTstAt] = static_cast<std::uint8_t>(tst >> 24);
    f[kTstAt + 1] = static_cast<std::uint8_t>(tst >> 16);
    f[kTstAt + 2] = static_cast<std::uint8_t>(tst >> 8);
    f[kTstAt + 3] = static_cast<std::uint8_t>(tst);
    link.inject(gn::testing::mac(static_cast<std::uint8_t>(i + 2)), link::kBroadcastMac,
                link::kEtherTypeGeoNetworking, f, rt.wall_now());
  }
  state.SetItemsProcessed(state.iterations());
  if (ca.counters().received != static_cast<std::uint64_t>(state.iterations()))
    state.SkipWithError("not every CAM reached the LDM");
  state.counters["neighbours"] = static_cast<double>(ldm.neighbours().size());
  state.counters["cam_bytes"] = static_cast<double>(frames[0].size());
}
BENCHMARK(BM_CamFrameToLdm);

}  // namespace

BENCHMARK_MAIN();
