// The emulator's processing per vehicle state (the thesis's p2 without the kernel's share):
// decode the datagram, run the station's GPS agent and CAN feeder, hand the bytes to the
// sinks. Sinks here discard; the cost of the send system calls is measured separately.

#include <benchmark/benchmark.h>

#include <cstring>

#include <boost/asio/ip/udp.hpp>

#include "common/can/udp_can_bus.hpp"
#include "common/clock/clock.hpp"
#include "common/scenario/loader.hpp"
#include "common/wire/signal_feed.hpp"
#include "network-emulator/app/emulator.hpp"

namespace tb::emu {
namespace {

class NullSink final : public DatagramSink {
 public:
  std::error_code send(std::span<const std::uint8_t>) override { return {}; }
};
class NullBus final : public tb::can::CanBus {
 public:
  std::string_view kind() const override { return "null"; }
  std::error_code send(std::span<const tb::can::CanFrame>) override { return {}; }
  void start_receive(FrameHandler) override {}
};

scenario::Scenario make_scenario(int stations, bool noisy) {
  std::string v;
  for (int i = 0; i < stations; ++i)
    v += (i ? "," : "") + std::string("{\"id\": \"v") + std::to_string(i) +
         "\", \"station_id\": " + std::to_string(1000 + i) +
         ", \"spawn\": {\"x\": " + std::to_string(i * 10) + ", \"y\": 0, \"heading_deg\": 90}}";
  return scenario::parse(
      std::string("{\"name\": \"bench\", \"map\": {\"type\": \"straight\", \"length\": 20000}, "
                  "\"origin\": {\"lat\": 48, \"lon\": 11}, \"gnss\": ") +
          (noisy ? "{\"model\": \"noisy\"}" : "{}") + ", \"vehicles\": [" + v + "]}",
      "bench.json");
}

/// 1000 stations, states at 100 Hz in sim time, round robin: each iteration is one state.
void BM_StateUpdate(benchmark::State& st) {
  const int n = static_cast<int>(st.range(0));
  const auto scen = make_scenario(n, st.range(1) != 0);
  const auto dbc = *tb::can::Database::load(TESTBED_VEHICLE_DBC);
  clock::ManualClock clock;
  trace::Tracer tracer;
  Emulator emu(
      scen, dbc, default_stations(scen),
      [](const StationEndpoints&) {
        return StationIo{std::make_unique<NullSink>(), std::make_unique<NullBus>()};
      },
      clock, tracer);
  std::vector<std::array<std::uint8_t, wire::kVehicleStateSize>> datagrams;
  wire::VehicleState s;
  s.velocity = {10.0f, 0.0f, 0.0f};
  s.speed = 10.0f;
  std::int64_t tick = 0;
  int i = 0;
  std::array<std::uint8_t, wire::batch_datagram_size(1)> datagram{};
  for (auto _ : st) {
    if (i == 0)
      ++tick;
    s.station_id = static_cast<std::uint32_t>(1000 + i);
    s.tick = static_cast<std::uint64_t>(tick);
    s.sim_time_ns = tick * 10'000'000;
    s.position = {static_cast<double>(i) * 10.0, static_cast<double>(tick) * 0.1, 0.0};
    // One state per datagram: the dearest case per state (a batch shares its head).
    const std::size_t size = wire::encode_batch({&s, 1}, datagram);
    emu.handle_datagram(std::span<const std::uint8_t>(datagram.data(), size));
    i = (i + 1) % n;
  }
  st.counters["nmea/state"] =
      static_cast<double>(emu.counters().nmea_sent) / static_cast<double>(emu.counters().states);
  st.counters["frames/state"] = static_cast<double>(emu.counters().can_frames_sent) /
                                static_cast<double>(emu.counters().states);
}
BENCHMARK(BM_StateUpdate)->Args({1000, 0})->Args({1000, 1})->ArgNames({"stations", "noise"});

/// The kernel's share: one send() of an NMEA epoch (about 560 bytes) on a connected UDP
/// socket to a loopback receiver that does not read (the kernel drops what overflows).
void BM_SendNmeaDatagram(benchmark::State& st) {
  boost::asio::io_context io;
  boost::asio::ip::udp::socket rx(io, {boost::asio::ip::make_address("127.0.0.1"), 0});
  boost::asio::ip::udp::socket tx(io, boost::asio::ip::udp::v4());
  tx.non_blocking(true);
  tx.connect(rx.local_endpoint());
  const std::vector<std::uint8_t> epoch(560, 'x');
  boost::system::error_code ec;
  for (auto _ : st)
    benchmark::DoNotOptimize(tx.send(boost::asio::buffer(epoch), 0, ec));
}
BENCHMARK(BM_SendNmeaDatagram);

/// One cannelloni datagram with the 5 frames a 100 Hz state makes.
void BM_SendCanDatagram(benchmark::State& st) {
  boost::asio::io_context io;
  boost::asio::ip::udp::socket rx(io, {boost::asio::ip::make_address("127.0.0.1"), 0});
  auto bus = tb::can::UdpCanBus::connect(io, rx.local_endpoint());
  std::vector<tb::can::CanFrame> frames(
      5, tb::can::make_frame(0x100, std::vector<std::uint8_t>(8, 1)));
  for (auto _ : st)
    benchmark::DoNotOptimize(bus->send(frames));
}
BENCHMARK(BM_SendCanDatagram);

/// The signal feed's hop (issue 34): one SignalStates of J junctions × 4 groups from a
/// sim-client, decoded, checked for a copy, and each of J RSUs sent its junction's 4 groups
/// (discarding sinks). Every iteration is a new world time, so nothing is dropped as a copy.
void BM_SignalFeedToRsus(benchmark::State& st) {
  const auto junctions = static_cast<std::uint16_t>(st.range(0));
  NullSink sink;
  std::vector<SignalFeed::Rsu> rsus;
  for (std::uint16_t j = 0; j < junctions; ++j)
    rsus.push_back({static_cast<std::uint32_t>(5000 + j), j, &sink});
  trace::Tracer tracer;
  SignalFeed feed(rsus, tracer);
  wire::sim::SignalStates states{1'795'000'000'000, {}};
  for (std::uint16_t j = 0; j < junctions; ++j)
    for (std::uint8_t g = 1; g <= 4; ++g)
      states.groups.push_back({j, g, wire::sim::MovementPhaseState::kStopAndRemain,
                               states.world_time_ms + 5000, states.world_time_ms + 5000});
  std::vector<std::uint8_t> datagram = *wire::encode_signal_feed(states);
  for (auto _ : st) {
    ++states.world_time_ms;
    std::memcpy(datagram.data() + 8, &states.world_time_ms, 8);  // little-endian host
    benchmark::DoNotOptimize(feed.handle_datagram(datagram));
  }
  if (feed.counters().sent != static_cast<std::uint64_t>(st.iterations()) * junctions)
    st.SkipWithError("not every RSU was sent its groups");
}
BENCHMARK(BM_SignalFeedToRsus)->Arg(1)->Arg(25);

}  // namespace
}  // namespace tb::emu

BENCHMARK_MAIN();
