// Rebuilding the draw list of a character every frame allocates nothing after warm-up.
#include "character/load.h"
#include "render/canvas.h"
#include "render/tessellate.h"
#include "alloc_counter.h"
#include "test_util.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

TEST(build_draw_list, NoHeapAllocationAfterWarmUp) {
  auto ch = load_character((test::characters_dir() / "figure.svg").string());
  ASSERT_TRUE(ch.ok()) << ch.error;
  const CharacterMesh mesh = prepare_mesh(*ch.value);
  std::vector<Points> pos;
  for (const SubShape& s : ch.value->shapes) pos.push_back(s.points);
  DrawList list;
  auto frame = [&](int f) {
    for (size_t i = 0; i < pos.size(); ++i) {
      for (size_t k = 0; k < pos[i].size(); ++k) {
        pos[i][k] = ch.value->shapes[i].points[k] + Vec2(std::sin(f * 0.1 + k) * 3, std::cos(f * 0.07 + i) * 3);
      }
    }
    list.clear();
    build_draw_list(*ch.value, mesh, pos, Affine2::scale(1.5, 1.5), 0.25, list);
  };
  // The animation cycles every 100 frames; the first cycle is the warm-up in which the
  // buffers reach their working size, the next two must not allocate.
  for (int f = 0; f < 100; ++f) frame(f);
  const long before = test::allocation_count();
  for (int f = 100; f < 300; ++f) frame(f % 100);
  EXPECT_EQ(test::allocation_count() - before, 0);
  EXPECT_GT(list.indices.size(), 100u);
}

// Drawing a frame with the anti-aliased rasterizer allocates nothing once its buffers have
// grown to the canvas: a drawing and a textured (raster) character, moving every frame.
TEST(Canvas, AntiAliasedFramesAllocateNothingAfterWarmUp) {
  for (const char* file : {"figure.svg", "boy.png"}) {
    auto ch = load_character((test::characters_dir() / file).string());
    ASSERT_TRUE(ch.ok()) << ch.error;
    const CharacterMesh mesh = prepare_mesh(*ch.value);
    auto canvas = Canvas::offscreen(640, 720);
    ASSERT_TRUE(canvas.ok());
    Canvas& c = **canvas.value;
    ASSERT_TRUE(c.antialias());
    DrawList list;
    auto frame = [&](int f) {
      c.clear(Rgba{1, 1, 1, 1});
      list.clear();
      const Affine2 view = Affine2::translate(40 + 20 * std::sin(f * 0.1), 30) * Affine2::scale(1.1, 1.1);
      build_draw_list(*ch.value, mesh, {}, view, 0.25, list);
      EXPECT_EQ(c.draw(list), "");
    };
    for (int f = 0; f < 30; ++f) frame(f);
    const long before = test::allocation_count();
    for (int f = 30; f < 90; ++f) frame(f);
    EXPECT_EQ(test::allocation_count() - before, 0) << file;
  }
}

}  // namespace
}  // namespace mar
