// What an output costs the frame thread: PipeWireOut::push (a copy of the canvas into the ring;
// PipeWire's own thread swizzles to BGRA and sends it) at 640x480, 1280x720 and 1920x1080, with
// no daemon (its thread drains the ring, so every push finds room), beside a plain memcpy of the
// same frame — the floor any hand-over of the pixels costs.
#include "output/pipewire_out.h"

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <thread>
#include <vector>

namespace {

void BM_PipeWirePush(benchmark::State& state) {
  const int w = int(state.range(0)), h = int(state.range(1));
  const auto empty = std::filesystem::temp_directory_path() / "marionette-bench-no-pipewire";
  std::filesystem::create_directories(empty);
  ::setenv("XDG_RUNTIME_DIR", empty.c_str(), 1);  // no daemon: measured alone
  mar::PipeWireOptions o;
  o.node_name = "marionette-bench";
  o.width = w;
  o.height = h;
  o.rate = 240;
  o.slots = 64;
  auto out = mar::PipeWireOut::open(o);
  std::vector<uint8_t> px(size_t(w) * size_t(h) * 4, 128);
  uint64_t n = 0;
  for (auto _ : state) {
    out->push(px.data(), w * 4, n, int64_t(n));
    ++n;
    if (n % 32 == 0) {  // let its thread drain (outside the timing)
      state.PauseTiming();
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      state.ResumeTiming();
    }
  }
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(px.size()));
}
BENCHMARK(BM_PipeWirePush)->Args({640, 480})->Args({1280, 720})->Args({1920, 1080})->Unit(benchmark::kMicrosecond)->Repetitions(5)->ReportAggregatesOnly();

void BM_Memcpy(benchmark::State& state) {
  const size_t bytes = size_t(state.range(0)) * size_t(state.range(1)) * 4;
  std::vector<uint8_t> a(bytes, 128), b(bytes);
  for (auto _ : state) {
    std::memcpy(b.data(), a.data(), bytes);
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(bytes));
}
BENCHMARK(BM_Memcpy)->Args({640, 480})->Args({1280, 720})->Args({1920, 1080})->Unit(benchmark::kMicrosecond)->Repetitions(5)->ReportAggregatesOnly();

}  // namespace

BENCHMARK_MAIN();
