// The RSU's CPU per message: a feed datagram that changes a state → the SPATEM handed to the
// network (parse, build, UPER encode), a periodic SPATEM, and building the MAPEM of the
// shipped four-way junction (once per start).

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string>

#include "common/clock/runtime.hpp"
#include "common/geodesy/local_frame.hpp"
#include "common/map/opendrive/reader.hpp"
#include "its-station/rsu/rsu_service.hpp"

namespace {

namespace sim = tb::wire::sim;

class NullSender final : public tb::its::facilities::MessageSender {
 public:
  tb::its::facilities::SendResult send_single_hop(std::uint16_t,
                                                  std::span<const std::uint8_t> p) override {
    bytes += p.size();
    return tb::its::facilities::SendResult::kSent;
  }
  tb::its::facilities::SendResult send_geobroadcast(std::uint16_t,
                                                    const tb::its::facilities::GeoArea&,
                                                    std::span<const std::uint8_t>, std::uint32_t,
                                                    std::uint8_t) override {
    return tb::its::facilities::SendResult::kLinkError;
  }
  std::size_t bytes = 0;
};

std::string four_way() {
  const char* root = std::getenv("TESTBED_ROOT");
  return std::string(root != nullptr ? root : ".") + "/scenarios/maps/four_way_junction.xodr";
}

tb::its::rsu::IntersectionMap four_way_map() {
  static const auto net = tb::map::odr::load_opendrive(four_way());
  static const tb::map::odr::SignalLayout layout(net);
  static const tb::geodesy::LocalFrame frame({48.137, 11.575, 520.0});
  return tb::its::rsu::MapemBuilder(net, layout, frame).build("100");
}

std::vector<std::uint8_t> datagram(sim::MovementPhaseState g1, std::int64_t now) {
  sim::SignalStates s;
  s.world_time_ms = now;
  s.groups = {{100, 1, g1, now + 5000, now + 5000},
              {100, 2, sim::MovementPhaseState::kStopAndRemain, now + 9000, now + 9000},
              {100, 3, g1, now + 5000, now + 5000},
              {100, 4, sim::MovementPhaseState::kStopAndRemain, now + 9000, now + 9000}};
  return sim::encode(s);
}

void BM_FeedChangeToSpatem(benchmark::State& state) {
  tb::clock::ManualRuntime rt;
  NullSender sender;
  tb::its::rsu::RsuService rsu(rt, sender, four_way_map());
  rsu.start();
  const std::int64_t now = 1'795'779'612'345;
  const auto red = datagram(sim::MovementPhaseState::kStopAndRemain, now);
  const auto green = datagram(sim::MovementPhaseState::kProtectedMovementAllowed, now);
  bool flip = false;
  for (auto _ : state) {
    rsu.on_datagram(flip ? red : green);  // every datagram a change: a SPATEM each
    flip = !flip;
  }
  if (rsu.counters().spatem_on_change < static_cast<std::uint64_t>(state.iterations()))
    state.SkipWithError("not every change made a SPATEM");
  state.counters["spatem_bytes"] =
      static_cast<double>(sender.bytes) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_FeedChangeToSpatem);

void BM_SpatemBuildEncode(benchmark::State& state) {
  tb::its::rsu::SpatemBuilder b(100);
  sim::SignalStates s;
  const std::int64_t now = 1'795'779'612'345;
  s.groups = {{100, 1, sim::MovementPhaseState::kStopAndRemain, now + 5000, now + 5000},
              {100, 2, sim::MovementPhaseState::kProtectedMovementAllowed, now + 9000, now + 9000},
              {100, 3, sim::MovementPhaseState::kStopAndRemain, now + 5000, now + 5000},
              {100, 4, sim::MovementPhaseState::kProtectedMovementAllowed, now + 9000, now + 9000}};
  for (auto _ : state)
    benchmark::DoNotOptimize(b.build(s, now));
}
BENCHMARK(BM_SpatemBuildEncode);

void BM_MapemBuildFourWay(benchmark::State& state) {
  for (auto _ : state)
    benchmark::DoNotOptimize(four_way_map());
}
BENCHMARK(BM_MapemBuildFourWay)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
