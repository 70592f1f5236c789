// The publishing thread's cost per QoS 0 message on a real Mosquitto (the station's mirror of
// received CAMs, issue 33): each message written at once (one TCP write and segment each, and
// libmosquitto's byte to its socket pair), against bursts held and written by one flush() as
// its-station does once per io wake-up. Bursts of 1, 2, 4 and 16 messages: a station at 49
// neighbours mirrors about 110-160 CAMs a second, 2.1 per batch. Read the CPU column:
// the publishing thread's time per burst, burst 0 being the pause's own cost. TESTBED_ROOT must
// name the repository (the broker's configuration is rendered from docker/mosquitto).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <string>

#include "common/clock/clock.hpp"
#include "common/mqtt/mosquitto_client.hpp"
#include "common/mqtt/tests/test_broker.hpp"

namespace {

using namespace std::chrono_literals;
using tb::mqtt::testing::Broker;

Broker& broker() {
  static Broker b("1001");
  static const bool started = b.configured() && b.start();
  if (!started)
    std::fprintf(stderr, "publish_bench: no broker (is TESTBED_ROOT the repository?)\n");
  return b;
}

tb::mqtt::ClientConfig station(const Broker& b) {
  tb::mqtt::ClientConfig c;
  c.port = b.port();
  c.client_id = "station-1001-bench";
  c.username = "station-1001";
  c.password = b.password(1001);
  return c;
}

void BM_PublishCams(benchmark::State& state) {
  const bool batched = state.range(0) != 0;
  const auto burst = static_cast<int>(state.range(1));
  tb::clock::SystemClock clk;
  tb::mqtt::MosquittoClient client(clk, station(broker()));
  bool requested = false;
  if (batched)
    client.set_flush_request([&] { requested = true; });
  client.start();
  if (!tb::mqtt::testing::wait_until([&] { return client.connected(); }, 5s)) {
    state.SkipWithError("not connected to the broker");
    return;
  }
  const std::string payload(350, 'x');  // a received CAM's JSON is about this long
  for (auto _ : state) {
    for (int i = 0; i < burst; ++i)
      client.publish("its/1001/in/cam/1002", payload, tb::mqtt::Qos::kAtMostOnce, false);
    if (requested) {
      requested = false;
      client.flush();
    }
    // Bursts come apart as a station's wake-ups do, so that the broker has gone idle and each
    // segment wakes it (the cost a batch saves); the CPU column is this thread's and excludes
    // the wait.
    std::this_thread::sleep_for(2ms);
  }
  state.SetItemsProcessed(state.iterations() * burst);
  client.stop();
}
BENCHMARK(BM_PublishCams)
    ->ArgNames({"batched", "burst"})
    ->ArgsProduct({{0, 1}, {0, 1, 2, 4, 16}})
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
