// The brush of seed 004 (app/loop/brush.h) on the figure, 60 Hz, headless on the virtual clock,
// side by side in one run: the figure with no brush, with a [[brush]] whose pen never touches
// (its finer feature frame: kBrushSpacing), and brushed — a stroke pushing the cheek out by 25
// units at full pressure, held — then a knob swaying the figure with the stroke held. Reports
// the solve's p50/p99 (µs), the brushed outline's worst distance from the Gaussian profile (% of
// the drag), the largest distance from rest (% of the height) of the parts away from the stroke
// (torso, arms, legs) and of those sewn to the face inside the brush (hair cap, neck), the
// frame's vertices, and allocations after warm-up.
#include "app/live.h"

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace {

const mar::Vec2 kCheek(106.5, 96.0), kDrag(-24.0, 6.0);

std::string show(int mode, const mar::Affine2& view) {
  // mode 0: no brush; 1: a brush never touching; 2: brushed
  auto at = [&](const mar::Vec2& p) {
    const mar::Vec2 c = view.apply(p);
    char s[64];
    std::snprintf(s, sizeof s, "%.6f,%.6f", c.x() / 800, c.y() / 600);
    return std::string(s);
  };
  std::string pen = mode == 2 ? "0.1 hover " + at(kCheek) + "\n0.2 stroke " + at(kCheek) + " " + at(kCheek + kDrag) +
                                    " over 0.5 pressure 1.0\n"
                              : "0.1 leave\n";
  std::string text = "[show]\nrig = \"" MARIONETTE_SOURCE_DIR "/config/rigs/figure.toml\"\nrate = 60\niterations = 10\n"
                     "min_iterations = 10\n[display]\nwidth = 800\nheight = 600\nhud = false\n"
                     "[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\nscript = \"\"\"\n" + pen + "\"\"\"\n"
                     "[[device]]\nname = \"knobs\"\nsim = \"knob_box\"\nscript = \"\"\"\n";
  for (int k = 0; k < 5; ++k)
    text += std::to_string(2 * k + 1) + ".0 turn 1 -12 over 1.0\n" + std::to_string(2 * k + 2) + ".0 turn 1 12 over 1.0\n";
  text += "\"\"\"\n[[binding]]\ndevice = \"knobs\"\ncontrol = \"encoder 1\"\nmode = \"delta\"\nstep = 2.0\ntarget = \"handle.chest.x\"\n";
  if (mode > 0) text += "[[brush]]\ndevice = \"pen\"\nradius = [12, 40]\nrelease = \"hold\"\n";
  const auto path = std::filesystem::temp_directory_path() / ("marionette_bench_brush_" + std::to_string(mode) + ".toml");
  std::ofstream(path) << text;
  return path.string();
}

void BM_Brush(benchmark::State& state) {
  const int mode = int(state.range(0));
  mar::RunOptions o;
  o.headless = true;
  o.quiet = true;
  auto probe = mar::LiveShow::load(show(0, mar::Affine2{}), o);
  if (!probe.ok()) {
    state.SkipWithError(probe.error.c_str());
    return;
  }
  const mar::Affine2 view = (*probe.value)->actors()[0]->view;
  for (auto _ : state) {
    o.frames = 660;  // 11 s: the stroke, then the sway
    auto s = mar::LiveShow::load(show(mode, view), o);
    if (!s.ok()) {
      state.SkipWithError(s.error.c_str());
      return;
    }
    mar::LiveShow& live = **s.value;
    const mar::Actor& a = *live.actors()[0];
    const mar::Puppet& p = a.puppet();
    double profile = 0;
    {  // measured at 0.9 s (the stroke held, before the sway); with no stroke, what moves without one
      for (long f = 0; f < 54; ++f) live.frame(int64_t(double(f) * 1e9 / 60));
      const mar::BrushStage& br = a.brush();
      const auto& ff = *p.feature_frame();
      const double sigma = br.radius() / 3;
      for (const mar::BrushStage::Point& pt : br.points()) {
        const double d = std::exp(-pt.s * pt.s / (2 * sigma * sigma));
        const mar::Vec2 moved = ff.core().vertices()[size_t(pt.v)] - ff.frame().rest[size_t(pt.v)];
        profile = std::max(profile, (moved - d * kDrag).norm() / kDrag.norm());
      }
      // The parts away from the stroke (the torso, the arms, the legs) and those sewn to the
      // face where it was brushed (the hair cap over the cheek's top, the neck under the chin).
      double far = 0, near = 0;
      for (size_t k = 0; k < p.shapes.size(); ++k) {
        const std::string& id = p.character.shapes[k].id;
        const bool away = id == "torso" || id.rfind("arm", 0) == 0 || id.rfind("leg", 0) == 0;
        const bool sewn = id == "hair-cap" || id == "neck";
        if (!away && !sewn) continue;
        double part = 0;
        for (size_t i = 0; i < p.shapes[k].size(); ++i) part = std::max(part, (p.shapes[k][i] - p.character.shapes[k].points[i]).norm());
        if (std::getenv("MARIONETTE_BENCH_VERBOSE")) std::fprintf(stderr, "%s %.3f\n", id.c_str(), part);
        (away ? far : near) = std::max(away ? far : near, part);
      }
      const mar::Bounds b = p.character.bounds();
      const double h = b.hi.y() - b.lo.y();
      if (mode == 2) state.counters["profile_pct"] = 100 * profile;
      state.counters["away_off_rest_pct"] = 100 * far / h;
      state.counters["sewn_off_rest_pct"] = 100 * near / h;
    }
    live.run();
    const auto j = nlohmann::json::parse(live.stats_json());
    state.counters["solve_p50_us"] = j["stages_us"]["solve"]["p50"].get<double>();
    state.counters["solve_p99_us"] = j["stages_us"]["solve"]["p99"].get<double>();
    state.counters["frame_vertices"] = double(p.feature_frame()->frame().rest.size());
    state.counters["allocs_after_warmup"] = double(live.allocations_after_warmup());
  }
}
BENCHMARK(BM_Brush)->ArgName("mode")->Arg(0)->Arg(1)->Arg(2)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
