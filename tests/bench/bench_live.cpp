// The live loop at 120 Hz, headless, with 1 kHz input events (a simulated nanoKONTROL2
// fader sweeping continuously plus a knob-box encoder), for MARIONETTE_BENCH_FRAMES frames
// (default 100,000). Reports p50/p99 frame compute, p99 input-to-frame latency and
// overruns as counters; writes the stats JSON to bench_live.json.
#include "app/live.h"

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include <cstdlib>

namespace {

std::string show_path() { return MARIONETTE_SOURCE_DIR "/tests/data/shows/bench_live.toml"; }

void BM_Live120HzWith1kHzInput(benchmark::State& state) {
  const char* env = std::getenv("MARIONETTE_BENCH_FRAMES");
  const long frames = env ? std::atol(env) : 100000;
  const std::string show = show_path();
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
