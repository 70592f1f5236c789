// A station's receive path per CAM, as at 49 neighbours: a frame from the link through the GN
// router (parse, checks, location table), BTP dispatch to the CAM port, UPER decoding, the CA
// service's checks and the LDM update with its history. What a full station spends per
// received CAM besides the wake-up that brought it, the MQTT mirror and LCRW (issue 33,
// docs/latency.md); steadier before/after figures than whole-testbed runs on a busy machine.

#include <benchmark/benchmark.h>

#include <memory>
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
/// station @p station_id, @p east metres from the origin.
std::vector<std::uint8_t> cam_of(tb::clock::ManualRuntime& rt, std::uint32_t station_id,
                                 double east) {
  fac::InjectedPositionProvider position;
  CapturingSender sender;
  fac::Ldm ldm(rt);
  fac::CaConfig cfg;
  cfg.station_id = station_id;
  cfg.vehicle_length_m = 4.5;
  cfg.vehicle_width_m = 1.8;
  fac::CaService ca(rt, position, nullptr, sender, ldm, cfg);
  position.inject(fix_at(rt, east, 5.0));
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
    const auto cam = cam_of(rt, 2000 + static_cast<std::uint32_t>(i), 10.0 * i);
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

/// One receiving stack of a pooled station: link, GN router, BTP, CA service and LDM, no LCRW
/// and no MQTT (station-host's pooled stations, station-host/README.md).
struct PooledReceiver {
  PooledReceiver(tb::clock::ManualRuntime& rt, const gn::PositionProvider& own,
                 fac::PositionProvider& position, fac::MessageSender& sender,
                 const tb::its::link::MacAddress& address, std::uint32_t station_id)
      : link(address),
        router(rt, link, own),
        btp(router),
        ldm(rt),
        ca(rt, position, nullptr, sender, ldm, [&] {
          fac::CaConfig c;
          c.station_id = station_id;
          return c;
        }()) {
    btp.register_port(fac::kBtpPortCam, [this, &rt](const tb::its::btp::Indication& ind,
                                                    std::span<const std::uint8_t> payload) {
      ca.receive(payload, ind.gn ? ind.gn->rx_time : rt.wall_now());
    });
  }
  link::TestLink link;
  gn::Router router;
  tb::its::btp::Dispatcher btp;
  fac::Ldm ldm;
  fac::CaService ca;
};

tb::its::link::MacAddress pooled_mac(std::uint32_t id) {
  return {
      0x02, 0x00, 0x00, 0x00, static_cast<std::uint8_t>(id >> 8), static_cast<std::uint8_t>(id)};
}

/// Issue 33's load: N pooled stations in range of each other, each iteration one CAM (of the
/// next station in turn) handed to the other N − 1, the clock moved on as at 815 CAMs received
/// per station-second (station-host/README.md's 300-in-range run), so that the LDMs' and
/// location tables' expiry timers run at their real rate. The figure: ns per station per CAM
/// (`per_station_cam`), the receive path plus its share of the timers.
void BM_CamToPooledStations(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const bool share_decoder = state.range(1) != 0;
  tb::clock::ManualRuntime rt;
  fac::SharedCamDecoder decoder;
  gn::StaticPositionProvider own;
  own.set({rt.wall_now(), gn::testing::kOriginLat, gn::testing::kOriginLon, 10.0, 90.0, true});
  fac::InjectedPositionProvider position;
  CapturingSender sender;
  std::vector<std::unique_ptr<PooledReceiver>> stations;
  std::vector<std::vector<std::uint8_t>> frames;
  for (int i = 0; i < n; ++i) {
    const auto id = 1000 + static_cast<std::uint32_t>(i);
    stations.push_back(
        std::make_unique<PooledReceiver>(rt, own, position, sender, pooled_mac(id), id));
    if (share_decoder)
      stations.back()->ca.set_shared_decoder(&decoder);
    gn::testing::PacketSpec s;
    s.source =
        gn::testing::remote_pv(0, gn::testing::at(10.0 * i, 5), gn::to_timestamp(rt.wall_now()));
    s.source.address.mid = pooled_mac(id);
    s.payload = {0x07, 0xd1, 0, 0};  // BTP-B to port 2001
    const auto cam = cam_of(rt, id, 10.0 * i);
    s.payload.insert(s.payload.end(), cam.begin(), cam.end());
    frames.push_back(gn::testing::make_packet(s));
  }
  constexpr std::size_t kTstAt = 20;
  // 815 CAMs received per station-second: one CAM sent every 1/815 s.
  constexpr auto kStep = std::chrono::microseconds{1227};
  std::uint64_t counter = 0;
  for (auto _ : state) {
    const auto from = static_cast<std::size_t>(counter % static_cast<std::uint64_t>(n));
    ++counter;
    rt.advance(kStep);
    auto& f = frames[from];
    const std::uint32_t tst = gn::to_timestamp(rt.wall_now());
    f[kTstAt] = static_cast<std::uint8_t>(tst >> 24);
    f[kTstAt + 1] = static_cast<std::uint8_t>(tst >> 16);
    f[kTstAt + 2] = static_cast<std::uint8_t>(tst >> 8);
    f[kTstAt + 3] = static_cast<std::uint8_t>(tst);
    const auto src = stations[from]->link.address();
    for (std::size_t i = 0; i < stations.size(); ++i)
      if (i != from)
        stations[i]->link.inject(src, link::kBroadcastMac, link::kEtherTypeGeoNetworking, f,
                                 rt.wall_now());
  }
  std::uint64_t received = 0;
  std::size_t neighbours = 0;
  for (const auto& s : stations) {
    received += s->ca.counters().received;
    neighbours += s->ldm.neighbours().size();
  }
  const auto deliveries =
      static_cast<std::uint64_t>(state.iterations()) * static_cast<std::uint64_t>(n - 1);
  if (received != deliveries)
    state.SkipWithError("not every CAM reached the LDMs");
  state.SetItemsProcessed(static_cast<std::int64_t>(deliveries));
  state.counters["per_station_cam"] = benchmark::Counter(
      static_cast<double>(deliveries), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["neighbours"] = static_cast<double>(neighbours) / n;
}
// Second argument 1: the stations share one SharedCamDecoder (one decoded CAM per frame).
BENCHMARK(BM_CamToPooledStations)
    ->ArgNames({"stations", "shared_decoder"})
    ->Args({300, 0})
    ->Args({300, 1})
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
