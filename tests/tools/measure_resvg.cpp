// Measures how many of resvg's tests our loader + renderer reproduce: `structure` and `shapes`
// (the headline figure, as README has always given it), then `painting`, `paint-servers` and
// `masking` (strokes, dashes, markers, opacity, gradients, patterns, clips and masks), each
// group on a line of its own.
// For each test SVG with a reference PNG: render at the reference size (4x supersampled,
// transparent background) and compare per pixel (premultiplied channels). A test
// matches when at most 1% of its pixels differ by more than 32/255 in any channel.
// Prints the share, and writes per-test numbers as JSON with --json FILE.
// This is a measurement for README, not a pass/fail gate. External images are read wherever
// they are (the suite's are in its `resources` folder), as `[show] images = "anywhere"` allows.
#include "character/load.h"
#include "render/canvas.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  std::string json_path;
  fs::path root = fs::path(MARIONETTE_CORPUS_DIR) / "svg" / "resvg" / "tests";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--json" && i + 1 < argc) json_path = argv[++i];
    if (a == "--root" && i + 1 < argc) root = argv[++i];
  }
  if (!fs::is_directory(root)) {
    std::printf("resvg tests not found at %s; nothing measured\n", root.string().c_str());
    return 0;
  }
  constexpr int kTolerance = 32;
  constexpr double kMaxShare = 0.01;
  struct Row {
    std::string file;
    std::string status;
    double share = 1;
  };
  std::vector<Row> rows;
  const char* const groups[] = {"structure", "shapes", "painting", "paint-servers", "masking"};
  for (const char* group : groups) {
    std::vector<fs::path> svgs;
    if (!fs::is_directory(root / group)) continue;
    for (const auto& e : fs::recursive_directory_iterator(root / group)) {
      if (e.path().extension() == ".svg" && fs::exists(fs::path(e.path()).replace_extension(".png"))) {
        svgs.push_back(e.path());
      }
    }
    std::sort(svgs.begin(), svgs.end());
    for (const fs::path& svg : svgs) {
      Row row{std::string(group) + "/" + fs::relative(svg, root / group).string(), "", 1.0};
      auto ref = mar::read_png_image(fs::path(svg).replace_extension(".png").string());
      // (the suite keeps its pictures in a folder of their own, `resources`, beside the tests:
      // what a show allows with [show] images = "anywhere")
      mar::LoadOptions lo;
      lo.images_anywhere = true;
      auto ch = mar::load_character(svg.string(), lo);
      if (!ref.ok()) {
        row.status = "no-reference";
      } else if (!ch.ok()) {
        row.status = "rejected";
      } else {
        mar::RenderOptions o;
        o.width = ref.value->width;
        o.height = ref.value->height;
        o.supersample = 4;
        auto img = mar::render_character(*ch.value, mar::prepare_mesh(*ch.value), o);
        if (!img.ok()) {
          row.status = "render-failed";
        } else {
          const mar::ImageDiff d = mar::compare_images(*img.value, *ref.value, kTolerance);
          row.share = d.differing_share();
          row.status = row.share <= kMaxShare ? "match" : "differs";
        }
      }
      rows.push_back(row);
    }
  }
  size_t match = 0;
  for (const Row& r : rows) match += r.status == "match";
  auto count = [&](const std::string& group) {
    size_t n = 0, m = 0;
    for (const Row& r : rows) {
      if (r.file.rfind(group + "/", 0) == 0) {
        ++n;
        m += r.status == "match";
      }
    }
    return std::make_pair(m, n);
  };
  const auto [sm, sn] = count("structure");
  const auto [hm, hn] = count("shapes");
  std::printf("resvg agreement (<=1%% of pixels off by >32/255, 4x supersampled): %zu of %zu structure and shapes tests = %.1f%%\n",
              sm + hm, sn + hn, sn + hn ? 100.0 * double(sm + hm) / double(sn + hn) : 0.0);
  for (const char* group : groups) {
    const auto [m, n] = count(group);
    std::printf("  %-14s %3zu of %3zu (%.1f%%)\n", group, m, n, n ? 100.0 * double(m) / double(n) : 0.0);
  }
  std::printf("  all            %3zu of %3zu (%.1f%%)\n", match, rows.size(), rows.empty() ? 0.0 : 100.0 * double(match) / double(rows.size()));
  if (!json_path.empty()) {
    std::ofstream out(json_path);
    out << "{\n  \"tolerance\": " << kTolerance << ",\n  \"max_differing_share\": " << kMaxShare
        << ",\n  \"matched\": " << match << ",\n  \"total\": " << rows.size() << ",\n  \"tests\": [\n";
    for (size_t i = 0; i < rows.size(); ++i) {
      out << "    {\"file\": \"" << rows[i].file << "\", \"status\": \"" << rows[i].status
          << "\", \"differing_share\": " << rows[i].share << "}" << (i + 1 < rows.size() ? "," : "") << "\n";
    }
    out << "  ]\n}\n";
  }
  return 0;
}
