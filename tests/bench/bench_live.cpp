// The live loop at 120 Hz, headless, with 1 kHz input events (a simulated nanoKONTROL2
// fader sweeping continuously plus a knob-box encoder), for MARIONETTE_BENCH_FRAMES frames
// (default 100,000). Reports p50/p99 frame compute, p99 input-to-frame latency and
// overruns as counters; writes the stats JSON to bench_live.json.
#include "app/live.h"

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace {

std::string write_show() {
  const auto dir = std::filesystem::temp_directory_path() / "marionette-bench";
  std::filesystem::create_directories(dir);
  const auto path = dir / "bench_live.toml";
  std::ofstream(path) << "[show]\nrig = \"" MARIONETTE_SOURCE_DIR "/config/rigs/figure.toml\"\n" << R"(rate = 120
iterations = 8
min_iterations = 3
[display]
width = 320
height = 400
[[device]]
name = "korg"
sim = "nanokontrol2"
script = """
0.0 move fader1 0
0.001 move fader1 1 over 0.127
0.128 move fader1 0 over 0.127
loop 0.256
"""
[[device]]
name = "knobs"
sim = "knob_box"
bounce_ms = 1
script = """
0.0 turn 1 50 over 1.0
1.0 turn 1 -50 over 1.0
loop 2.0
"""
[[group]]
name = "head"
handles = ["head"]
pivot_handle = "chest"
[[binding]]
device = "korg"
control = "cc 0"
target = "handle.left-hand.y"
range = [250.0, 110.0]
filter = { min_cutoff = 1.0, beta = 0.2 }
[[binding]]
device = "knobs"
control = "encoder 1"
target = "rotate.head"
mode = "delta"
step = 0.5
)";
  return path.string();
}

void BM_Live120HzWith1kHzInput(benchmark::State& state) {
  const char* env = std::getenv("MARIONETTE_BENCH_FRAMES");
  const long frames = env ? std::atol(env) : 100000;
  const std::string show = write_show();
  for (auto _ : state) {
    mar::RunOptions o;
    o.headless = true;
    o.quiet = true;
    o.frames = frames;
    o.stats_path = "bench_live.json";
    auto s = mar::LiveShow::load(show, o);
    if (!s.ok()) {
      state.SkipWithError(s.error.c_str());
      return;
    }
    (*s.value)->run();
    const auto j = nlohmann::json::parse((*s.value)->stats_json());
    state.counters["frames"] = j["frames"].get<double>();
    state.counters["frame_p50_us"] = j["stages_us"]["frame"]["p50"].get<double>();
    state.counters["frame_p99_us"] = j["stages_us"]["frame"]["p99"].get<double>();
    state.counters["frame_max_us"] = j["stages_us"]["frame"]["max"].get<double>();
    state.counters["solve_p99_us"] = j["stages_us"]["solve"]["p99"].get<double>();
    state.counters["latency_p50_us"] = j["latency_us"]["p50"].get<double>();
    state.counters["latency_p99_us"] = j["latency_us"]["p99"].get<double>();
    state.counters["events"] = j["latency_us"]["events"].get<double>();
    state.counters["overruns"] = j["overruns"].get<double>();
    state.counters["allocs_after_warmup"] = j["heap_allocations_after_warmup"].get<double>();
  }
}
BENCHMARK(BM_Live120HzWith1kHzInput)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
