#include <benchmark/benchmark.h>

#include <filesystem>

#include "common/trace/tracer.hpp"

namespace {

void BM_TraceRecordEnabled(benchmark::State& state) {
  const auto path = std::filesystem::temp_directory_path() / "tracer_bench.jsonl";
  tb::trace::Tracer t(path.string(), "bench");
  std::uint64_t tick = 0;
  for (auto _ : state) {
    t.record("cam.tx", {{"station", 1001u}, {"tick", ++tick}, {"gdt", 4242}, {"lat", 41.0255123}});
  }
  t.flush();
  std::filesystem::remove(path);
}
BENCHMARK(BM_TraceRecordEnabled);

void BM_TraceRecordDisabled(benchmark::State& state) {
  tb::trace::Tracer t;
  std::uint64_t tick = 0;
  for (auto _ : state) {
    t.record("cam.tx", {{"station", 1001u}, {"tick", ++tick}, {"gdt", 4242}, {"lat", 41.0255123}});
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_TraceRecordDisabled);

}  // namespace

BENCHMARK_MAIN();
