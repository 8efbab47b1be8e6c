// Golden images of the example characters. Renderer pinned: the anti-aliased rasterizer
// (render/raster.h) on an offscreen ABGR8888 canvas, 256x256, 2x supersampling, transparent
// background.
// Tolerance: a pixel matches when every premultiplied channel is within 8/255; at most
// 0.5% of pixels may differ (covers float rounding differences across compilers/CPUs).
// Regenerate with MARIONETTE_UPDATE_GOLDEN=1 after an intended rendering change.
#include "character/load.h"
#include "render/canvas.h"
#include "test_util.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

constexpr int kTolerance = 8;
constexpr double kMaxDifferingShare = 0.005;

class Golden : public ::testing::TestWithParam<std::string> {};

TEST_P(Golden, MatchesReference) {
  const std::string name = GetParam();
  auto ch = load_character((test::characters_dir() / (name + ".svg")).string());
  ASSERT_TRUE(ch.ok()) << ch.error;
  RenderOptions o;
  o.width = o.height = 256;
  o.supersample = 2;
  auto img = render_character(*ch.value, prepare_mesh(*ch.value), o);
  ASSERT_TRUE(img.ok()) << img.error;
  const auto golden = test::source_dir() / "tests" / "golden" / (name + ".png");
  if (const char* u = std::getenv("MARIONETTE_UPDATE_GOLDEN"); u && std::string(u) == "1") {
    ASSERT_EQ(write_png(golden.string(), *img.value), "");
    GTEST_SKIP() << "updated " << golden;
  }
  auto ref = read_png_image(golden.string());
  ASSERT_TRUE(ref.ok()) << ref.error;
  const ImageDiff d = compare_images(*img.value, *ref.value, kTolerance);
  ASSERT_TRUE(d.same_size);
  EXPECT_LE(d.differing_share(), kMaxDifferingShare)
      << d.differing << " of " << d.total << " pixels differ, max channel diff " << d.max_channel_diff;
  // The picture is not empty: a sizeable part is covered.
  size_t covered = 0;
  for (size_t i = 3; i < img.value->rgba.size(); i += 4) covered += img.value->rgba[i] > 0;
  EXPECT_GT(covered, d.total / 10);
}

INSTANTIATE_TEST_SUITE_P(ExampleCharacters, Golden, ::testing::Values("butterfly", "figure", "koi"));

}  // namespace
}  // namespace mar
