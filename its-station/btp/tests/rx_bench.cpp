// The GN + BTP receive path on one core: a frame from the link through parsing, header checks,
// location table update, duplicate detection (multi-hop) and BTP dispatch to a port handler.

#include <benchmark/benchmark.h>

#include <vector>

#include "its-station/btp/dispatcher.hpp"
#include "its-station/geonet/tests/router_fixture.hpp"
#include "its-station/link/test_link.hpp"

namespace {

using namespace tb::its;
using namespace std::chrono_literals;
using geonet::testing::at;

constexpr int kSources = 64;

struct Receiver {
  tb::clock::ManualRuntime rt;
  link::TestLink link{geonet::testing::mac(1)};
  geonet::StaticPositionProvider pos;
  geonet::Router router{rt, link, pos};
  btp::Dispatcher btp{router};
  std::uint64_t bytes_seen = 0;

  Receiver() {
    link.keeps_sent_frames = false;  // forwarded GBCs go nowhere
    pos.set({rt.wall_now(), 48.15, -1.6, 10.0, 90.0, true});
    btp.register_port(btp::kPortCam,
                      [this](const btp::Indication&, auto p) { bytes_seen += p.size(); });
    btp.register_port(btp::kPortDenm,
                      [this](const btp::Indication&, auto p) { bytes_seen += p.size(); });
  }
};

// kSources stations' packets; each iteration bumps a packet's TST (single hop: every packet
// updates the location table entry) or SN (multi hop: none is a duplicate), as in real traffic.
void run(benchmark::State& state, geonet::PacketType type) {
  Receiver rx;
  std::vector<std::vector<std::uint8_t>> frames;
  const geonet::Timestamp tst0 = geonet::to_timestamp(rx.rt.wall_now());
  for (int i = 0; i < kSources; ++i) {
    geonet::testing::PacketSpec s;
    s.type = type;
    s.source = geonet::testing::remote_pv(static_cast<std::uint8_t>(i + 2), at(10.0 * i, 5), tst0);
    // A GBC inside the area arrives with RHL 2: delivered, then rebroadcast with RHL 1.
    s.rhl = type == geonet::PacketType::kSingleHopBroadcast ? 1 : 2;
    s.mhl = type == geonet::PacketType::kSingleHopBroadcast ? 1 : 10;
    s.area = geonet::testing::circle_at(at(0, 0), 1000);
    s.lifetime = 10s;
    s.payload = {0x07, 0xd1, 0, 0};
    s.payload.resize(4 + 40, 0x5a);  // a 40-byte CAM-sized body
    frames.push_back(geonet::testing::make_packet(s));
  }
  const bool single_hop = type == geonet::PacketType::kSingleHopBroadcast;
  const std::size_t tst_at = single_hop ? 20 : 24;  // LPV after basic+common (+ SN, reserved)
  std::uint32_t counter = 0;
  for (auto _ : state) {
    auto& f = frames[counter % kSources];
    ++counter;
    if (single_hop) {
      const std::uint32_t tst = tst0 + counter;
      f[tst_at] = static_cast<std::uint8_t>(tst >> 24);
      f[tst_at + 1] = static_cast<std::uint8_t>(tst >> 16);
      f[tst_at + 2] = static_cast<std::uint8_t>(tst >> 8);
      f[tst_at + 3] = static_cast<std::uint8_t>(tst);
    } else {
      f[12] = static_cast<std::uint8_t>(counter >> 8);
      f[13] = static_cast<std::uint8_t>(counter);
    }
    rx.link.inject(geonet::testing::mac(static_cast<std::uint8_t>(2 + counter % kSources)),
                   link::kBroadcastMac, link::kEtherTypeGeoNetworking, f, rx.rt.wall_now());
  }
  state.SetItemsProcessed(state.iterations());
  const auto delivered = rx.btp.stats().delivered;
  if (delivered != static_cast<std::uint64_t>(state.iterations()))
    state.SkipWithError("not every packet reached the port handler");
  benchmark::DoNotOptimize(rx.bytes_seen);
}

void BM_ReceiveShbToBtpPort(benchmark::State& state) {
  run(state, geonet::PacketType::kSingleHopBroadcast);
}
void BM_ReceiveGbcInsideAreaToBtpPort(benchmark::State& state) {
  run(state, geonet::PacketType::kGeoBroadcastCircle);
}

void BM_ParseShbOnly(benchmark::State& state) {
  geonet::testing::PacketSpec s;
  s.source = geonet::testing::remote_pv(2, at(0, 0), 1);
  const auto f = geonet::testing::make_packet(s);
  for (auto _ : state) {
    auto p = geonet::parse_packet(f);
    benchmark::DoNotOptimize(p);
  }
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK(BM_ReceiveShbToBtpPort);
BENCHMARK(BM_ReceiveGbcInsideAreaToBtpPort);
BENCHMARK(BM_ParseShbOnly);

}  // namespace

BENCHMARK_MAIN();
