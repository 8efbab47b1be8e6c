// Props ([[prop]]): a flag held in the figure's right hand goes up with the hand when a knob
// lifts it, whole (its own shape), drawn with no allocation; a prop on a part the character
// does not have is refused with the show's file and line.
#include "app/alloc_count.h"
#include "app/live.h"
#include "render/image.h"
#include "test_util.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

struct Green {
  double x = 0, y = 0;
  long n = 0;
};

// The flag's cloth: the only green in the show.
Green green_of(const std::string& png) {
  Green g;
  auto img = read_png_image(png);
  EXPECT_TRUE(img.ok()) << img.error;
  if (!img.ok()) return g;
  const Image& im = *img.value;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      const uint8_t* p = &im.rgba[size_t(y * im.width + x) * 4];
      if (p[1] > p[0] + 60 && p[1] > p[2] + 60) {
        g.x += x;
        g.y += y;
        ++g.n;
      }
    }
  if (g.n) g.x /= double(g.n), g.y /= double(g.n);
  return g;
}

TEST(LiveProp, AFlagInTheHandGoesUpWithTheHandWhole) {
  set_allocation_counter(&heap_allocation_count);
  const auto dir = test::temp_dir("prop");
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  o.warmup = 30;
  o.dump_dir = (dir / "f").string();
  o.every = 150;
  o.frames = 301;
  auto live = LiveShow::load((test::source_dir() / "tests/data/shows/prop.toml").string(), o);
  ASSERT_TRUE(live.ok()) << live.error;
  LiveShow& s = **live.value;
  EXPECT_EQ(s.run(), 0);
  EXPECT_EQ(s.allocations_after_warmup(), 0u) << "props are drawn with no allocation";
  const Green rest = green_of((dir / "f" / "frame_000000.png").string()), up = green_of((dir / "f" / "frame_000300.png").string());
  ASSERT_GT(rest.n, 20) << "the flag is drawn";
  EXPECT_LT(up.y, rest.y - 15) << "the flag went up with the hand: " << rest.y << " -> " << up.y;
  EXPECT_NEAR(double(up.n), double(rest.n), 0.25 * double(rest.n)) << "the same flag, not stretched";
}

TEST(LiveProp, APropOnAPartTheCharacterDoesNotHaveIsRefusedWithItsLine) {
  const std::string text = "[show]\nrig = \"" + (test::source_dir() / "config/rigs/figure.toml").string() +
                           "\"\n[[prop]]\nfile = \"" + (test::source_dir() / "config/props/flag.svg").string() +
                           "\"\npart = \"tentacle\"\n";
  const std::string path = test::write_temp("prop-no-part.toml", text);
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  auto live = LiveShow::load(path, o);
  ASSERT_FALSE(live.ok());
  EXPECT_NE(live.error.find(path + ":3: prop: the character has no part 'tentacle'"), std::string::npos) << live.error;
}

}  // namespace
}  // namespace mar
