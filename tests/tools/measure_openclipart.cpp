// Measures how close our renders of real clip art are to librsvg's (rsvg-convert): for each
// drawing in tests/data/openclipart_bench.txt (Debian's openclipart-svg, chosen by rule, by
// category), render it 800 px wide on white with `marionette render`'s defaults and with
// rsvg-convert, and count the drawn pixels (not white in either picture) whose every channel is
// within 16/255 of librsvg's. Prints each drawing's share, each category's median and the overall
// median; --json FILE writes them, --keep DIR keeps both pictures for a contact sheet.
// A measurement, not a gate. Without the package or rsvg-convert it says so and measures nothing.
#include "character/load.h"
#include "render/canvas.h"
#include "render/image.h"

#include <sys/wait.h>
#include <spawn.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace fs = std::filesystem;

namespace {

// Runs a program (searched on PATH) with its arguments; true when it exits 0.
bool run(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return false;
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return false;
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

bool on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream ss(path ? path : "/usr/bin:/bin");
  for (std::string dir; std::getline(ss, dir, ':');)
    if (!dir.empty() && access((fs::path(dir) / program).c_str(), X_OK) == 0) return true;
  return false;
}

// Of the pixels drawn in either picture (a channel more than 16/255 from white), the share
// whose channels are all within 16/255 of each other's.
double agreement(const mar::Image& a, const mar::Image& b) {
  if (a.width != b.width || a.height != b.height) return 0;
  size_t drawn = 0, same = 0;
  for (size_t i = 0; i + 3 < a.rgba.size(); i += 4) {
    bool inked = false, close = true;
    for (size_t k = 0; k < 3; ++k) {
      inked = inked || a.rgba[i + k] < 239 || b.rgba[i + k] < 239;
      close = close && std::abs(int(a.rgba[i + k]) - int(b.rgba[i + k])) <= 16;
    }
    drawn += inked;
    same += inked && close;
  }
  return drawn ? double(same) / double(drawn) : 1.0;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  fs::path list = fs::path(MARIONETTE_SOURCE_DIR) / "tests" / "data" / "openclipart_bench.txt";
  fs::path root = "/usr/share/openclipart/svg";
  std::string json_path, keep;
  int width = 800;
  for (int i = 1; i + 1 < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--list") list = argv[++i];
    else if (a == "--root") root = argv[++i];
    else if (a == "--json") json_path = argv[++i];
    else if (a == "--keep") keep = argv[++i];
    else if (a == "--width") width = std::clamp(std::atoi(argv[++i]), 16, 4096);
  }
  if (!fs::is_directory(root) || !on_path("rsvg-convert")) {
    std::printf("openclipart-svg or rsvg-convert not installed (apt-get install openclipart-svg librsvg2-bin); nothing measured\n");
    return 0;
  }
  std::ifstream in(list);
  if (!in) {
    std::fprintf(stderr, "%s: cannot read the list\n", list.c_str());
    return 1;
  }
  const fs::path work = keep.empty() ? fs::temp_directory_path() / ("measure_openclipart." + std::to_string(getpid())) : fs::path(keep);
  fs::create_directories(work);
  struct Row {
    std::string category, file, status;
    double share = 0, load_ms = 0;
    size_t points = 0;
    int warnings = 0;
  };
  std::vector<Row> rows;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    Row r;
    ls >> r.category >> r.file;
    const fs::path svg = root / r.file;
    const auto t0 = std::chrono::steady_clock::now();
    mar::LoadOptions lo;
    int h = 0;
    auto ch = mar::load_character(svg.string());  // (its size first, for the picture's height)
    if (ch.ok() && ch.value->width > 0) h = std::clamp(int(std::lround(width * ch.value->height / ch.value->width)), 1, 8192);
    lo.pixels_per_unit = [&](double w, double hh) { return mar::fit_view(w, hh, width, h).max_scale(); };
    if (h > 0) ch = mar::load_character(svg.string(), lo);
    r.load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const std::string stem = r.category + "_" + svg.stem().string();
    const fs::path ours = work / (stem + ".marionette.png"), theirs = work / (stem + ".rsvg.png");
    if (!ch.ok() || h <= 0) {
      r.status = "rejected";
    } else {
      r.warnings = int(ch.value->warnings.size());
      for (const mar::SubShape& s : ch.value->shapes) r.points += s.points.size();
      mar::RenderOptions o;
      o.width = width;
      o.height = h;
      o.background = mar::Rgba{1, 1, 1, 1};
      auto img = mar::render_character(*ch.value, mar::prepare_mesh(*ch.value), o);
      if (!img.ok() || !mar::write_png(ours.string(), *img.value).empty()) {
        r.status = "render-failed";
      } else if (!run({"rsvg-convert", "-w", std::to_string(width), "-h", std::to_string(h), "-b", "white", svg.string(), "-o",
                       theirs.string()})) {
        r.status = "rsvg-failed";
      } else if (auto ref = mar::read_png_image(theirs.string()); !ref.ok()) {
        r.status = "rsvg-failed";
      } else {
        r.share = agreement(*img.value, *ref.value);
        r.status = "measured";
      }
    }
    std::printf("%-18s %-60s %6.1f%%  %s  %zu points, %d warnings, %.0f ms to load\n", r.category.c_str(), r.file.c_str(),
                100 * r.share, r.status.c_str(), r.points, r.warnings, r.load_ms);
    rows.push_back(r);
  }
  if (keep.empty()) fs::remove_all(work);
  std::map<std::string, std::vector<double>> by;
  std::vector<double> all;
  int good = 0;
  for (const Row& r : rows) {
    by[r.category].push_back(r.share);
    all.push_back(r.share);
    good += r.share >= 0.95;
  }
  std::printf("\nagreement with librsvg (drawn pixels within 16/255, %d px wide), median by category:\n", width);
  for (const auto& [c, v] : by) std::printf("  %-18s %5.1f%%  (%zu drawings)\n", c.c_str(), 100 * median(v), v.size());
  std::printf("  all                %5.1f%%  median of %zu drawings; %d of them at 95%% or more\n", 100 * median(all), all.size(), good);
  if (!json_path.empty()) {
    std::ofstream out(json_path);
    out << "{\n  \"width\": " << width << ",\n  \"median\": " << median(all) << ",\n  \"drawings\": [\n";
    for (size_t i = 0; i < rows.size(); ++i)
      out << "    {\"category\": \"" << rows[i].category << "\", \"file\": \"" << rows[i].file << "\", \"status\": \"" << rows[i].status
          << "\", \"agreement\": " << rows[i].share << ", \"points\": " << rows[i].points << ", \"load_ms\": " << rows[i].load_ms << "}"
          << (i + 1 < rows.size() ? "," : "") << "\n";
    out << "  ]\n}\n";
    if (!out) {
      std::fprintf(stderr, "%s: could not write\n", json_path.c_str());
      return 1;
    }
  }
  return 0;
}
