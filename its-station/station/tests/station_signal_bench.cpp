// What one SPATEM costs a vehicle station (issue 34): the frame from the link through the GN
// router and BTP, the SPATEM decoded into the LDM's intersection store, converted into the signal
// application's model and handed to it. `changes:0` — the own group's state as before (most of
// the 10 a second); `changes:1` — every SPATEM changes it, so the application evaluates and
// publishes the `signal` message at once (the HMI's latency path).

#include <benchmark/benchmark.h>

#include "its-station/station/tests/signal_station_fixture.hpp"

namespace {

using namespace tb;
using namespace tb::its;
using namespace tb::its::station::testing;

void BM_SpatemFrameToSignalApp(benchmark::State& state) {
  const bool changes = state.range(0) != 0;
  SignalRun run;
  // Two seconds on the lane, 100 m before the line: MAPEM and SPATEM held, the lane matched.
  run.drive(130.0, 2.0, [](double) { return 15.0; });
  const auto start = run.world();
  // A green (t < 3 s) and an amber (3 s ≤ t < 6 s) SPATEM of the same light, as frames.
  std::vector<link::TestLink::SentFrame> frames;
  for (const double at : {0.0, 4.0}) {
    run.rsu.link.sent().clear();
    run.rsu.fix(run.host, run.world());
    const auto bytes = spatem(start - std::chrono::milliseconds{std::llround(at * 1000)}, start);
    run.rsu.sender.send_single_hop(facilities::kBtpPortSpatem, bytes);
    frames.push_back(run.rsu.link.sent().front());
  }
  const auto published = run.sink.published.size();
  std::size_t i = 0;
  for (auto _ : state) {
    const auto& f = frames[changes ? (i++ & 1) : 0];
    run.link.inject(run.rsu.link.address(), f.destination, f.ethertype, f.payload,
                    run.host.wall_now());
  }
  state.counters["published_per_spatem"] =
      benchmark::Counter(static_cast<double>(run.sink.published.size() - published),
                         benchmark::Counter::kAvgIterations);
  state.counters["spatem_received"] =
      static_cast<double>(run.station.intersection_receiver()->counters().spatem_received);
}
BENCHMARK(BM_SpatemFrameToSignalApp)
    ->ArgName("changes")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
