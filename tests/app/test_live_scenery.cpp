// Scenery ([[scenery]]): a drawing that stays still, behind the character filling the canvas
// (cover) or placed in front of it (at, width), loaded with the show and drawn each frame with
// no allocation; a scenery file that does not load is refused with the show's file and line.
#include "app/alloc_count.h"
#include "app/live.h"
#include "render/image.h"
#include "test_util.h"

#include <gtest/gtest.h>


namespace mar {
namespace {

TEST(LiveScenery, ABackdropFillsTheCanvasBehindAndAPlacedOneIsInFront) {
  set_allocation_counter(&heap_allocation_count);
  const auto dir = test::temp_dir("scenery");
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  o.warmup = 30;
  o.dump_dir = (dir / "f").string();
  o.every = 100;
  o.frames = 400;
  auto live = LiveShow::load((test::source_dir() / "tests/data/shows/scenery.toml").string(), o);
  ASSERT_TRUE(live.ok()) << live.error;
  LiveShow& s = **live.value;
  EXPECT_EQ(s.run(), 0);
  EXPECT_EQ(s.frames(), 400);
  EXPECT_EQ(s.allocations_after_warmup(), 0u) << "scenery is drawn with no allocation";
  auto img = read_png_image((dir / "f" / "frame_000000.png").string());
  ASSERT_TRUE(img.ok()) << img.error;
  const Image& im = *img.value;
  auto px = [&](int x, int y) {
    const uint8_t* p = &im.rgba[size_t(y * im.width + x) * 4];
    return std::array<int, 3>{p[0], p[1], p[2]};
  };
  // the meadow's sky at the top right (the show's background is a warm grey, 244 241 234)
  const auto sky = px(im.width - 3, 2);
  EXPECT_GT(sky[2], sky[0] + 60) << "blue sky, not the background: " << sky[0] << " " << sky[1] << " " << sky[2];
  // its hills at the bottom corners, green
  const auto hill = px(2, im.height - 3);
  EXPECT_GT(hill[1], hill[0] + 30);
  EXPECT_GT(hill[1], hill[2] + 30);
  // the small meadow in front at the top left: its sky's gradient (a small copy: darker blue
  // at its top than the big one's at the same height is not asked; its hill is green at y = 25)
  const auto small_hill = px(20, 27);
  EXPECT_GT(small_hill[1], small_hill[2] + 30) << "the placed meadow's hill, in front";
  // the figure is drawn over the backdrop: its middle is not sky or hill
  const auto middle = px(im.width / 2, im.height / 2);
  EXPECT_FALSE(middle[2] > middle[0] + 60) << "the figure covers the middle";
}

TEST(LiveScenery, ASceneryFileThatDoesNotLoadIsRefusedWithTheShowsLine) {
  const std::string text = "[show]\nrig = \"" + (test::source_dir() / "config/rigs/figure.toml").string() +
                           "\"\n[[scenery]]\nfile = \"no-such-backdrop.svg\"\n";
  const std::string path = test::write_temp("scenery-missing.toml", text);
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  auto live = LiveShow::load(path, o);
  ASSERT_FALSE(live.ok());
  EXPECT_NE(live.error.find(path + ":3: scenery:"), std::string::npos) << live.error;
  EXPECT_NE(live.error.find("no-such-backdrop.svg"), std::string::npos) << live.error;
  const std::string both = "[show]\nrig = \"" + (test::source_dir() / "config/rigs/figure.toml").string() +
                           "\"\n[[scenery]]\nfile = \"x.svg\"\nfit = \"cover\"\nat = [0, 0]\nwidth = 5\n";
  auto refused = LiveShow::load(test::write_temp("scenery-both.toml", both), o);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error.find(":3: a placed [[scenery]] gives at"), std::string::npos) << refused.error;
}

}  // namespace
}  // namespace mar
