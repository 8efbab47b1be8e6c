// The rigging benchmark: for each drawing in tests/data/openclipart_rigging.txt (Debian's
// openclipart-svg, people and animals chosen by rule, each with the limbs a person sees written
// beside it), the automatic rig's limbs against that count, and its starter show for a simulated
// nanoKONTROL2 played headless to its end: the worst part's distortion (best rigid fit per
// part, % of the character's height) and whether the character is back at rest once every
// control is back where it started and two seconds have passed (no point more than 1% of the
// height from its rest). A rig from the silhouette is also played frame by frame: its shapes
// measured piece by piece, and its reach (the farthest any handle is from its target: a limb
// that lags its knob, or is too stiff to turn as far as it is told). Each row also keeps what
// its solve cost a frame (median ms; a timing, so read it from a machine left alone).
// Prints a row per drawing and the shares; --json FILE writes them (a grid rig's row names its
// worst piece and the frame of the show it is worst on, `worst_piece_name`, `worst_piece_frame`:
// `marionette run SHOW --dump-frames DIR --every 1` shows that moment; with --keep,
// N-NAME-pieces.svg draws every point by its piece at rest and at that moment), --keep DIR keeps each
// rig, starter show and preview, --list FILE measures another list, --bones rigs as `rig
// --bones` does (a long, straight limb inside one shape turning whole at its joint),
// --untried takes the automatic rig without trying it on its starter show first. A
// measurement, not a gate: without the package it says so and measures nothing.
#include "app/live.h"
#include "app/rig_preview.h"
#include "app/rig_trial.h"
#include "character/load.h"
#include "geom/polygon.h"
#include "rig/auto_rig.h"
#include "rig/starter_show.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {

// A silhouette rig's pieces: each limb's medial axis (AutoRigPart::path, from its free end to
// its joint) cut at its bends (the rig's [[stiffness]] `NAME-bend` centres) into pieces; a
// point belongs to the piece of the limb whose axis is nearest, when its nearest axis point is
// short of the joint and it is within two of the limb's half-widths of it (else it is the body:
// beyond the joint, or beside the limb, as a torso under an arm is). Each shape's points are
// grouped by piece and each group fitted rigidly.
class Regions {
 public:
  Regions(const mar::AutoRig& ar, const std::vector<mar::Points>& rest) {
    struct Axis {
      std::vector<mar::Vec2> pts;
      std::vector<double> cuts;  // arc lengths from the free end where it bends
      std::vector<double> radius;  // its half-width at each point (empty: unbounded)
    };
    std::vector<Axis> axes;
    for (const mar::AutoRigPart& p : ar.parts) {
      if ((p.kind != mar::AutoRigPart::Limb && p.kind != mar::AutoRigPart::Head) || p.path.size() < 2) continue;
      Axis a{p.path, {}, p.path_radius.size() == p.path.size() ? p.path_radius : std::vector<double>{}};
      for (const mar::RigStiffness& st : ar.rig.stiffness) {
        if (st.name != p.handle + "-bend") continue;
        double best = 1e300, at = 0, s = 0;
        for (size_t i = 0; i < a.pts.size(); ++i) {
          if (i > 0) s += (a.pts[i] - a.pts[i - 1]).norm();
          if (const double d = (a.pts[i] - st.center).norm(); d < best) best = d, at = s;
        }
        a.cuts.push_back(at);
      }
      axes.push_back(std::move(a));
      names_.push_back(p.handle);
    }
    region_.resize(rest.size());
    for (size_t k = 0; k < rest.size(); ++k) {
      region_[k].resize(rest[k].size(), 0);
      for (size_t i = 0; i < rest[k].size(); ++i) {
        const mar::Vec2 q = rest[k][i];
        double best = 1e300;
        for (size_t a = 0; a < axes.size(); ++a) {
          const auto& P = axes[a].pts;
          double d_best = 1e300, s_best = 0, s = 0, total = 0, r_best = INFINITY;
          for (size_t j = 1; j < P.size(); ++j) total += (P[j] - P[j - 1]).norm();
          for (size_t j = 1; j < P.size(); ++j) {
            const mar::Vec2 ab = P[j] - P[j - 1];
            const double len = ab.norm(), t = len > 0 ? std::clamp((q - P[j - 1]).dot(ab) / (len * len), 0.0, 1.0) : 0.0;
            if (const double d = (q - (P[j - 1] + t * ab)).norm(); d < d_best) {
              d_best = d, s_best = s + t * len;
              if (!axes[a].radius.empty()) r_best = (1 - t) * axes[a].radius[j - 1] + t * axes[a].radius[j];
            }
            s += len;
          }
          if (s_best >= total - 1e-9 || d_best >= best) continue;  // beyond the joint, or another axis nearer
          if (d_best > 2 * r_best) continue;  // more than two of its half-widths from its axis: not the limb (the body under an arm)
          best = d_best;
          int piece = 0;
          for (double c : axes[a].cuts) piece += s_best > c;
          region_[k][i] = int(1 + 4 * a) + std::min(piece, 3);
        }
      }
    }
  }
  // The worst piece's RMS residual of its best rigid fit (character units); `in_limb` says
  // whether that piece is a limb's (else the body's).
  double worst(const std::vector<mar::Points>& rest, const std::vector<mar::Points>& now, bool* in_limb = nullptr,
               std::string* which = nullptr, std::pair<size_t, int>* at = nullptr) const {
    double w = 0;
    for (size_t k = 0; k < rest.size() && k < now.size(); ++k) {
      if (rest[k].size() != now[k].size() || region_[k].size() != rest[k].size()) continue;
      std::vector<int> ids(region_[k].begin(), region_[k].end());
      std::sort(ids.begin(), ids.end());
      ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
      for (int id : ids) {
        mar::Points a, b;
        for (size_t i = 0; i < rest[k].size(); ++i)
          if (region_[k][i] == id) a.push_back(rest[k][i]), b.push_back(now[k][i]);
        if (const double d = a.size() >= 3 ? mar::rigid_fit_rms(a, b) : 0.0; d > w) {
          w = d;
          if (in_limb) *in_limb = id != 0;
          if (which) *which = id == 0 ? "the body" : names_[size_t(id - 1) / 4] + " piece " + std::to_string((id - 1) % 4);
          if (at) *at = {k, id};
        }
      }
    }
    return w;
  }
  // A picture of the pieces (SVG): every point at rest (left) and at `now` (right), coloured by
  // its piece (the body grey, each limb a hue, its pieces lighter outward), the worst piece's
  // points ringed in red.
  std::string picture(const std::vector<mar::Points>& rest, const std::vector<mar::Points>& now, std::pair<size_t, int> worst) const {
    mar::Bounds b;
    for (const auto& s : rest)
      for (const mar::Vec2& q : s) b.add(q);
    for (const auto& s : now)
      for (const mar::Vec2& q : s) b.add(q);
    if (b.empty()) return "";
    const mar::Vec2 size = b.hi - b.lo;
    const double r = 0.004 * std::max(size.x(), size.y()), gap = 0.1 * size.x();
    std::ostringstream o;
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"" << b.lo.x() - gap << " " << b.lo.y() - gap << " " << 2 * size.x() + 3 * gap << " "
      << size.y() + 2 * gap << "\"><rect x=\"" << b.lo.x() - gap << "\" y=\"" << b.lo.y() - gap << "\" width=\"100%\" height=\"100%\" fill=\"#fff\"/>\n";
    for (int side = 0; side < 2; ++side) {
      const auto& pts = side == 0 ? rest : now;
      const double dx = side == 0 ? 0.0 : size.x() + gap;
      for (size_t k = 0; k < pts.size() && k < region_.size(); ++k)
        for (size_t i = 0; i < pts[k].size() && i < region_[k].size(); ++i) {
          const int id = region_[k][i];
          char colour[32];
          if (id == 0) std::snprintf(colour, sizeof colour, "#888");
          else std::snprintf(colour, sizeof colour, "hsl(%d,80%%,%d%%)", (id - 1) / 4 * 67 % 360, 35 + 12 * ((id - 1) % 4));
          const bool bad = k == worst.first && id == worst.second;
          o << "<circle cx=\"" << pts[k][i].x() + dx << "\" cy=\"" << pts[k][i].y() << "\" r=\"" << r << "\" fill=\"" << colour << "\""
            << (bad ? " stroke=\"red\" stroke-width=\"" + std::to_string(0.5 * r) + "\"" : std::string()) << "/>\n";
        }
    }
    o << "</svg>\n";
    return o.str();
  }
  // The worst whole shape's, as the show's own figure.
  static double whole(const std::vector<mar::Points>& rest, const std::vector<mar::Points>& now) {
    double w = 0;
    for (size_t k = 0; k < rest.size() && k < now.size(); ++k)
      if (rest[k].size() == now[k].size()) w = std::max(w, mar::rigid_fit_rms(rest[k], now[k]));
    return w;
  }

 private:
  std::vector<std::vector<int>> region_;  // per shape, per point: 0 the body, else 1 + 4 * limb + piece
  std::vector<std::string> names_;        // per limb: its handle
};

}  // namespace

int main(int argc, char** argv) {
  std::string json_path, keep;
  fs::path list = fs::path(MARIONETTE_SOURCE_DIR) / "tests/data/openclipart_rigging.txt";
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) == "--json") json_path = argv[++i];
    else if (std::string(argv[i]) == "--keep") keep = argv[++i];
    else if (std::string(argv[i]) == "--list") list = argv[++i];  // (lines as the benchmark's)
  }
  mar::AutoRigOptions options;
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--bones") options.bones = true;  // (as `rig --bones`)
  bool untried = false;  // --untried: auto_rig alone, as before `rig` tried its rig on its starter show
  for (int i = 1; i < argc; ++i) untried = untried || std::string(argv[i]) == "--untried";
  const fs::path root = "/usr/share/openclipart/svg";
  if (!fs::is_directory(root)) {
    std::cout << "openclipart-svg is not installed (apt-get install openclipart-svg): nothing measured\n";
    return 0;
  }
  // (a folder of its own: two runs at once must not play each other's rigs)
  const fs::path work = keep.empty() ? fs::temp_directory_path() / ("marionette-rigging-" + std::to_string(getpid())) : fs::path(keep);
  fs::create_directories(work);
  struct Cleanup {  // the rigs and shows of a run not kept go with it
    fs::path dir;
    ~Cleanup() {
      std::error_code ec;
      if (!dir.empty()) fs::remove_all(dir, ec);
    }
  } cleanup{keep.empty() ? work : fs::path()};
  std::ifstream in(list);
  nlohmann::json rows = nlohmann::json::array();
  std::vector<double> reaches;  // per rig from the silhouette
  std::vector<double> solves;   // per rig played: its solve's median ms a frame
  int n = 0, enough = 0, calm = 0, rested = 0, both = 0, calm_regions = 0, both_regions = 0;
  std::printf("%-8s %-52s %6s %6s %9s %9s %7s\n", "category", "drawing", "person", "found", "worst %", "by region", "rest");
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    std::string category, rel;
    int person = 0;
    ss >> category >> person >> rel;
    const fs::path file = root / rel;
    const std::string stem = std::to_string(n + 1) + "-" + file.stem().string();
    nlohmann::json row{{"category", category}, {"drawing", rel}, {"person", person}};
    ++n;
    auto ch = mar::load_character(file.string());
    if (!ch.ok()) {
      row["error"] = ch.error;
      rows.push_back(row);
      std::printf("%-8s %-52s %6d  (does not load: %s)\n", category.c_str(), rel.c_str(), person, ch.error.c_str());
      continue;
    }
    // as `marionette rig` writes it: tried on its starter show (app/rig_trial.h)
    std::string tried;
    const mar::AutoRig ar = untried ? mar::auto_rig(*ch.value, file.string(), "", options)
                                    : mar::auto_rig_tried(*ch.value, file.string(), "", file.string(), "", options, &tried);
    if (!tried.empty()) row["tried"] = tried;
    int limbs = 0;
    for (const mar::AutoRigPart& p : ar.parts) limbs += p.kind == mar::AutoRigPart::Limb;
    row["found"] = limbs;
    row["handles"] = ar.rig.handles.size();
    row["solver"] = ar.rig.solver;
    enough += limbs >= person;
    const fs::path rig = work / (stem + ".toml"), show = work / (stem + "-show.toml");
    auto write = [](const fs::path& to, const std::string& body) { return bool(std::ofstream(to) << body); };
    if (!write(rig, mar::write_auto_rig(ar, *ch.value))) {
      std::fprintf(stderr, "error: %s: cannot be written\n", rig.c_str());
      return 1;
    }
    if (!keep.empty())
      if (const std::string e = mar::write_rig_preview((work / (stem + ".png")).string(), *ch.value, ar); !e.empty())
        std::fprintf(stderr, "warning: %s\n", e.c_str());
    auto text = mar::starter_show(ar, *ch.value, rig.filename().string(), "nanokontrol2");
    double worst = -1, away = -1, by_region = -1, reach_pct = -1, solve_ms = -1;
    std::string worst_part, worst_piece;
    if (ar.rig.handles.empty() || !text.ok()) {
      row["error"] = ar.rig.handles.empty() ? "nothing to rig" : text.error;
    } else if (!write(show, *text.value)) {
      std::fprintf(stderr, "error: %s: cannot be written\n", show.c_str());
      return 1;
    } else {
      mar::RunOptions o;
      o.headless = true;
      o.quiet = true;
      auto live = mar::LiveShow::load(show.string(), o);
      // (the same show again, frame by frame, for the measure by region: as long as the first)
      mar::RunOptions one = o;
      one.frames = 1;
      auto again = mar::LiveShow::load(show.string(), one);
      if (!live.ok() || !again.ok()) {
        row["error"] = live.ok() ? again.error : live.error;
      } else {
        mar::LiveShow& s = **live.value;
        const std::vector<mar::Points> rest = s.puppet().shapes;
        (void)s.run();
        // two seconds more with every control back where it started: the solver settles
        const double period = 1.0 / 60;
        const long base = s.frames();
        for (int k = 1; k <= 120; ++k) s.frame(int64_t(double(base + k) * period * 1e9));
        const auto j = nlohmann::json::parse(s.stats_json());
        worst = j["quality"]["worst_part_distortion"]["max"].get<double>();
        // (what its solve costs a frame, median: a performer's frame is 16.7 ms at 60 Hz)
        if (j["stages_us"]["solve"]["p50"].is_number()) {
          solve_ms = j["stages_us"]["solve"]["p50"].get<double>() / 1000;
          row["solve_p50_ms"] = solve_ms;
          solves.push_back(solve_ms);
        }
        if (j["quality"]["worst_part"].is_object()) worst_part = j["quality"]["worst_part"]["part"].get<std::string>();
        // By region: a rig from the silhouette bends a limb inside one shape, so each shape is
        // measured piece by piece — the piece of each limb between its free end, its bends and
        // its joint, and the body beyond the joints (Regions) — as a drawing in parts is
        // measured part by part. A drawing in parts: the same figure as above.
        if (ar.rig.solver == "rigid_grid") {
          mar::LiveShow& r = **again.value;
          const Regions reg(ar, rest);
          (void)r.run();
          bool limb = false;
          std::string which;  // (the worst piece, and the frame it is worst on: for --dump-frames)
          long which_frame = 0;
          std::pair<size_t, int> which_at{0, -1};
          std::vector<mar::Points> which_now;  // (for --keep's picture of the pieces)
          if (!keep.empty()) which_now = r.puppet().shapes;
          double whole = reg.whole(rest, r.puppet().shapes), pieces = reg.worst(rest, r.puppet().shapes, &limb, &which, &which_at);
          // How far a handle is from its target at worst: a limb that lags its knob, or one too
          // stiff to reach where it is turned to.
          double reach = 0;
          auto lag = [&] {
            const std::span<const mar::Vec2> t = r.targets();
            const mar::Solver& sv = *r.puppet().solver;
            for (size_t h = 0; h < sv.handle_count() && h < t.size(); ++h)
              if (t[h].allFinite()) reach = std::max(reach, (sv.handle_point(h) - t[h]).norm());
          };
          lag();
          for (long k = 1; k < base + 120; ++k) {
            r.frame(int64_t(double(k) * period * 1e9));
            lag();
            whole = std::max(whole, reg.whole(rest, r.puppet().shapes));
            bool in_limb = false;
            std::string piece;
            std::pair<size_t, int> at{0, -1};
            if (const double d = reg.worst(rest, r.puppet().shapes, &in_limb, &piece, &at); d > pieces) {
              pieces = d;
              limb = in_limb;
              which = piece;
              which_frame = k;
              which_at = at;
              if (!keep.empty()) which_now = r.puppet().shapes;
            }
          }
          worst_piece = limb ? "a limb's piece" : "the body's";
          if (!keep.empty() && !write(work / (stem + "-pieces.svg"), reg.picture(rest, which_now, which_at)))
            std::fprintf(stderr, "warning: %s: cannot be written\n", (work / (stem + "-pieces.svg")).c_str());
          const double height = std::max(1e-9, r.puppet().character.height);
          by_region = 100.0 * pieces / height;
          // (played again frame by frame it is the same show: the same worst whole shape)
          if (std::abs(100.0 * whole / height - worst) > 1e-3)
            std::fprintf(stderr, "warning: %s: played again, its worst part is %.4f %%, not %.4f %%\n", rel.c_str(), 100.0 * whole / height, worst);
          row["worst_by_region_pct"] = by_region;
          reach_pct = 100.0 * reach / height;
          reaches.push_back(reach_pct);
          row["worst_reach_pct"] = reach_pct;
          row["worst_piece"] = worst_piece;
          row["worst_piece_name"] = which;
          row["worst_piece_frame"] = which_frame;
        } else {
          by_region = worst;
        }
        const mar::Bounds b = s.puppet().character.bounds();
        const double height = b.empty() ? 1.0 : std::max(1e-9, b.hi.y() - b.lo.y());
        away = 0;
        const auto& now = s.puppet().shapes;
        for (size_t k = 0; k < rest.size() && k < now.size(); ++k)
          for (size_t i = 0; i < rest[k].size() && i < now[k].size(); ++i) away = std::max(away, (now[k][i] - rest[k][i]).norm() / height * 100);
        row["worst_distortion_pct"] = worst;
        row["worst_part"] = worst_part;
        row["away_from_rest_pct"] = away;
      }
    }
    const bool ok_worst = worst >= 0 && worst <= 1.5, ok_rest = away >= 0 && away <= 1.0, ok_region = by_region >= 0 && by_region <= 1.5;
    calm += ok_worst;
    rested += ok_rest;
    both += ok_worst && ok_rest;
    calm_regions += ok_region;
    both_regions += ok_region && ok_rest;
    rows.push_back(row);
    char reach_text[64] = "";
    if (reach_pct >= 0) std::snprintf(reach_text, sizeof reach_text, "  (silhouette, reach %.2f %%)", reach_pct);
    std::printf("%-8s %-52s %6d %6d %9.2f %9.2f %7s%s%s\n", category.c_str(), rel.c_str(), person, limbs, worst, by_region,
                away < 0 ? "-" : ok_rest ? "yes" : "no", reach_text,
                worst > 1.5 ? ("  worst: " + worst_part + (by_region > 1.5 && !worst_piece.empty() ? ", by piece " + worst_piece : "")).c_str() : "");
    std::fflush(stdout);
  }
  if (n == 0) return 0;
  auto pct = [&](int k) { return 100.0 * k / n; };
  std::printf("\n%d drawings: limbs found >= the person's count on %.0f%%; worst part distortion <= 1.5%% on %.0f%%; back at rest on "
              "%.0f%%; both on %.0f%%\n",
              n, pct(enough), pct(calm), pct(rested), pct(both));
  std::printf("by region (a limb inside one shape measured piece by piece): distortion <= 1.5%% on %.0f%%; both on %.0f%%\n",
              pct(calm_regions), pct(both_regions));
  auto median = [](std::vector<double>& v) {  // (sorts v; -1 when empty)
    std::sort(v.begin(), v.end());
    const size_t m = v.size();
    return m == 0 ? -1.0 : m % 2 ? v[m / 2] : 0.5 * (v[m / 2 - 1] + v[m / 2]);
  };
  const double reach_median = median(reaches), solve_median = median(solves);
  if (!reaches.empty()) {
    std::printf("rigs from the silhouette: reach (farthest handle from its target) median %.2f%%, worst %.2f%% of the height\n",
                reach_median, reaches.back());
  }
  if (!solves.empty()) {
    const size_t m = solves.size();
    const auto slow = std::count_if(solves.begin(), solves.end(), [](double ms) { return ms > 8.0; });
    std::printf("solve a frame (median of each show): median %.2f ms, worst %.2f ms; %ld of %zu over 8 ms (half a 60 Hz frame)\n",
                solve_median, solves.back(), long(slow), m);
  }
  if (!json_path.empty()) {
    nlohmann::json out{{"drawings", n},
                       {"solve_median_ms", solve_median},
                       {"silhouette_reach_median_pct", reach_median},
                       {"limbs_at_least_person_pct", pct(enough)},
                       {"distortion_at_most_1_5_pct", pct(calm)},
                       {"back_at_rest_pct", pct(rested)},
                       {"both_pct", pct(both)},
                       {"distortion_by_region_at_most_1_5_pct", pct(calm_regions)},
                       {"both_by_region_pct", pct(both_regions)},
                       {"rows", rows}};
    if (!(std::ofstream(json_path) << out.dump(1) << "\n")) {
      std::fprintf(stderr, "error: %s: cannot be written\n", json_path.c_str());
      return 1;
    }
  }
  return 0;
}
