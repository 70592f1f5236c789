// The publishing thread's cost per QoS 0 message on a real Mosquitto (the station's mirror of
// received CAMs, issue 33): each message written at once, against bursts held and written by one
// flush() as its-station does once per io wake-up, both with this client's own QoS 0 packets
// (one send() per write); and, side by side, plain libmosquitto's mosquitto_publish, which the
// client used before (a write per packet and a byte to its socket pair per publish). Bursts of 1,
// 2, 4 and 16 messages: a station at 49 neighbours mirrors about 110-160 CAMs a second, 2.1 per
// batch. Read the CPU column: the publishing thread's time per burst, burst 0 being the pause's own
// cost. TESTBED_ROOT must name the repository (the broker's configuration is rendered from
// docker/mosquitto).
#include <benchmark/benchmark.h>
#include <mosquitto.h>

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
  tb::mqtt::ClientConfig c = b.station_account(1001);
  c.client_id += "-bench";
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

// The baseline: libmosquitto without its thread, publishing as MosquittoClient did before it
// encoded QoS 0 packets itself.
void BM_LibmosquittoPublish(benchmark::State& state) {
  const auto burst = static_cast<int>(state.range(0));
  const tb::mqtt::ClientConfig c = station(broker());
  mosquitto_lib_init();
  bool connected = false;
  mosquitto* m = mosquitto_new((c.client_id + "-lib").c_str(), true, &connected);
  mosquitto_connect_callback_set(
      m, [](mosquitto*, void* flag, int rc) { *static_cast<bool*>(flag) = rc == 0; });
  mosquitto_int_option(m, MOSQ_OPT_TCP_NODELAY, 1);
  mosquitto_username_pw_set(m, c.username.c_str(), c.password.c_str());
  if (mosquitto_connect(m, c.host.c_str(), c.port, 60) != MOSQ_ERR_SUCCESS) {
    state.SkipWithError("libmosquitto cannot connect");
    mosquitto_destroy(m);
    return;
  }
  for (int i = 0; i < 50 && !connected; ++i)
    mosquitto_loop(m, 100, 1);
  if (!connected) {
    state.SkipWithError("no CONNACK");
    mosquitto_destroy(m);
    return;
  }
  const std::string payload(350, 'x');
  for (auto _ : state) {
    for (int i = 0; i < burst; ++i)
      mosquitto_publish(m, nullptr, "its/1001/in/cam/1002", static_cast<int>(payload.size()),
                        payload.data(), 0, false);
    std::this_thread::sleep_for(2ms);
  }
  state.SetItemsProcessed(state.iterations() * burst);
  mosquitto_disconnect(m);
  mosquitto_destroy(m);
}
BENCHMARK(BM_LibmosquittoPublish)
    ->ArgNames({"burst"})
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->Arg(4)
    ->Arg(16)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
