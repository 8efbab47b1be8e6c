// The live loop at 120 Hz, headless, with 1 kHz input events (a simulated nanoKONTROL2
// fader sweeping continuously plus a knob-box encoder), for MARIONETTE_BENCH_FRAMES frames
// (default 100,000), on the virtual clock and then on the wall clock with late input off and on.
// Reports p50/p99 frame compute, p99 input-to-frame latency and
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

// The same show on the wall clock (run --realtime), side by side: late input off (a frame reads
// when it is due, as before) and on (it wakes its predicted compute plus a margin before).
// "newest_*" is the age of the newest input a frame shows: at frame-ready, and at the tick that
// shows it (its deadline, or the next one when it was late). Per-event latency keeps the
// sampling gap (a 1 kHz event waits up to a period for the next frame to read it).
void BM_Live120HzRealtime(benchmark::State& state) {
  const char* env = std::getenv("MARIONETTE_BENCH_FRAMES");
  const long frames = env ? std::atol(env) : 100000;
  for (auto _ : state) {
    mar::RunOptions o;
    o.headless = true;
    o.realtime = true;
    o.quiet = true;
    o.frames = frames;
    o.late_input = int(state.range(0));
    o.stats_path = state.range(0) ? "bench_live_late.json" : "bench_live_realtime.json";
    auto s = mar::LiveShow::load(show_path(), o);
    if (!s.ok()) {
      state.SkipWithError(s.error.c_str());
      return;
    }
    (*s.value)->run();
    const auto j = nlohmann::json::parse((*s.value)->stats_json());
    const auto& l = j["late_input"];
    state.counters["frames"] = j["frames"].get<double>();
    state.counters["frame_p99_us"] = j["stages_us"]["frame"]["p99"].get<double>();
    state.counters["lead_p50_us"] = l["lead_us"]["p50"].get<double>();
    state.counters["newest_to_ready_p50_us"] = l["newest_input_to_ready_us"]["p50"].get<double>();
    state.counters["newest_to_ready_p99_us"] = l["newest_input_to_ready_us"]["p99"].get<double>();
    state.counters["newest_to_shown_p50_us"] = l["newest_input_to_shown_us"]["p50"].get<double>();
    state.counters["newest_to_shown_p99_us"] = l["newest_input_to_shown_us"]["p99"].get<double>();
    state.counters["event_latency_p50_us"] = j["latency_us"]["p50"].get<double>();
    state.counters["event_latency_p99_us"] = j["latency_us"]["p99"].get<double>();
    state.counters["missed_deadlines"] = l["missed_deadlines"].get<double>();
    state.counters["overruns"] = j["overruns"].get<double>();
    state.counters["allocs_after_warmup"] = j["heap_allocations_after_warmup"].get<double>();
  }
}
BENCHMARK(BM_Live120HzRealtime)->Arg(0)->Arg(1)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
