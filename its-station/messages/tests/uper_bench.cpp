// CAM/DENM UPER encode and decode times, for the targets of issue 7: HF-only passenger-car CAM
// encode <= 250 ns, decode <= 350 ns; with LF container and 20 path points encode <= 1 us,
// decode <= 1.7 us (medians); and the signal messages of issue 34 beside them: a typical SPATEM
// (one intersection, 8 signal groups with timing) and MAPEM (4 arms, 8 ingress and 4 egress
// lanes of 4-6 nodes, connections). Run with --benchmark_repetitions=10 or more.

#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "its-station/messages/cam.hpp"
#include "its-station/messages/denm.hpp"
#include "its-station/messages/mapem.hpp"
#include "its-station/messages/spatem.hpp"
#include "its-station/messages/tests/samples.hpp"
#include "its-station/messages/tests/signal_samples.hpp"

namespace tb::its::messages {
namespace {

void encode_cam(benchmark::State& state, const Cam& cam) {
  std::array<std::uint8_t, kCamMaxEncodedSize> buf{};
  for (auto _ : state) {
    auto n = encode(cam, buf);
    benchmark::DoNotOptimize(n);
    benchmark::DoNotOptimize(buf.data());
    benchmark::ClobberMemory();
  }
  auto n = encode(cam, buf);
  state.counters["bytes"] = n ? static_cast<double>(*n) : -1.0;
}

void decode_cam_bench(benchmark::State& state, const Cam& cam) {
  auto bytes = encode(cam);
  if (!bytes) {
    state.SkipWithError(asn1::to_string(bytes.error()).c_str());
    return;
  }
  Cam out;
  for (auto _ : state) {
    auto n = decode(*bytes, out);
    benchmark::DoNotOptimize(n);
    benchmark::DoNotOptimize(out);
    benchmark::ClobberMemory();
  }
  if (!(out == cam))
    state.SkipWithError("decoded CAM differs");
  state.counters["bytes"] = static_cast<double>(bytes->size());
}

void BM_CamHfEncode(benchmark::State& s) {
  encode_cam(s, samples::cam_hf());
}
void BM_CamHfDecode(benchmark::State& s) {
  decode_cam_bench(s, samples::cam_hf());
}
void BM_CamLf20Encode(benchmark::State& s) {
  encode_cam(s, samples::cam_with_path(20));
}
void BM_CamLf20Decode(benchmark::State& s) {
  decode_cam_bench(s, samples::cam_with_path(20));
}

void BM_DenmEncode(benchmark::State& state) {
  const Denm d = samples::denm_collision_risk();
  std::vector<std::uint8_t> buf(kDenmMaxEncodedSize);
  for (auto _ : state) {
    auto n = encode(d, buf);
    benchmark::DoNotOptimize(n);
    benchmark::ClobberMemory();
  }
}
void BM_DenmDecode(benchmark::State& state) {
  auto bytes = encode(samples::denm_collision_risk());
  Denm out;
  for (auto _ : state) {
    auto n = decode(*bytes, out);
    benchmark::DoNotOptimize(n);
    benchmark::DoNotOptimize(out);
    benchmark::ClobberMemory();
  }
}

// Signal messages: encode into a buffer of the message's usual size, decode into an object held
// on the heap (as a station holds its last SPATEM and MAPEM).
template <typename Msg>
void encode_signal(benchmark::State& state, const Msg& msg) {
  std::vector<std::uint8_t> buf(8192);
  for (auto _ : state) {
    auto n = encode(msg, buf);
    benchmark::DoNotOptimize(n);
    benchmark::DoNotOptimize(buf.data());
    benchmark::ClobberMemory();
  }
  auto n = encode(msg, buf);
  state.counters["bytes"] = n ? static_cast<double>(*n) : -1.0;
}
template <typename Msg>
void decode_signal(benchmark::State& state, const Msg& msg) {
  auto bytes = encode(msg);
  if (!bytes) {
    state.SkipWithError(asn1::to_string(bytes.error()).c_str());
    return;
  }
  auto out = std::make_unique<Msg>();
  for (auto _ : state) {
    auto n = decode(*bytes, *out);
    benchmark::DoNotOptimize(n);
    benchmark::DoNotOptimize(out.get());
    benchmark::ClobberMemory();
  }
  if (!(*out == msg))
    state.SkipWithError("decoded message differs");
  state.counters["bytes"] = static_cast<double>(bytes->size());
}

void BM_SpatemEncode(benchmark::State& s) {
  encode_signal(s, *samples::spatem_typical(8));
}
void BM_SpatemDecode(benchmark::State& s) {
  decode_signal(s, *samples::spatem_typical(8));
}
void BM_MapemEncode(benchmark::State& s) {
  encode_signal(s, *samples::mapem_typical());
}
void BM_MapemDecode(benchmark::State& s) {
  decode_signal(s, *samples::mapem_typical());
}

BENCHMARK(BM_CamHfEncode);
BENCHMARK(BM_CamHfDecode);
BENCHMARK(BM_CamLf20Encode);
BENCHMARK(BM_CamLf20Decode);
BENCHMARK(BM_DenmEncode);
BENCHMARK(BM_DenmDecode);
BENCHMARK(BM_SpatemEncode);
BENCHMARK(BM_SpatemDecode);
BENCHMARK(BM_MapemEncode);
BENCHMARK(BM_MapemDecode);

}  // namespace
}  // namespace tb::its::messages

BENCHMARK_MAIN();
