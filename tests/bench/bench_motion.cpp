// Secondary motion (issue: a character that is alive): what one chain step costs, what the
// motion stage costs a frame on the example rigs, and the physics figures README quotes —
// a small-angle pendulum's period, the spring's frequency, the decay per cycle, the same motion
// at 30/60/144/240 Hz frames, 10^6 random jerks. Medians of the benchmark runs.
//   bench_motion [--smoke] [google benchmark flags]
#include "app/loop/physics.h"
#include "app/puppet.h"
#include "median_reporter.h"
#include "motion/chain.h"
#include "../motion/chain_measure.h"

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>

namespace {

using namespace mar;

void BM_chain_step(benchmark::State& st) {
  const int links = int(st.range(0));
  std::vector<Vec2> rest;
  for (int i = 0; i <= links; ++i) rest.emplace_back(3.0 * i, 40.0 * i);
  ChainParams p;
  p.frequency = 2;
  p.damping = 0.15;
  Chain c(rest, p);
  MotionWorld w;
  w.gravity = {0, 980};
  double t = 0;
  for (auto _ : st) {
    t += measure::kStep;
    c.advance(measure::kStep, measure::kStep, Vec2(30 * std::sin(3 * t), 10 * std::cos(2 * t)), 0.2 * std::sin(t), w);
    benchmark::DoNotOptimize(c.ends().data());
  }
}
BENCHMARK(BM_chain_step)->Arg(1)->Arg(3)->Arg(8)->Repetitions(5)->ReportAggregatesOnly(true);

const char* kRigs[] = {"figure", "koi", "butterfly", "candle"};

void BM_motion_stage(benchmark::State& st) {
  const std::string rig = (std::filesystem::path(MARIONETTE_SOURCE_DIR) / "config/rigs" / (std::string(kRigs[st.range(0)]) + ".toml")).string();
  auto p = load_puppet("", rig, "", true);
  if (!p.ok()) {
    st.SkipWithError(p.error.c_str());
    return;
  }
  PhysicsStage stage;
  stage.prepare(**p.value, ShowPhysics{});
  std::vector<Vec2> targets = (*p.value)->rest_targets();
  for (auto _ : st) {
    stage.step(1.0 / 60, **p.value, targets);  // a 60 Hz frame: two steps of every chain
    benchmark::DoNotOptimize(targets.data());
  }
  st.counters["chains"] = double(stage.size());
}
BENCHMARK(BM_motion_stage)->DenseRange(0, 3)->Repetitions(5)->ReportAggregatesOnly(true);

}  // namespace

int main(int argc, char** argv) {
  bool smoke = false;
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--smoke") == 0) smoke = true;
  std::vector<char*> args;
  for (int i = 0; i < argc; ++i)
    if (std::strcmp(argv[i], "--smoke") != 0) args.push_back(argv[i]);
  static char min_time[] = "--benchmark_min_time=0.01";
  if (smoke) args.push_back(min_time);
  int n = int(args.size());
  benchmark::Initialize(&n, args.data());
  benchmark::ConsoleReporter console;
  bench::Collector collector;
  bench::Tee tee(&console, &collector);
  benchmark::RunSpecifiedBenchmarks(&tee);
  benchmark::Shutdown();

  std::printf("\ncost (median)\n");
  for (int links : {1, 3, 8}) {
    const double us = bench::median_us(collector, "BM_chain_step/" + std::to_string(links) + "/");
    std::printf("  a chain of %d link%s, one step:     %7.3f us (%.3f us a link)\n", links, links > 1 ? "s" : " ", us, us / links);
  }
  for (int r = 0; r < 4; ++r) {
    const double us = bench::median_us(collector, "BM_motion_stage/" + std::to_string(r) + "/");
    std::printf("  the motion stage, %-9s a 60 Hz frame: %7.3f us\n", kRigs[r], us);
  }
  const double L = 100, g = 980, T = 2 * M_PI * std::sqrt(L / g), Tm = measure::pendulum_period(L, g);
  std::printf("\nphysics (120 Hz steps)\n");
  std::printf("  small-angle pendulum period   %.4f s   theory 2 pi sqrt(L/g) %.4f s   %+.2f%%\n", Tm, T, 100 * (Tm / T - 1));
  const double fa = measure::spring_frequency(2), fl = measure::spring_length_frequency(3);
  std::printf("  angular spring set 2 Hz        %.4f Hz   %+.2f%%\n", fa, 100 * (fa / 2 - 1));
  std::printf("  spring length set 3 Hz         %.4f Hz   %+.2f%%\n", fl, 100 * (fl / 3 - 1));
  for (double z : {0.05, 0.1, 0.2}) {
    const double want = std::exp(-2 * M_PI * z / std::sqrt(1 - z * z)), got = measure::decay_per_cycle(z);
    std::printf("  damping %.2f: amplitude x%.4f a cycle   theory x%.4f   %+.2f%%\n", z, got, want, 100 * (got / want - 1));
  }
  for (int rate : {30, 60, 144})
    std::printf("  %3d Hz frames vs 240 Hz: RMS %.3f%% of the chain's length\n", rate, measure::frame_rate_rms_pct(rate));
  const long jerks = smoke ? 20000 : 1000000;
  for (ChainParams::Model m : {ChainParams::Pendulum, ChainParams::Spring}) {
    const measure::Jerks j = measure::random_jerks(m, jerks);
    std::printf("  %ld random jerks, %-8s: %ld non-finite, fastest end %.1f units/s (limit 900)\n", jerks,
                m == ChainParams::Spring ? "spring" : "pendulum", j.bad, j.fastest);
    if (j.bad > 0 || j.fastest > 900 * 1.001) return 1;
  }
  return 0;
}
