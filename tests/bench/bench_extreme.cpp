// Extreme input through every example rig's solver (issue: kiosk reliability): random handle
// target sets — far away, coincident, ±1e12, NaN, Inf, flipping every frame, or ordinary drags —
// one solve each, as a live frame would run them. Counts non-finite output, the largest output
// (relative to the larger of the character's diagonal and the farthest finite target) and the
// slowest solve, per rig. Exit 1 on any non-finite output or unbounded pose (a handle farther
// from rest than 10 times the farthest target since the last reset).
//   bench_extreme [--sets N] [--json out.json] [--seed S]      (default N = 1,000,000 per rig)
//   bench_extreme --smoke                                       (N = 3,000: CI)
#include "app/puppet.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

struct Row {
  std::string rig;
  long sets = 0, nonfinite = 0, reset = 0;
  double worst_ratio = 0, worst_us = 0, total_us = 0;
};

}  // namespace

int main(int argc, char** argv) {
  long sets = 1'000'000;
  unsigned seed = 1;
  std::string json;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--smoke") sets = 3000;
    else if (a == "--sets" && i + 1 < argc) sets = std::atol(argv[++i]);
    else if (a == "--seed" && i + 1 < argc) seed = unsigned(std::atol(argv[++i]));
    else if (a == "--json" && i + 1 < argc) json = argv[++i];
    else {
      std::fprintf(stderr, "usage: bench_extreme [--smoke | --sets N] [--seed S] [--json out.json]\n");
      return 2;
    }
  }
  std::vector<std::string> rigs;
  for (const auto& e : std::filesystem::directory_iterator(std::string(MARIONETTE_SOURCE_DIR) + "/config/rigs"))
    if (e.path().extension() == ".toml") rigs.push_back(e.path().string());
  std::sort(rigs.begin(), rigs.end());
  std::vector<Row> rows;
  bool bad = false;
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN(), kInf = std::numeric_limits<double>::infinity();
  for (const std::string& path : rigs) {
    auto loaded = mar::load_puppet("", path);
    if (!loaded.ok()) {
      std::fprintf(stderr, "%s\n", loaded.error.c_str());
      return 2;
    }
    mar::Puppet& p = **loaded.value;
    const std::vector<mar::Vec2> rest = p.rest_targets();
    const size_t h = rest.size();
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    Row row;
    row.rig = std::filesystem::path(path).stem().string();
    std::vector<mar::Vec2> t(h);
    double far = 0;  // the farthest finite target from its rest point since the last reset (a warm
                     // start may still be there)
    for (long k = 0; k < sets; ++k) {
      const int kind = int(rng() % 8);
      for (size_t i = 0; i < h; ++i) {
        const mar::Vec2 r = rest[i];
        switch (kind) {
          case 0: t[i] = r + 0.3 * p.diagonal * mar::Vec2(u(rng), u(rng)); break;         // an ordinary drag
          case 1: t[i] = r + 1e3 * p.diagonal * mar::Vec2(u(rng), u(rng)); break;         // far away
          case 2: t[i] = rest[0]; break;                                                  // all coincident
          case 3: t[i] = mar::Vec2(u(rng) > 0 ? 1e12 : -1e12, u(rng) > 0 ? 1e12 : -1e12); break;
          case 4: t[i] = u(rng) > 0 ? mar::Vec2(kNaN, r.y()) : r; break;                  // NaN
          case 5: t[i] = u(rng) > 0 ? mar::Vec2(kInf, -kInf) : r; break;                   // Inf
          case 6: t[i] = (k % 2 ? 1.0 : -1.0) * 10 * p.diagonal * mar::Vec2(1, 1) + r; break;  // flipping
          default: t[i] = r + (u(rng) > 0.9 ? mar::Vec2(1e-300, -1e-300) : mar::Vec2::Zero()); break;
        }
        if (t[i].allFinite()) far = std::max(far, (t[i] - rest[i]).norm());
      }
      const auto t0 = std::chrono::steady_clock::now();
      p.solver->solve(t, 1);
      const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
      row.total_us += us;
      row.worst_us = std::max(row.worst_us, us);
      double out = 0;
      bool finite = true;
      for (size_t i = 0; i < h; ++i) {
        const mar::Vec2 q = p.solver->handle_point(i);
        finite = finite && q.allFinite();
        if (q.allFinite()) out = std::max(out, (q - rest[i]).norm());
      }
      if (k % 64 == 0) {  // every shape point now and then (reconstruction is the slow part)
        p.reconstruct();
        for (const mar::Points& s : p.shapes)
          for (const mar::Vec2& q : s) finite = finite && q.allFinite();
      }
      if (!finite) ++row.nonfinite;
      row.worst_ratio = std::max(row.worst_ratio, out / std::max(p.diagonal, far));
      if (k % 1000 == 999) {  // as a show would after a wild stretch: back to rest
        p.solver->reset_to_rest();
        far = 0;
        ++row.reset;
      }
      ++row.sets;
    }
    // Bounded: no handle ever ends farther from rest than a few times the farthest target.
    if (row.nonfinite > 0 || !(row.worst_ratio < 10)) bad = true;
    std::printf("%-12s %9ld sets  non-finite %ld  worst |out| / max(diag, |target|) %.3f  solve mean %.1f us, worst %.0f us\n",
                row.rig.c_str(), row.sets, row.nonfinite, row.worst_ratio, row.total_us / double(std::max(1L, row.sets)),
                row.worst_us);
    rows.push_back(row);
  }
  if (!json.empty()) {
    std::ofstream f(json);
    f << "{\"sets_per_rig\": " << sets << ", \"rigs\": [";
    for (size_t i = 0; i < rows.size(); ++i)
      f << (i ? ", " : "") << "{\"rig\": \"" << rows[i].rig << "\", \"nonfinite\": " << rows[i].nonfinite
        << ", \"worst_ratio\": " << rows[i].worst_ratio << ", \"worst_us\": " << rows[i].worst_us
        << ", \"mean_us\": " << rows[i].total_us / double(std::max(1L, rows[i].sets)) << "}";
    f << "]}\n";
  }
  return bad ? 1 : 0;
}
