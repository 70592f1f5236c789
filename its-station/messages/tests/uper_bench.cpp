// CAM/DENM UPER encode and decode times, for the targets of issue 7: HF-only passenger-car CAM
// encode <= 250 ns, decode <= 350 ns; with LF container and 20 path points encode <= 1 us,
// decode <= 1.7 us (medians). Run with --benchmark_repetitions=10 or more.

#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <vector>

#include "its-station/messages/cam.hpp"
#include "its-station/messages/denm.hpp"
#include "its-station/messages/tests/samples.hpp"

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

BENCHMARK(BM_CamHfEncode);
BENCHMARK(BM_CamHfDecode);
BENCHMARK(BM_CamLf20Encode);
BENCHMARK(BM_CamLf20Decode);
BENCHMARK(BM_DenmEncode);
BENCHMARK(BM_DenmDecode);

}  // namespace
}  // namespace tb::its::messages

BENCHMARK_MAIN();
