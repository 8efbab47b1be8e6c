// Every SVG in the shared corpus loads or fails with a clean message, and what loads
// also triangulates and renders. No crash, no hang, no sanitizer report (the test
// command runs this under ASan+UBSan too).
#include "character/load.h"
#include "render/canvas.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace mar {
namespace {

std::vector<std::filesystem::path> corpus_svgs() {
  std::vector<std::filesystem::path> files;
  if (!test::have_corpus()) return files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(test::corpus_dir() / "svg")) {
    if (e.is_regular_file() && e.path().extension() == ".svg") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(corpus_sweep, EverySvgLoadsOrFailsCleanly) {
  const auto files = corpus_svgs();
  if (files.empty()) GTEST_SKIP() << "corpus not present at " << test::corpus_dir();
  size_t loaded = 0, failed = 0, warned = 0, shapes = 0;
  for (const auto& f : files) {
    SCOPED_TRACE(f.string());
    auto r = load_character(f.string());
    if (!r.ok()) {
      ++failed;
      // A clean message names the file.
      EXPECT_NE(r.error.find(f.string()), std::string::npos) << r.error;
      continue;
    }
    ++loaded;
    warned += r.value->warnings.empty() ? 0 : 1;
    shapes += r.value->shapes.size();
    for (const SubShape& s : r.value->shapes) {
      for (const Vec2& p : s.points) ASSERT_TRUE(p.allFinite());
      ASSERT_GE(s.layer, 0);
      ASSERT_LT(static_cast<size_t>(s.layer), r.value->layers.size());
    }
    RenderOptions o;
    o.width = o.height = 48;
    auto img = render_character(*r.value, prepare_mesh(*r.value), o);
    EXPECT_TRUE(img.ok()) << img.error;
  }
  std::printf("corpus sweep: %zu files, %zu loaded (%zu with warnings, %zu sub-shapes), %zu rejected\n",
              files.size(), loaded, warned, shapes, failed);
  EXPECT_GT(files.size(), 1000u);
  EXPECT_GT(loaded, files.size() * 9 / 10);
}

TEST(corpus_sweep, DicebearCharactersKeepOnePartPerGroup) {
  if (!test::have_corpus()) GTEST_SKIP() << "corpus not present";
  const auto dir = test::corpus_dir() / "svg" / "characters-dicebear-cc0";
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".svg") continue;
    auto r = load_character(e.path().string());
    ASSERT_TRUE(r.ok()) << r.error;
    EXPECT_GE(r.value->layers.size(), 3u) << e.path();  // body, head, hair, face parts ...
    EXPECT_GE(r.value->shapes.size(), r.value->layers.size()) << e.path();
  }
}

}  // namespace
}  // namespace mar
