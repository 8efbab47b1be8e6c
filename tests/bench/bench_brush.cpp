// The pen's tools on the figure. The brush of seed 004 (app/loop/brush.h), 60 Hz, headless on the virtual clock,
// side by side in one run: the figure with no brush, with a [[brush]] whose pen never touches
// (its finer feature frame: kSculptSpacing), and brushed — a stroke pushing the cheek out by 25
// units at full pressure, held — and the same stroke as a plain grab of the cheek (mode 3: the
// handle drag the tools' cost stands beside); then a knob swaying the figure. Reports
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
#include <algorithm>
#include <filesystem>
#include <fstream>

namespace {

const mar::Vec2 kCheek(106.5, 96.0), kDrag(-24.0, 6.0);

std::string show(int mode, const mar::Affine2& view) {
  // mode 0: no brush; 1: a brush never touching; 2: brushed; 3: the same stroke a plain grab
  // (the pen drags the cheek's point as a temporary handle: the drag the tools stand beside)
  auto at = [&](const mar::Vec2& p) {
    const mar::Vec2 c = view.apply(p);
    char s[64];
    std::snprintf(s, sizeof s, "%.6f,%.6f", c.x() / 800, c.y() / 600);
    return std::string(s);
  };
  std::string pen = mode >= 2 ? "0.1 hover " + at(kCheek) + "\n0.2 stroke " + at(kCheek) + " " + at(kCheek + kDrag) +
                                    " over 0.5 pressure 1.0\n"
                              : "0.1 leave\n";
  std::string text = "[show]\nrig = \"" MARIONETTE_SOURCE_DIR "/config/rigs/figure.toml\"\nrate = 60\niterations = 10\n"
                     "min_iterations = 10\n[display]\nwidth = 800\nheight = 600\nhud = false\n"
                     "[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\nscript = \"\"\"\n" + pen + "\"\"\"\n"
                     "[[device]]\nname = \"knobs\"\nsim = \"knob_box\"\nscript = \"\"\"\n";
  for (int k = 0; k < 5; ++k)
    text += std::to_string(2 * k + 1) + ".0 turn 1 -12 over 1.0\n" + std::to_string(2 * k + 2) + ".0 turn 1 12 over 1.0\n";
  text += "\"\"\"\n[[binding]]\ndevice = \"knobs\"\ncontrol = \"encoder 1\"\nmode = \"delta\"\nstep = 2.0\ntarget = \"handle.chest.x\"\n";
  if (mode == 1 || mode == 2) text += "[[brush]]\ndevice = \"pen\"\nradius = [12, 40]\nrelease = \"hold\"\n";
  if (mode == 3) text += "[[binding]]\ndevice = \"pen\"\ncontrol = \"pointer\"\ntarget = \"grab\"\narea = \"canvas\"\n";
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
BENCHMARK(BM_Brush)->ArgName("mode")->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Iterations(1)->Unit(benchmark::kMillisecond);

// The drawn curve of seed 001 (app/loop/curve.h) on the figure's neck, face and hair cap (a
// line of action bending right, drawn over 0.6 s and held): the chain's axis from the drawn
// curve and each part's RMS distance from its rest shape laid along the curve (its distortion
// apart from its bend), % of the height, at 1.5 s; the solve's p50 (µs) over 3 s.
void BM_Curve(benchmark::State& state) {
  const std::string text =
      "[show]\nrig = \"" MARIONETTE_SOURCE_DIR "/config/rigs/figure.toml\"\nrate = 60\niterations = 12\nmin_iterations = 12\n"
      "[display]\nwidth = 400\nheight = 560\nhud = false\n[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\nscript = \"\"\"\n"
      "0.1 hover 0.5,0.5\n0.2 stroke 0.5,0.5 0.515,0.43 0.54,0.37 0.575,0.32 0.615,0.285 over 0.6 pressure 0.8\n\"\"\"\n"
      "[[curve]]\ndevice = \"pen\"\nparts = [\"neck\", \"face\", \"hair-cap\"]\nfrom = \"torso\"\nrelease = \"hold\"\n";
  const auto path = std::filesystem::temp_directory_path() / "marionette_bench_curve.toml";
  std::ofstream(path) << text;
  for (auto _ : state) {
    mar::RunOptions o;
    o.headless = true;
    o.quiet = true;
    o.frames = 180;
    auto s = mar::LiveShow::load(path.string(), o);
    if (!s.ok()) {
      state.SkipWithError(s.error.c_str());
      return;
    }
    mar::LiveShow& live = **s.value;
    for (long f = 0; f < 90; ++f) live.frame(int64_t(double(f) * 1e9 / 60));
    const mar::Actor& a = *live.actors()[0];
    const mar::Puppet& p = a.puppet();
    const mar::CurveStage& c = a.curve();
    const auto& ff = *p.feature_frame();
    const mar::Bounds b = p.character.bounds();
    const double h = b.hi.y() - b.lo.y();
    double axis = 0, own = 0, bent = 0, at = 0;
    const mar::ChainGeometry& g = c.chain();
    for (size_t i = 0; i < g.rest.size(); ++i) {
      if (i > 0) at += (g.rest[i] - g.rest[i - 1]).norm();
      const mar::Vec2 q = mar::eval_param(mar::bind_point(ff.frame(), p.character, g.rest[i]), ff.core().vertices());
      axis = std::max(axis, (q - c.curve_at(at)).norm());
    }
    for (int k : g.shapes) {
      const mar::Points& rest = p.character.shapes[size_t(k)].points;
      double sum = 0;
      for (size_t i = 0; i < rest.size(); ++i) sum += (p.shapes[size_t(k)][i] - c.lay(rest[i])).squaredNorm();
      own = std::max(own, std::sqrt(sum / double(std::max<size_t>(1, rest.size()))));
      bent = std::max(bent, mar::rigid_fit_rms(rest, p.shapes[size_t(k)]));
    }
    live.run();
    const auto j = nlohmann::json::parse(live.stats_json());
    state.counters["axis_off_curve_pct"] = 100 * axis / h;
    state.counters["parts_off_laid_pct"] = 100 * own / h;
    state.counters["parts_rigid_rms_pct"] = 100 * bent / h;
    state.counters["soft_targets"] = double(c.vertices().size());
    state.counters["solve_p50_us"] = j["stages_us"]["solve"]["p50"].get<double>();
    state.counters["allocs_after_warmup"] = double(live.allocations_after_warmup());
  }
}
BENCHMARK(BM_Curve)->Iterations(1)->Unit(benchmark::kMillisecond);

// The contour fit (app/loop/contour.h): a stroke redrawing the figure's left cheek 9 units
// fuller, drawn over 0.6 s (the pen covers the figure's drawing: area in its units); at 0.8 s,
// the pen still down, the farthest of the fitted outline vertices from the stroke in canvas px,
// their largest detail (off a smooth line) and the largest move of the parts the stroke did not
// touch, % of the height; the solve's p50 (µs) over 3 s, the fit held after the lift.
void BM_Contour(benchmark::State& state) {
  std::string pts;
  for (int i = 0; i <= 10; ++i) {
    const double a = M_PI * (1.0 + 0.25 * i / 10.0), bulge = 9 * std::sin(M_PI * i / 10.0);
    char b[64];
    std::snprintf(b, sizeof b, " %.6f,%.6f", (150 + (44 + bulge) * std::cos(a)) / 300, (88 - (48 + bulge) * std::sin(a)) / 420);
    pts += b;
  }
  const std::string text =
      "[show]\nrig = \"" MARIONETTE_SOURCE_DIR "/config/rigs/figure.toml\"\nrate = 60\niterations = 12\nmin_iterations = 12\n"
      "[display]\nwidth = 400\nheight = 560\nhud = false\n[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\nscript = \"\"\"\n"
      "0.1 hover" + pts.substr(0, pts.find(' ', 1)) + "\n0.2 stroke" + pts + " over 0.6 pressure 0.8\n\"\"\"\n"
      "[[curve]]\ndevice = \"pen\"\nfit = \"contour\"\nparts = [\"face\"]\nrelease = \"hold\"\narea = [0, 0, 300, 420]\n";
  const auto path = std::filesystem::temp_directory_path() / "marionette_bench_contour.toml";
  std::ofstream(path) << text;
  for (auto _ : state) {
    mar::RunOptions o;
    o.headless = true;
    o.quiet = true;
    o.frames = 180;
    auto s = mar::LiveShow::load(path.string(), o);
    if (!s.ok()) {
      state.SkipWithError(s.error.c_str());
      return;
    }
    mar::LiveShow& live = **s.value;
    for (long f = 0; f < 49; ++f) live.frame(int64_t(double(f) * 1e9 / 60));
    const mar::Actor& a = *live.actors()[0];
    const mar::Puppet& p = a.puppet();
    const mar::ContourStage& c = a.contour();
    const auto v = p.feature_frame()->core().vertices();
    const auto stroke = c.stroke();
    double off = 0, detail = 0, others = 0;
    for (size_t j = 0; j < c.segment().size(); ++j) {
      const mar::Vec2 x = v[size_t(c.segment()[j])];
      double best = 1e300;
      for (size_t i = 0; i + 1 < stroke.size(); ++i) {
        const mar::Vec2 e = stroke[i + 1] - stroke[i];
        const double t = e.squaredNorm() > 0 ? std::clamp((x - stroke[i]).dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
        best = std::min(best, (stroke[i] + t * e - x).norm());
      }
      off = std::max(off, best);
      detail = std::max(detail, c.detail(int(j)).norm());
    }
    const mar::Bounds b = p.character.bounds();
    const double h = b.hi.y() - b.lo.y();
    for (size_t k = 0; k < p.shapes.size(); ++k) {
      const std::string& id = p.character.shapes[k].id;
      if (id == "face" || id.rfind("hair", 0) == 0 || id.rfind("eye", 0) == 0 || id == "mouth" || id == "neck") continue;
      for (size_t i = 0; i < p.shapes[k].size(); ++i) others = std::max(others, (p.shapes[k][i] - p.character.shapes[k].points[i]).norm());
    }
    live.run();
    const auto j = nlohmann::json::parse(live.stats_json());
    state.counters["fitted_vertices"] = double(c.segment().size());
    state.counters["off_stroke_px"] = off * a.px_per_unit;
    state.counters["detail_px"] = detail * a.px_per_unit;
    state.counters["others_off_rest_pct"] = 100 * others / h;
    state.counters["solve_p50_us"] = j["stages_us"]["solve"]["p50"].get<double>();
    state.counters["allocs_after_warmup"] = double(live.allocations_after_warmup());
  }
}
BENCHMARK(BM_Contour)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
