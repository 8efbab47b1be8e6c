#include "app/rig_trial.h"

#include "app/live.h"
#include "rig/starter_show.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <unistd.h>

namespace fs = std::filesystem;

namespace mar {

namespace {

std::string fixed(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2f", v);
  return b;
}

std::string figures(const RigTrial& t) {
  if (!t.error.empty()) return "not played: " + t.error;
  return "worst part " + fixed(t.worst_pct) + " %, " + fixed(t.away_pct) + " % off its rest at the end, reach " + fixed(t.reach_pct) +
         " %, moved " + fixed(t.moved_pct) + " %";
}

}  // namespace

RigTrial try_rig(const AutoRig& ar, const Character& ch, const std::string& file, const std::string& mask_file) {
  RigTrial t;
  if (ar.rig.handles.empty()) {
    t.error = "nothing to rig";
    return t;
  }
  // A folder of its own: two rigs tried at once (two processes, or two threads) never share one.
  static std::atomic<int> count{0};
  const fs::path dir = fs::temp_directory_path() / ("marionette-trial-" + std::to_string(getpid()) + "-" + std::to_string(count++));
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    t.error = dir.string() + ": cannot be made (" + ec.message() + ")";
    return t;
  }
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code e;
      fs::remove_all(dir, e);
    }
  } cleanup{dir};
  AutoRig tried = ar;
  tried.rig.character = fs::absolute(file).string();
  tried.rig.mask = mask_file.empty() ? "" : fs::absolute(mask_file).string();
  auto show = starter_show(tried, ch, "rig.toml", "nanokontrol2");
  if (!show.ok()) {
    t.error = show.error;
    return t;
  }
  for (const auto& [name, body] : {std::pair{"rig.toml", write_auto_rig(tried, ch)}, std::pair{"show.toml", *show.value}}) {
    std::ofstream out(dir / name);
    if (!(out << body) || !(out.flush())) {
      t.error = (dir / name).string() + ": cannot be written";
      return t;
    }
  }
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  o.frames = 1;  // the first frame; then frame by frame, to follow each handle against its target
  auto live = LiveShow::load((dir / "show.toml").string(), o);
  if (!live.ok()) {
    t.error = live.error;
    return t;
  }
  LiveShow& s = **live.value;
  const std::vector<Points> rest = s.puppet().shapes;
  if (s.run() != 0) {
    t.error = "its starter show does not start";
    return t;
  }
  const double height = std::max(1e-9, s.puppet().character.height);
  double reach = 0, moved = 0;
  auto lag = [&] {
    const std::vector<Points>& now = s.puppet().shapes;
    for (size_t k = 0; k < rest.size() && k < now.size(); ++k)
      for (size_t i = 0; i < rest[k].size() && i < now[k].size(); ++i) moved = std::max(moved, (now[k][i] - rest[k][i]).squaredNorm());
    const std::span<const Vec2> targets = s.targets();
    const Solver& sv = *s.puppet().solver;
    for (size_t h = 0; h < sv.handle_count() && h < targets.size(); ++h)
      if (targets[h].allFinite()) reach = std::max(reach, (sv.handle_point(h) - targets[h]).norm());
  };
  lag();
  // to the scripts' end, and two seconds more with every control back where it started
  const double period = 1.0 / 60;
  const long frames = long(std::ceil(double(s.scripts_end_ns()) * 1e-9 / period)) + 120;
  for (long k = 1; k <= frames; ++k) {
    s.frame(int64_t(double(k) * period * 1e9));
    lag();
  }
  const auto stats = nlohmann::json::parse(s.stats_json(), nullptr, false);
  if (stats.is_discarded() || !stats["quality"]["worst_part_distortion"]["max"].is_number()) {
    t.error = "its starter show gave no figures";
    return t;
  }
  t.worst_pct = stats["quality"]["worst_part_distortion"]["max"].get<double>();
  t.reach_pct = 100.0 * reach / height;
  t.moved_pct = 100.0 * std::sqrt(moved) / height;
  const Bounds b = s.puppet().character.bounds();
  const double tall = b.empty() ? 1.0 : std::max(1e-9, b.hi.y() - b.lo.y());
  double away = 0;
  const std::vector<Points>& now = s.puppet().shapes;
  for (size_t k = 0; k < rest.size() && k < now.size(); ++k)
    for (size_t i = 0; i < rest[k].size() && i < now[k].size(); ++i) away = std::max(away, (now[k][i] - rest[k][i]).norm());
  t.away_pct = 100.0 * away / tall;
  return t;
}

AutoRig auto_rig_tried(const Character& ch, const std::string& file, const std::string& mask_file, const std::string& character,
                       const std::string& mask, const AutoRigOptions& options, std::string* why) {
  if (why) why->clear();
  AutoRig parts = auto_rig(ch, character, mask, options);
  if (parts.rig.handles.empty() || parts.rig.solver == "rigid_grid" || !options.silhouette) return parts;
  AutoRigOptions anywhere = options;
  anywhere.grid_anywhere = true;
  AutoRig grid = auto_rig(ch, character, mask, anywhere);
  if (grid.rig.solver != "rigid_grid" || grid.rig.handles.empty()) return parts;  // (no limb in its silhouette)
  const RigTrial a = try_rig(parts, ch, file, mask_file);
  if (a.holds() || !a.error.empty()) {
    if (why) *why = "parts: " + figures(a);
    return parts;
  }
  const RigTrial b = try_rig(grid, ch, file, mask_file);
  // It moves at least half as much as the parts' rig, and a point thrown further than the
  // character's height is torn, not lively: no more motion than that is asked. Its reach is not
  // asked: a grid that holds and lags a knob (a crawfish's worst handle 17 % of the height
  // short of its target) looks better than parts that tear (3.5 %) and stay torn (1.8 % off
  // rest); asked within 5 %, it left a busy mother, sandals, a bearded head and the crawfish
  // torn.
  const bool follows = b.error.empty() && b.moved_pct >= 0.5 * std::min(a.moved_pct, 100.0);
  if (b.holds() && follows) {
    grid.notes.push_back("from its parts its starter show tore or drifted (" + figures(a) + "); on its silhouette's grid, its parts' limbs riding, it holds (" +
                         figures(b) + ")");
    if (why) *why = "grid: " + figures(b) + "; parts: " + figures(a);
    return grid;
  }
  parts.notes.push_back("its starter show tears or drifts (" + figures(a) + "); on its silhouette's grid it did no better (" + figures(b) + ")");
  if (why) *why = "parts: " + figures(a) + "; grid: " + figures(b);
  return parts;
}

}  // namespace mar
