// The rigid grid's costs like seed 003 Table 1, on a bottle like its Fig. 3 (d-g) with about
// 2,256 nodes, at region half-widths w = 1, 6, 9:
//   PRE   prepare: grid, curves, triangulation, regions, factorisation
//   OPT1  one live frame: 8 local/global iterations warm-started, with the fast summation
//   OPT2  the same without it (every region member visited)
// Same run: CGAL's Surface_mesh_deformation (ARAP, 8 iterations) on the rigid grid's own
// triangle mesh with the same handles, and our outline ARAP baseline on the bottle, with the
// ratios to OPT1; and the region sums alone (one gather and one scatter), fast and naive. And
// a frame with the bottle's points (solve + shape_points, w = 3) with the neck a [[bone]]
// turning whole at the shoulders and without, side by side; and a frame of a fleece drawn in
// 11,600 points, its contours thinned to about a cell and every point a node. Prints a table and writes
// bench_rigid_grid.json (or MARIONETTE_BENCH_JSON).
#include "solve/arap.h"
#include "solve/rigid_grid.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>

#include "cgal_arap.h"
#include "median_reporter.h"

namespace {

constexpr int kIterations = 8;
constexpr size_t kTargetNodes = 2256;  // seed 003 Table 1, Fig. 3 (d-g)
const int kWidths[] = {1, 3, 6, 9};  // the seed's 1, 6, 9 and this project's default 3

// A bottle 240 wide and 520 tall: a neck 80 wide, round shoulders, rounded base corners.
mar::Character bottle() {
  mar::Points p;
  auto arc = [&](mar::Vec2 c, double rx, double ry, double a0, double a1) {
    const int n = int(std::ceil(std::abs(a1 - a0) * std::max(rx, ry) / 4));
    for (int k = 0; k <= n; ++k) {
      const double a = a0 + (a1 - a0) * k / n;
      p.push_back(c + mar::Vec2(rx * std::cos(a), ry * std::sin(a)));
    }
  };
  auto line = [&](mar::Vec2 a, mar::Vec2 b) {
    const int n = int(std::ceil((b - a).norm() / 4));
    for (int k = 0; k < n; ++k) p.push_back(a + (b - a) * (double(k) / n));
  };
  line({80, 0}, {160, 0});
  line({160, 0}, {160, 60});
  arc({240, 60}, 80, 100, M_PI, M_PI / 2);  // right shoulder, out to the body's side
  line({240, 160}, {240, 480});
  arc({200, 480}, 40, 40, 0, M_PI / 2);
  line({200, 520}, {40, 520});
  arc({40, 480}, 40, 40, M_PI / 2, M_PI);
  line({0, 480}, {0, 160});
  arc({0, 60}, 80, 100, M_PI / 2, 0);  // left shoulder, in to the neck
  line({80, 60}, {80, 0});
  mar::Character ch;
  mar::SubShape s;
  s.id = "bottle";
  s.points = p;
  s.contours.push_back({0, int(p.size()), true});
  s.fill.enabled = true;
  ch.shapes.push_back(s);
  ch.width = 240;
  ch.height = 520;
  return ch;
}

const std::vector<mar::Vec2> kHandles{{30, 500}, {210, 500}, {120, 15}};

// Frame k of a live drag: the neck pulled to the right and down and back.
std::vector<mar::Vec2> targets_at(int k) {
  const double f = 0.5 - 0.5 * std::cos(k * 0.05);
  return {kHandles[0], kHandles[1], kHandles[2] + mar::Vec2(150 * f, 60 * f)};
}

double g_cell = 0;  // chosen so the bottle has about kTargetNodes nodes

// every = true: a region centred on every grid node, as seed 003 writes it (stride 1); false: the
// default stride (about w / 2).
mar::Rig rig(int w, bool every) {
  mar::Rig r = mar::default_rig();
  r.solver = "rigid_grid";
  r.grid_cell = g_cell;
  r.grid_half_width = w;
  r.grid_stride = every ? 1 : 0;
  return r;
}

struct Prepared {
  mar::Character ch = bottle();
  mar::RigidGrid s;
};
std::unique_ptr<Prepared>& prepared(int w, bool every = false) {
  static std::unique_ptr<Prepared> p[2][16];
  std::unique_ptr<Prepared>& q = p[every ? 1 : 0][w];
  if (!q) {
    q = std::make_unique<Prepared>();
    std::string err;
    if (!q->s.prepare(q->ch, rig(w, every), kHandles, mar::SolverWeights{}, &err)) {
      std::fprintf(stderr, "bench_rigid_grid: %s\n", err.c_str());
      std::exit(2);
    }
  }
  return q;
}

void BM_pre(benchmark::State& st) {
  const int w = int(st.range(0));
  for (auto _ : st) {
    mar::Character ch = bottle();
    mar::RigidGrid s;
    std::string err;
    benchmark::DoNotOptimize(s.prepare(ch, rig(w, st.range(1) != 0), kHandles, mar::SolverWeights{}, &err));
  }
}

void BM_opt(benchmark::State& st) {
  const int w = int(st.range(0));
  mar::RigidGrid& s = prepared(w, st.range(2) != 0)->s;
  s.set_fast_summation(st.range(1) != 0);
  s.reset_to_rest();
  int k = 0;
  for (auto _ : st) {
    s.solve(targets_at(k++), kIterations);
    benchmark::DoNotOptimize(s.nodes().data());
  }
  s.set_fast_summation(true);
}

// The region sums alone (one gather over every region and one scatter back, one channel):
// with the fast summation their cost does not depend on w.
void BM_sums(benchmark::State& st) {
  const int w = int(st.range(0));
  const bool fast = st.range(1) != 0;
  const mar::RigidGrid& s = prepared(w)->s;
  std::vector<double> f(s.rest().size(), 1.0), r(s.regions()), back(s.rest().size());
  for (size_t i = 0; i < f.size(); ++i) f[i] = s.rest()[i].x();
  for (auto _ : st) {
    s.region_sums(f, r, fast);
    s.region_scatter(r, back, fast);
    benchmark::DoNotOptimize(back.data());
  }
}

void BM_cgal_arap(benchmark::State& st) {
  const int w = int(st.range(0));
  const mar::RigidGrid& s = prepared(w)->s;
  bench::CgalArap arap(s.rest(), s.mesh_triangles(), kHandles);
  int k = 0;
  for (auto _ : st) arap.frame(targets_at(k++), kIterations);
}

// One frame with the shape's points, w = 3: the neck bent by the grid (0) or turning whole as a
// [[bone]] about the shoulders (1).
void BM_frame(benchmark::State& st) {
  mar::Character ch = bottle();
  mar::Rig r = rig(3, false);
  r.handles = {{"left", kHandles[0]}, {"right", kHandles[1]}, {"neck", kHandles[2]}};
  if (st.range(0)) {
    mar::RigBone b;
    b.handle = "neck", b.at = mar::Vec2(120, 60), b.axis = {{120, 5}, {120, 60}}, b.radius = {40, 40};
    r.bones = {b};
  }
  mar::RigidGrid s;
  std::string err;
  if (!s.prepare(ch, r, kHandles, mar::SolverWeights{}, &err)) st.SkipWithError(err.c_str());
  std::vector<mar::Points> out{ch.shapes[0].points};
  int k = 0;
  for (auto _ : st) {
    s.solve(targets_at(k++), kIterations);
    s.shape_points(out);
    benchmark::DoNotOptimize(out[0].data());
  }
}

// A fleece: a body whose rim curls 60 times, with 40 curls of wool on it, each flattened the way
// an editor's curves are (a point every unit or so: 11,600 points), at the default cell.
mar::Character fleece() {
  mar::Character ch;
  auto ring = [&](mar::Vec2 c, double r, double wave, int curls, int n, const std::string& id) {
    mar::SubShape s;
    s.id = id;
    for (int k = 0; k < n; ++k) {
      const double a = 2 * M_PI * k / n, rr = r + wave * std::sin(curls * a);
      s.points.push_back(c + mar::Vec2(rr * std::cos(a), rr * std::sin(a)));
    }
    s.contours.push_back({0, n, true});
    s.fill.enabled = true;
    ch.shapes.push_back(s);
  };
  ring({300, 250}, 220, 10, 60, 1600, "body");
  for (int k = 0; k < 40; ++k) {
    const double a = 2 * M_PI * k / 40, r = 60 + 100 * ((k * 7) % 10) / 10.0;
    ring(mar::Vec2(300, 250) + r * mar::Vec2(std::cos(a), std::sin(a)), 24, 4, 8, 250, "curl-" + std::to_string(k));
  }
  ch.width = 600;
  ch.height = 500;
  return ch;
}
const std::vector<mar::Vec2> kFleeceHandles{{120, 250}, {480, 250}, {300, 60}};

// One frame of the fleece (solve + shape_points, w = 3): its contours thinned to about a cell
// between nodes (0) or every drawn point a node (1).
void BM_fleece(benchmark::State& st) {
  mar::Character ch = fleece();
  mar::Rig r = mar::default_rig();
  r.solver = "rigid_grid";
  r.handles = {{"left", kFleeceHandles[0]}, {"right", kFleeceHandles[1]}, {"top", kFleeceHandles[2]}};
  mar::RigidGrid s;
  s.keep_every_contour_point(st.range(0) != 0);
  std::string err;
  if (!s.prepare(ch, r, kFleeceHandles, mar::SolverWeights{}, &err)) st.SkipWithError(err.c_str());
  std::vector<mar::Points> out;
  for (const mar::SubShape& sh : ch.shapes) out.push_back(sh.points);
  int k = 0;
  for (auto _ : st) {
    const double f = 0.5 - 0.5 * std::cos(k++ * 0.05);
    const std::vector<mar::Vec2> t{kFleeceHandles[0], kFleeceHandles[1], kFleeceHandles[2] + mar::Vec2(120 * f, 40 * f)};
    s.solve(t, kIterations);
    s.shape_points(out);
    benchmark::DoNotOptimize(out[0].data());
  }
  st.counters["nodes"] = double(s.grid_nodes() + s.boundary_nodes() + s.free_vertices());
}

void BM_outline_arap(benchmark::State& st) {
  mar::Character ch = bottle();
  mar::OutlineArap s;
  std::string err;
  mar::Rig r = mar::default_rig();
  r.solver = "arap";
  if (!s.prepare(ch, r, kHandles, mar::SolverWeights{}, &err)) st.SkipWithError(err.c_str());
  int k = 0;
  for (auto _ : st) s.solve(targets_at(k++), kIterations);
}

}  // namespace

int main(int argc, char** argv) {
  // The cell that gives the bottle about kTargetNodes grid + boundary nodes.
  double best = 1e300;
  for (double cell = 3.0; cell <= 8.0; cell += 0.125) {
    mar::Character ch = bottle();
    mar::RigidGrid s;
    mar::Rig r = mar::default_rig();
    r.grid_cell = cell;
    r.grid_half_width = 1;
    std::string err;
    if (!s.prepare(ch, r, kHandles, mar::SolverWeights{}, &err)) continue;
    const double d = std::abs(double(s.grid_nodes() + s.boundary_nodes()) - double(kTargetNodes));
    if (d < best) best = d, g_cell = cell;
  }
  for (int w : kWidths) {
    benchmark::RegisterBenchmark(("PRE/w:" + std::to_string(w)).c_str(), BM_pre)->Args({w, 0})->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("OPT1/w:" + std::to_string(w)).c_str(), BM_opt)->Args({w, 1, 0})->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("OPT2/w:" + std::to_string(w)).c_str(), BM_opt)->Args({w, 0, 0})->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("PRE_every/w:" + std::to_string(w)).c_str(), BM_pre)->Args({w, 1})->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("OPT1_every/w:" + std::to_string(w)).c_str(), BM_opt)
        ->Args({w, 1, 1})
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("CGAL_ARAP/w:" + std::to_string(w)).c_str(), BM_cgal_arap)->Arg(w)->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("SUMS_fast/w:" + std::to_string(w)).c_str(), BM_sums)->Args({w, 1})->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("SUMS_naive/w:" + std::to_string(w)).c_str(), BM_sums)->Args({w, 0})->Unit(benchmark::kMicrosecond);
  }
  benchmark::RegisterBenchmark("OUTLINE_ARAP", BM_outline_arap)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("FRAME_grid", BM_frame)->Arg(0)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("FRAME_bone", BM_frame)->Arg(1)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("FLEECE_thinned", BM_fleece)->Arg(0)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("FLEECE_every_point", BM_fleece)->Arg(1)->Unit(benchmark::kMillisecond);
  benchmark::Initialize(&argc, argv);
  benchmark::ConsoleReporter console;
  bench::Collector collect;
  bench::Tee tee(&console, &collect);
  benchmark::RunSpecifiedBenchmarks(&tee);
  const double outline = bench::median_us(collect, "OUTLINE_ARAP") / 1000;
  std::printf("\nseed 003 Table 1 for the bottle (cell %.3f; ms, medians; OPT = one frame of %d iterations)\n", g_cell,
              kIterations);
  std::printf("s: region stride (default); 'every': a region on every grid node (stride 1, seed 003 as written)\n");
  std::printf("%6s %6s %3s %3s %9s %9s %9s %7s %10s %9s %11s %10s %10s %10s %10s %11s\n", "VER", "NOD", "w", "s", "PRE", "OPT1",
              "OPT2", "OPT2/1", "CGAL ARAP", "CGAL/1", "factor nnz", "sums fast", "sums naive", "PRE every", "OPT1 every",
              "nnz every");
  const char* json_path = std::getenv("MARIONETTE_BENCH_JSON");
  std::ofstream json(json_path ? json_path : "bench_rigid_grid.json");
  json << "{\n  \"cell\": " << g_cell << ", \"iterations\": " << kIterations << ", \"outline_arap_ms\": " << outline
       << ",\n  \"rows\": [\n";
  bool first = true;
  for (int w : kWidths) {
    const std::string k = "/w:" + std::to_string(w);
    const double pre = bench::median_us(collect, "PRE" + k) / 1000, o1 = bench::median_us(collect, "OPT1" + k) / 1000,
                 o2 = bench::median_us(collect, "OPT2" + k) / 1000, cg = bench::median_us(collect, "CGAL_ARAP" + k) / 1000,
                 sf = bench::median_us(collect, "SUMS_fast" + k), sn = bench::median_us(collect, "SUMS_naive" + k),
                 pe = bench::median_us(collect, "PRE_every" + k) / 1000, oe = bench::median_us(collect, "OPT1_every" + k) / 1000;
    if (pre < 0 && o1 < 0) continue;  // filtered out
    const mar::RigidGrid& s = prepared(w)->s;
    const mar::RigidGrid& e = prepared(w, true)->s;
    const size_t nod = s.grid_nodes() + s.boundary_nodes();
    std::printf("%6zu %6zu %3d %3d %9.3f %9.3f %9.3f %7.2f %10.3f %9.2f %11ld %9.1fus %9.1fus %10.3f %10.3f %11ld\n",
                s.mesh_vertices(), nod, w, s.stride(), pre, o1, o2, o1 > 0 ? o2 / o1 : 0.0, cg, o1 > 0 ? cg / o1 : 0.0,
                s.factor_nonzeros(), sf, sn, pe, oe, e.factor_nonzeros());
    json << (first ? "" : ",\n") << "    {\"w\": " << w << ", \"VER\": " << s.mesh_vertices() << ", \"NOD\": " << nod
         << ", \"PRE_ms\": " << pre << ", \"OPT1_ms\": " << o1 << ", \"OPT2_ms\": " << o2 << ", \"cgal_arap_ms\": " << cg
         << ", \"factor_nonzeros\": " << s.factor_nonzeros() << ", \"sums_fast_us\": " << sf << ", \"sums_naive_us\": " << sn
         << ", \"stride\": " << s.stride() << ", \"PRE_every_ms\": " << pe << ", \"OPT1_every_ms\": " << oe
         << ", \"factor_nonzeros_every\": " << e.factor_nonzeros() << "}";
    first = false;
  }
  json << "\n  ]\n}\n";
  std::printf("outline ARAP baseline on the bottle (its own mesh), %d iterations: %.3f ms\n", kIterations, outline);
  const double fg = bench::median_us(collect, "FRAME_grid") / 1000, fb = bench::median_us(collect, "FRAME_bone") / 1000;
  if (fg > 0 && fb > 0)
    std::printf("a frame with its points (w = 3): the neck bent by the grid %.3f ms, turning whole as a bone %.3f ms (%.2fx)\n", fg, fb, fb / fg);
  const double ft = bench::median_us(collect, "FLEECE_thinned") / 1000, fe = bench::median_us(collect, "FLEECE_every_point") / 1000;
  if (ft > 0 && fe > 0)
    std::printf("a frame of a fleece drawn in 11,600 points (w = 3): contours thinned to about a cell %.3f ms, every point a node %.3f ms (%.1fx)\n",
                ft, fe, fe / ft);
  benchmark::Shutdown();
  return 0;
}
