// The rigging benchmark: for each drawing in tests/data/openclipart_rigging.txt (Debian's
// openclipart-svg, people and animals chosen by rule, each with the limbs a person sees written
// beside it), the automatic rig's limbs against that count, and its starter show for a simulated
// nanoKONTROL2 played headless to its end: the worst part's distortion (best rigid fit per
// part, % of the character's height) and whether the character is back at rest once every
// control is back where it started and two seconds have passed (no point more than 1% of the
// height from its rest).
// Prints a row per drawing and the shares; --json FILE writes them, --keep DIR keeps each
// rig, starter show and preview. A measurement, not a gate: without the package it says so and
// measures nothing.
#include "app/live.h"
#include "app/rig_preview.h"
#include "character/load.h"
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

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  std::string json_path, keep;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) == "--json") json_path = argv[++i];
    else if (std::string(argv[i]) == "--keep") keep = argv[++i];
  }
  const fs::path root = "/usr/share/openclipart/svg";
  const fs::path list = fs::path(MARIONETTE_SOURCE_DIR) / "tests/data/openclipart_rigging.txt";
  if (!fs::is_directory(root)) {
    std::cout << "openclipart-svg is not installed (apt-get install openclipart-svg): nothing measured\n";
    return 0;
  }
  const fs::path work = keep.empty() ? fs::temp_directory_path() / "marionette-rigging" : fs::path(keep);
  fs::create_directories(work);
  std::ifstream in(list);
  nlohmann::json rows = nlohmann::json::array();
  int n = 0, enough = 0, calm = 0, rested = 0, both = 0;
  std::printf("%-8s %-52s %6s %6s %9s %7s\n", "category", "drawing", "person", "found", "worst %", "rest");
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
    const mar::AutoRig ar = mar::auto_rig(*ch.value, file.string());
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
    double worst = -1, away = -1;
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
      if (!live.ok()) {
        row["error"] = live.error;
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
        const mar::Bounds b = s.puppet().character.bounds();
        const double height = b.empty() ? 1.0 : std::max(1e-9, b.hi.y() - b.lo.y());
        away = 0;
        const auto& now = s.puppet().shapes;
        for (size_t k = 0; k < rest.size() && k < now.size(); ++k)
          for (size_t i = 0; i < rest[k].size() && i < now[k].size(); ++i) away = std::max(away, (now[k][i] - rest[k][i]).norm() / height * 100);
        row["worst_distortion_pct"] = worst;
        row["away_from_rest_pct"] = away;
      }
    }
    const bool ok_worst = worst >= 0 && worst <= 1.5, ok_rest = away >= 0 && away <= 1.0;
    calm += ok_worst;
    rested += ok_rest;
    both += ok_worst && ok_rest;
    rows.push_back(row);
    std::printf("%-8s %-52s %6d %6d %9.2f %7s%s\n", category.c_str(), rel.c_str(), person, limbs, worst, away < 0 ? "-" : ok_rest ? "yes" : "no",
                ar.rig.solver == "rigid_grid" ? "  (silhouette)" : "");
    std::fflush(stdout);
  }
  if (n == 0) return 0;
  auto pct = [&](int k) { return 100.0 * k / n; };
  std::printf("\n%d drawings: limbs found >= the person's count on %.0f%%; worst part distortion <= 1.5%% on %.0f%%; back at rest on "
              "%.0f%%; both on %.0f%%\n",
              n, pct(enough), pct(calm), pct(rested), pct(both));
  if (!json_path.empty()) {
    nlohmann::json out{{"drawings", n},
                       {"limbs_at_least_person_pct", pct(enough)},
                       {"distortion_at_most_1_5_pct", pct(calm)},
                       {"back_at_rest_pct", pct(rested)},
                       {"both_pct", pct(both)},
                       {"rows", rows}};
    if (!(std::ofstream(json_path) << out.dump(1) << "\n")) {
      std::fprintf(stderr, "error: %s: cannot be written\n", json_path.c_str());
      return 1;
    }
  }
  return 0;
}
