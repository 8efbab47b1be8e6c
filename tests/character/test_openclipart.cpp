// Real drawings no one here made: the benchmark list of Debian's openclipart-svg
// (tests/data/openclipart_bench.txt). Each loads, with every shape it leaves out said and
// counted, and renders at 800 px wide with something drawn. Skipped, saying so, where the
// package is not installed (`apt-get install openclipart-svg`).
#include "character/load.h"
#include "render/canvas.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace mar {
namespace {

TEST(Openclipart, EveryListedDrawingLoadsAndDraws) {
  const std::filesystem::path root = "/usr/share/openclipart/svg";
  if (!std::filesystem::is_directory(root)) GTEST_SKIP() << "openclipart-svg is not installed (apt-get install openclipart-svg)";
  std::ifstream list(test::source_dir() / "tests" / "data" / "openclipart_bench.txt");
  ASSERT_TRUE(list);
  int drawings = 0;
  for (std::string line; std::getline(list, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string category, file;
    ls >> category >> file;
    const std::string path = (root / file).string();
    LoadOptions lo;
    lo.pixels_per_unit = [](double w, double h) { return fit_view(w, h, 800, std::max(1, int(800 * h / w))).max_scale(); };
    auto ch = load_character(path, lo);
    ASSERT_TRUE(ch.ok()) << ch.error;
    ++drawings;
    // A dropped shape is said: each reason counted has a warning beside it.
    int dropped = 0;
    for (const auto& [reason, n] : ch.value->dropped) dropped += n;
    if (dropped > 0) {
      EXPECT_FALSE(ch.value->warnings.empty()) << file;
    }
    if (ch.value->shapes.empty()) {  // (the list holds a file that only defines a gradient)
      EXPECT_EQ(dropped, 0) << file;
      continue;
    }
    RenderOptions o;
    o.width = 400;
    o.height = std::clamp(int(400 * ch.value->height / ch.value->width), 1, 4000);
    auto img = render_character(*ch.value, prepare_mesh(*ch.value), o);
    ASSERT_TRUE(img.ok()) << file << ": " << img.error;
    size_t inked = 0;
    for (size_t i = 3; i < img.value->rgba.size(); i += 4) inked += img.value->rgba[i] > 0;
    EXPECT_GT(inked, 0u) << file;
  }
  EXPECT_GE(drawings, 50);
}

}  // namespace
}  // namespace mar
