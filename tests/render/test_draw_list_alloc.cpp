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

// A drawing with layers (a clip path, a mask, blur, group opacity) and dashed gradient strokes.
const char* kLayered = R"svg(<svg xmlns="http://www.w3.org/2000/svg" width="200" height="140">
  <defs><clipPath id="c"><circle cx="50" cy="40" r="30"/></clipPath>
    <mask id="m"><rect x="110" y="10" width="80" height="60" fill="#808080"/></mask>
    <filter id="b"><feGaussianBlur stdDeviation="4"/><feOffset dx="3" dy="3"/></filter>
    <linearGradient id="g"><stop offset="0" stop-color="red"/><stop offset="1" stop-color="blue"/></linearGradient></defs>
  <rect x="10" y="10" width="80" height="60" fill="#c00" clip-path="url(#c)"/>
  <rect x="110" y="10" width="80" height="60" fill="#00c" mask="url(#m)"/>
  <g opacity="0.5" filter="url(#b)"><rect x="10" y="80" width="40" height="40" fill="#0a0"/>
    <rect x="30" y="90" width="40" height="40" fill="#0a0" stroke="url(#g)" stroke-width="3" stroke-dasharray="6 3"/></g>
</svg>)svg";

// Drawing a frame with the anti-aliased rasterizer allocates nothing once its buffers have
// grown to the canvas: a drawing, a textured (raster) character and a drawing with layers,
// moving every frame.
TEST(Canvas, AntiAliasedFramesAllocateNothingAfterWarmUp) {
  const std::string layered = test::write_temp("layered.svg", kLayered);
  for (const std::string& file : {std::string("figure.svg"), std::string("boy.png"), layered}) {
    auto ch = load_character(file == layered ? file : (test::characters_dir() / file).string());
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
    if (file == layered) {
      EXPECT_EQ(list.layers.size(), 3u);
    }
  }
}

}  // namespace
}  // namespace mar
