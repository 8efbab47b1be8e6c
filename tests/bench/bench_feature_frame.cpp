// Feature-frame manipulation costs, like seed 000 Table 1, for the example characters and
// a generated multi-element character of about 2,000 shape vertices:
//   PRE  prepare (factorisation) for the rig's handle set
//   SOL  one live frame: 12 iterations warm-started from the previous frame's pose
//   REC  reconstruction of every shape vertex from the frame (parametric coordinates)
//   in-betweens: key-pose interpolation (seed 000 §5) between two of four key poses plus
//                reconstruction, per second; and a four-key blend per live frame
// Plus, for the generated character, CGAL's Surface_mesh_deformation (ARAP, same handles,
// 12 iterations) on its constrained triangulation, and the time ratio.
// Prints a table and writes bench_feature_frame.json (or the path in MARIONETTE_BENCH_JSON).
#include "app/puppet.h"
#include "character/load.h"
#include "geom/triangulate.h"
#include "interp/interpolation.h"

#include <benchmark/benchmark.h>

#include "cgal_arap.h"
#include "median_reporter.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>

namespace {

using Clock = std::chrono::steady_clock;

struct Case {
  std::string name;
  mar::Character character;
  mar::FeatureFrame frame;
  std::vector<mar::Vec2> handle_rest;
  std::vector<mar::ShapeParam> bindings;
};

// A caterpillar of 20 overlapping wobbly segments (closed, 80 vertices each) with two
// open legs each (10 vertices): 1,600 + 400 = 2,000 shape vertices, 60 sub-shapes.
mar::Character generated_character() {
  mar::Character ch;
  ch.width = 1400;
  ch.height = 400;
  ch.layers = {"body"};
  for (int s = 0; s < 20; ++s) {
    const double cx = 80 + s * 62, cy = 200 + 30 * std::sin(s * 0.5);
    mar::SubShape seg;
    seg.id = "segment-" + std::to_string(s);
    for (int k = 0; k < 80; ++k) {
      const double a = k * 2 * M_PI / 80, r = 45 + 4 * std::sin(5 * a);
      seg.points.emplace_back(cx + r * std::cos(a), cy + 0.8 * r * std::sin(a));
    }
    seg.contours = {{0, 80, true}};
    seg.fill.enabled = true;
    ch.shapes.push_back(seg);
    for (int side : {-1, 1}) {
      mar::SubShape leg;
      leg.id = "leg-" + std::to_string(s) + (side < 0 ? "a" : "b");
      for (int k = 0; k < 10; ++k) leg.points.emplace_back(cx + side * 8 + k * 1.5 * side, cy + 30 + k * 8);
      leg.contours = {{0, 10, false}};
      leg.stroke.enabled = true;
      ch.shapes.push_back(leg);
    }
  }
  return ch;
}

Case make_case(const std::string& name, mar::Character ch, std::vector<mar::Vec2> handles,
               const mar::FrameOptions& o = mar::default_frame_options()) {
  Case c;
  c.name = name;
  c.character = std::move(ch);
  mar::refine_for_frame(c.character, o);
  c.frame = mar::build_feature_frame(c.character, o);
  c.handle_rest = std::move(handles);
  for (const mar::Vec2& p : c.handle_rest) c.bindings.push_back(mar::bind_point(c.frame, c.character, p));
  return c;
}

// MARIONETTE_BENCH_ANDERSON=m overrides the Anderson history (0: the plain alternation).
mar::SolverWeights bench_weights() {
  mar::SolverWeights w;
  if (const char* m = std::getenv("MARIONETTE_BENCH_ANDERSON")) w.anderson = std::atoi(m);
  return w;
}

std::vector<Case>& cases() {
  static std::vector<Case> all = [] {
    std::vector<Case> v;
    for (const char* name : {"butterfly", "figure", "koi"}) {
      auto rig = mar::load_rig(std::string(MARIONETTE_SOURCE_DIR) + "/config/rigs/" + name + ".toml");
      auto ch = mar::load_character(rig.value->character_path());
      std::vector<mar::Vec2> hs;
      for (const mar::RigHandle& h : rig.value->handles) hs.push_back(h.rest);
      v.push_back(make_case(name, std::move(*ch.value), hs, mar::frame_options_from_rig(*rig.value)));
    }
    v.push_back(make_case("generated-2000", generated_character(),
                          {{80, 200}, {700, 200}, {1258, 200}, {390, 160}, {1010, 260}}));
    return v;
  }();
  return all;
}

// Targets for frame k of a slow wave: the first handle sweeps a circle, others hold.
std::vector<mar::Vec2> targets_at(const Case& c, int k) {
  std::vector<mar::Vec2> t = c.handle_rest;
  t[0] += 25.0 * mar::Vec2(std::cos(k * 0.05) - 1, std::sin(k * 0.05));
  return t;
}

void BM_prepare(benchmark::State& st) {
  const Case& c = cases()[static_cast<size_t>(st.range(0))];
  for (auto _ : st) {
    mar::FeatureFrameSolver s;
    s.prepare(c.frame, c.bindings, bench_weights());
    benchmark::DoNotOptimize(s.vertex_count());
  }
  st.SetLabel(c.name);
}

void BM_solve_frame(benchmark::State& st) {
  const Case& c = cases()[static_cast<size_t>(st.range(0))];
  mar::FeatureFrameSolver s;
  s.prepare(c.frame, c.bindings, bench_weights());
  int k = 0;
  for (auto _ : st) {
    const std::vector<mar::Vec2> t = targets_at(c, k++);
    s.solve(t, 12);
    benchmark::DoNotOptimize(s.vertices().data());
  }
  st.SetLabel(c.name);
  st.counters["nnz(L)"] = static_cast<double>(s.factor_nonzeros());
  st.counters["unknowns"] = static_cast<double>(2 * s.vertex_count());
}

void BM_reconstruct(benchmark::State& st) {
  const Case& c = cases()[static_cast<size_t>(st.range(0))];
  mar::FeatureFrameSolver s;
  s.prepare(c.frame, c.bindings, bench_weights());
  s.solve(targets_at(c, 10), 12);
  std::vector<mar::Points> shapes;
  for (const mar::SubShape& sh : c.character.shapes) shapes.push_back(sh.points);
  for (auto _ : st) {
    mar::reconstruct_shapes(c.frame, s.vertices(), shapes);
    benchmark::DoNotOptimize(shapes.data());
  }
  st.SetLabel(c.name);
}

// Key poses for the interpolation benches: four poses of the slow wave, each solved from rest.
mar::KeyInterpolator& interpolator(size_t ci) {
  static std::vector<std::unique_ptr<mar::KeyInterpolator>> all(cases().size());
  if (!all[ci]) {
    const Case& c = cases()[ci];
    all[ci] = std::make_unique<mar::KeyInterpolator>();
    std::string err;
    if (!all[ci]->prepare(c.frame, &err)) std::abort();
    for (int k : {30, 60, 90, 120}) {
      mar::FeatureFrameSolver s;
      s.prepare(c.frame, c.bindings, bench_weights());
      s.solve(targets_at(c, k), 100);
      all[ci]->add_key(s.vertices());
    }
  }
  return *all[ci];
}

// One in-between: interpolate the frame between two keys and reconstruct every shape vertex.
void BM_inbetween(benchmark::State& st) {
  const Case& c = cases()[static_cast<size_t>(st.range(0))];
  mar::KeyInterpolator& in = interpolator(static_cast<size_t>(st.range(0)));
  mar::Points v(c.frame.rest.size());
  std::vector<mar::Points> shapes;
  for (const mar::SubShape& sh : c.character.shapes) shapes.push_back(sh.points);
  int k = 0;
  for (auto _ : st) {
    in.morph(0, 3, (k++ % 100) / 99.0, v);
    mar::reconstruct_shapes(c.frame, v, shapes);
    benchmark::DoNotOptimize(shapes.data());
  }
  st.SetLabel(c.name + " (" + std::to_string(in.triangles()) + " triangles)");
}

// A live frame of four keys blended (four knobs), the frame only.
void BM_blend4(benchmark::State& st) {
  const Case& c = cases()[static_cast<size_t>(st.range(0))];
  mar::KeyInterpolator& in = interpolator(static_cast<size_t>(st.range(0)));
  mar::Points v(c.frame.rest.size());
  std::vector<double> w{0.2, 0.3, 0.1, 0.4};
  int k = 0;
  for (auto _ : st) {
    w[0] = 0.5 + 0.5 * std::sin(0.01 * k++);
    in.blend(w, v);
    benchmark::DoNotOptimize(v.data());
  }
  st.SetLabel(c.name);
}

BENCHMARK(BM_prepare)->DenseRange(0, 3)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_inbetween)->DenseRange(0, 3)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_blend4)->DenseRange(0, 3)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_solve_frame)->DenseRange(0, 3)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_reconstruct)->DenseRange(0, 3)->Unit(benchmark::kMicrosecond);

// --- CGAL ARAP on the generated character's constrained triangulation ---------------
bench::CgalArap& cgal_setup() {
  static bench::CgalArap s = [] {
    const Case& c = cases()[3];
    mar::Points pts;
    std::vector<mar::Ring> rings;
    std::vector<char> closed;
    for (const mar::SubShape& sh : c.character.shapes) {
      for (const mar::Contour& ct : sh.contours) {
        rings.push_back({static_cast<int>(pts.size()) + ct.begin, ct.count});
        closed.push_back(ct.closed ? 1 : 0);
      }
      pts.insert(pts.end(), sh.points.begin(), sh.points.end());
    }
    const mar::HullMesh hm = mar::triangulate_hull(pts, rings, closed);
    std::vector<std::array<int, 3>> tris;
    for (size_t t = 0; t + 2 < hm.triangles.size(); t += 3) tris.push_back({hm.triangles[t], hm.triangles[t + 1], hm.triangles[t + 2]});
    return bench::CgalArap(hm.vertices, tris, c.handle_rest);
  }();
  return s;
}

void BM_cgal_arap_frame(benchmark::State& st) {
  bench::CgalArap& s = cgal_setup();
  const Case& c = cases()[3];
  int k = 0;
  for (auto _ : st) s.frame(targets_at(c, k++), 12);
  st.SetLabel("generated-2000 (" + std::to_string(s.vertices()) + " vertices, " + std::to_string(s.faces()) + " faces)");
}
BENCHMARK(BM_cgal_arap_frame)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::ConsoleReporter console;
  bench::Collector collect;
  bench::Tee tee(&console, &collect);
  benchmark::RunSpecifiedBenchmarks(&tee);
  auto get = [&](const std::string& n) {
    for (const auto& [k, v] : collect.median_us) {
      if (k.rfind(n, 0) == 0) return v;
    }
    return -1.0;
  };
  std::printf("\nTable 1 (this machine; times in ms, medians)\n");
  std::printf("%-16s %7s %-22s %6s %8s %8s %8s\n", "character", "S.VER", "F.LINES (sewing, user)", "F.VER", "PRE", "SOL", "REC");
  const char* json_path = std::getenv("MARIONETTE_BENCH_JSON");
  std::ofstream json(json_path ? json_path : "bench_feature_frame.json");
  json << "{\n  \"rows\": [\n";
  for (size_t i = 0; i < cases().size(); ++i) {
    const Case& c = cases()[i];
    const std::string idx = "/" + std::to_string(i);
    const double pre = get("BM_prepare" + idx) / 1000, sol = get("BM_solve_frame" + idx) / 1000,
                 rec = get("BM_reconstruct" + idx) / 1000;
    const std::string lines = std::to_string(c.frame.lines.size()) + " (" + std::to_string(c.frame.sewing_lines) + ", " +
                              std::to_string(c.frame.user_sewing_lines) + ")";
    std::printf("%-16s %7zu %-22s %6zu %8.4f %8.4f %8.4f\n", c.name.c_str(), c.frame.shape_vertices, lines.c_str(),
                c.frame.rest.size(), pre, sol, rec);
    json << "    {\"character\": \"" << c.name << "\", \"S.VER\": " << c.frame.shape_vertices
         << ", \"F.LINES\": " << c.frame.lines.size() << ", \"sewing_total\": " << c.frame.sewing_lines
         << ", \"sewing_user\": " << c.frame.user_sewing_lines << ", \"F.VER\": " << c.frame.rest.size()
         << ", \"PRE_ms\": " << pre << ", \"SOL_ms\": " << sol << ", \"REC_ms\": " << rec << "}"
         << (i + 1 < cases().size() ? "," : "") << "\n";
  }
  std::printf("\nKey-pose interpolation (seed 000 §5): in-betweens per second (interpolate + reconstruct) and a "
              "four-key blend per frame\n");
  for (size_t i = 0; i < cases().size(); ++i) {
    const std::string idx = "/" + std::to_string(i);
    const double ib = get("BM_inbetween" + idx), b4 = get("BM_blend4" + idx);
    std::printf("%-16s %10.0f in-betweens/s %8.2f us per 4-key blend\n", cases()[i].name.c_str(), ib > 0 ? 1e6 / ib : 0.0, b4);
  }
  const double cgal = get("BM_cgal_arap_frame") / 1000, ours = get("BM_solve_frame/3") / 1000;
  std::printf("\nCGAL Surface_mesh_deformation (ARAP, 12 iterations) on generated-2000's triangulation "
              "(%zu vertices): %.3f ms per frame, preprocess %.3f ms; feature frame %.4f ms: %.0fx faster\n",
              cgal_setup().vertices(), cgal, cgal_setup().preprocess_ms(), ours, ours > 0 ? cgal / ours : 0.0);
  json << "  ],\n  \"cgal_arap\": {\"vertices\": " << cgal_setup().vertices() << ", \"faces\": " << cgal_setup().faces()
       << ", \"frame_ms\": " << cgal << ", \"preprocess_ms\": " << cgal_setup().preprocess_ms()
       << ", \"ratio_vs_feature_frame\": " << (ours > 0 ? cgal / ours : 0.0) << "}\n}\n";
  benchmark::Shutdown();
  return 0;
}
