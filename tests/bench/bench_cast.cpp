// A cast on one stage at 1920 x 1080, 60 Hz, headless on the virtual clock: 1, 2, 4, 8 and 16
// characters (the figure, the robot and the cat in turn, side by side), each with a knob moving
// one of its hands all show long, solved on the frame's thread alone (threads = 1) and on the
// worker pool (one thread a character, up to the cores: threads = 0 below 4 characters is the
// frame's alone, so 2 characters are given the pool), side by side in one run. Reports the
// p50 and p99 of the frame and of its solve and render stages (µs), and allocations after
// warm-up. MARIONETTE_BENCH_FRAMES frames (default 600).
#include "app/live.h"

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace {

std::string cast_show(int n, int threads) {
  static const char* const rigs[] = {"figure", "robot", "cat"};
  static const char* const hands[] = {"left-hand", "left-hand", "tail"};
  std::string text = "[show]\nrate = 60\niterations = 8\nmin_iterations = 8\n" +
                     (threads > 0 ? "threads = " + std::to_string(threads) + "\n" : std::string()) + "[display]\nwidth = 1920\nheight = 1080\nhud = false\n"
                     "[[device]]\nname = \"knobs\"\nsim = \"knob_box\"\nscript = \"\"\"\n";
  for (int k = 0; k < 10; ++k)  // the knob turns one way, then back, for 20 s
    text += std::to_string(2 * k) + ".0 turn 1 -12 over 1.0\n" + std::to_string(2 * k + 1) + ".0 turn 1 12 over 1.0\n";
  text += "\"\"\"\n";
  for (int c = 0; c < n; ++c) {
    const std::string name = "c" + std::to_string(c);
    text += "[[character]]\nname = \"" + name + "\"\nrig = \"" MARIONETTE_SOURCE_DIR "/config/rigs/" + rigs[c % 3] + ".toml\"\n";
    text += "[[binding]]\ndevice = \"knobs\"\ncontrol = \"encoder 1\"\nmode = \"delta\"\nstep = 3.0\ntarget = \"" + name +
            ".handle." + hands[c % 3] + ".y\"\n";
  }
  const auto path = std::filesystem::temp_directory_path() /
                    ("marionette_bench_cast_" + std::to_string(n) + "_" + std::to_string(threads) + ".toml");
  std::ofstream(path) << text;
  return path.string();
}

void BM_Cast(benchmark::State& state) {
  const char* env = std::getenv("MARIONETTE_BENCH_FRAMES");
  const long frames = env ? std::atol(env) : 600;
  const int n = int(state.range(0)), threads = int(state.range(1));
  for (auto _ : state) {
    mar::RunOptions o;
    o.headless = true;
    o.quiet = true;
    o.frames = frames;
    auto s = mar::LiveShow::load(cast_show(n, threads), o);
    if (!s.ok()) {
      state.SkipWithError(s.error.c_str());
      return;
    }
    (*s.value)->run();
    const auto j = nlohmann::json::parse((*s.value)->stats_json());
    const auto& st = j["stages_us"];
    state.counters["threads"] = (*s.value)->solve_threads();
    state.counters["frame_p50_us"] = st["frame"]["p50"].get<double>();
    state.counters["frame_p99_us"] = st["frame"]["p99"].get<double>();
    state.counters["solve_p50_us"] = st["solve"]["p50"].get<double>();
    state.counters["solve_p99_us"] = st["solve"]["p99"].get<double>();
    state.counters["render_p50_us"] = st["render"]["p50"].get<double>();
    state.counters["render_p99_us"] = st["render"]["p99"].get<double>();
    state.counters["allocs_after_warmup"] = j["heap_allocations_after_warmup"].get<double>();
  }
}
// (characters, threads: 1 = the frame's alone, 0 = the pool's default)
BENCHMARK(BM_Cast)
    ->Args({1, 1})
    ->Args({2, 1})
    ->Args({2, 2})
    ->Args({4, 1})
    ->Args({4, 0})
    ->Args({8, 1})
    ->Args({8, 0})
    ->Args({16, 1})
    ->Args({16, 0})
    ->Iterations(1)
    ->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
