// The anti-aliased rasterizer: edge pixels carry the share of their area a shape covers, shapes
// have no seams inside and strokes no pinholes, and whole characters agree with a 4x
// supersampled rendering of SDL's aliased triangles (an independent reference).
#include "character/load.h"
#include "render/canvas.h"
#include "render/raster.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

namespace mar {
namespace {

struct Target {
  int w, h;
  std::vector<std::uint8_t> px;
  Target(int w_, int h_) : w(w_), h(h_), px(size_t(w_) * size_t(h_) * 4, 0) {}
  PixelTarget view() { return {px.data(), w, h, w * 4}; }
  int alpha(int x, int y) const { return px[(size_t(y) * size_t(w) + size_t(x)) * 4 + 3]; }
};

void push_triangle(DrawList& l, Vec2 a, Vec2 b, Vec2 c, SDL_Color col = {0, 0, 0, 255}) {
  for (const Vec2& p : {a, b, c}) {
    l.indices.push_back(int(l.vertices.size()));
    l.vertices.push_back(SDL_Vertex{{float(p.x()), float(p.y())}, col, {0, 0}});
  }
}

void one_batch(DrawList& l) { l.batches = {{nullptr, 0, int(l.indices.size())}}; }

// A quad as two triangles (sharing the diagonal a-c).
void push_quad(DrawList& l, Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  push_triangle(l, a, b, c);
  push_triangle(l, a, c, d);
}

TEST(Raster, AStraightEdgeCarriesItsCoverage) {
  Target t(20, 10);
  DrawList l;
  push_quad(l, {2.25, 1}, {12.5, 1}, {12.5, 9}, {2.25, 9});
  one_batch(l);
  Rasterizer r;
  r.draw(l, t.view());
  EXPECT_NEAR(t.alpha(2, 5), 0.75 * 255, 1.5);  // 3/4 of the pixel
  EXPECT_EQ(t.alpha(3, 5), 255);
  EXPECT_NEAR(t.alpha(12, 5), 0.5 * 255, 1.5);
  EXPECT_EQ(t.alpha(13, 5), 0);
  EXPECT_EQ(t.alpha(1, 5), 0);
}

TEST(Raster, ADiagonalEdgeCoversTheAreaUnderIt) {
  Target t(8, 8);
  DrawList l;
  push_triangle(l, {0, 0}, {8, 0}, {0, 8});  // the edge x + y = 8 halves the pixels it crosses
  one_batch(l);
  Rasterizer r;
  r.draw(l, t.view());
  for (int x = 0; x < 8; ++x) EXPECT_NEAR(t.alpha(x, 7 - x), 127.5, 1.5) << x;
  EXPECT_EQ(t.alpha(2, 2), 255);
  EXPECT_EQ(t.alpha(6, 6), 0);
}

// A shape drawn as many triangles shares their edges: inside, every pixel is fully covered,
// whatever the angle of the inner edges (painting each triangle on its own would leave seams).
TEST(Raster, AShapeOfManyTrianglesHasNoSeams) {
  Target t(64, 64);
  DrawList l;
  const Vec2 c(32.3, 31.7);
  const int n = 37;
  for (int k = 0; k < n; ++k) {  // a fan: 37 thin triangles meeting at the centre
    const double a0 = 2 * M_PI * k / n, a1 = 2 * M_PI * (k + 1) / n;
    push_triangle(l, c, c + 28.0 * Vec2(std::cos(a0), std::sin(a0)), c + 28.0 * Vec2(std::cos(a1), std::sin(a1)),
                  {40, 90, 200, 255});
  }
  l.item_starts = {0};
  one_batch(l);
  Rasterizer r;
  r.draw(l, t.view());
  int inside = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      if ((Vec2(x + 0.5, y + 0.5) - c).norm() < 26.0) {
        ++inside;
        EXPECT_EQ(t.alpha(x, y), 255) << x << "," << y;
      }
  EXPECT_GT(inside, 2000);
}

TEST(Raster, AStrokeThinnerThanAPixelCoversItsWidth) {
  Target t(40, 20);
  DrawList l;
  StrokeStyle st;
  st.half_width = 0.15;  // 0.3 px wide, along the middle of row 10
  const std::vector<Vec2> line{{5, 10.5}, {35, 10.5}};
  stroke_polyline(line, false, st, {0, 0, 0, 255}, l);
  l.item_starts = {0};
  one_batch(l);
  Rasterizer r;
  r.draw(l, t.view());
  for (int x = 6; x < 34; ++x) EXPECT_NEAR(t.alpha(x, 10), 0.3 * 255, 2.0) << x;
  EXPECT_EQ(t.alpha(20, 9), 0);
}

// A thick zig-zag stroke at 3x zoom, every join kind: no pixel well inside the stroke shows
// the background (a pinhole or a crack at a join).
TEST(Raster, StrokeJoinsAndCapsHaveNoPinholes) {
  for (LineJoin join : {LineJoin::Miter, LineJoin::Round, LineJoin::Bevel}) {
    Target t(300, 120);
    DrawList l;
    StrokeStyle st;
    st.half_width = 9;
    st.join = join;
    st.cap = LineCap::Round;
    st.tolerance = 0.25;
    std::vector<Vec2> zig;
    for (int k = 0; k < 8; ++k) zig.push_back(Vec2(20 + 36.7 * k, k % 2 ? 95.3 : 24.9));
    stroke_polyline(zig, false, st, {200, 30, 30, 255}, l);
    l.item_starts = {0};
    one_batch(l);
    Rasterizer r;
    r.draw(l, t.view());
    int checked = 0;
    for (int y = 0; y < t.h; ++y)
      for (int x = 0; x < t.w; ++x) {
        const Vec2 p(x + 0.5, y + 0.5);
        double dist = 1e9;
        for (size_t k = 0; k + 1 < zig.size(); ++k) {
          const Vec2 d = zig[k + 1] - zig[k];
          const double s = std::clamp((p - zig[k]).dot(d) / d.squaredNorm(), 0.0, 1.0);
          dist = std::min(dist, (p - (zig[k] + s * d)).norm());
        }
        // Within the stroke, a pixel off its outer corners (which a bevel or a miter cuts).
        bool inside_a_segment = false;
        for (size_t k = 0; k + 1 < zig.size(); ++k) {
          const Vec2 d = zig[k + 1] - zig[k];
          const double s = (p - zig[k]).dot(d) / d.squaredNorm();
          const double off = std::abs(d.x() * (p - zig[k]).y() - d.y() * (p - zig[k]).x()) / d.norm();
          inside_a_segment = inside_a_segment || (s > 0 && s < 1 && off < st.half_width - 1.0);
        }
        if (dist > st.half_width - 1.0 || (join != LineJoin::Round && !inside_a_segment)) continue;
        ++checked;
        ASSERT_EQ(t.alpha(x, y), 255) << "join " << int(join) << " at " << x << "," << y;
      }
    EXPECT_GT(checked, 5000);
  }
}

// Straight colour over a premultiplied background: half coverage of opaque red over opaque
// white is pink, and over transparent it is red at half alpha (premultiplied 128, 0, 0, 128).
TEST(Raster, CompositesPremultiplied) {
  Target t(4, 2);
  for (int i = 0; i < 4; ++i) t.px[size_t(i) * 4 + 0] = t.px[size_t(i) * 4 + 1] = t.px[size_t(i) * 4 + 2] = t.px[size_t(i) * 4 + 3] = 255;
  DrawList l;
  push_quad(l, {0, 0}, {4, 0}, {4, 2}, {0, 2});
  for (auto& v : l.vertices) v.color = {255, 0, 0, 128};
  one_batch(l);
  Rasterizer r;
  r.draw(l, t.view());
  EXPECT_NEAR(t.px[0], 255, 1);
  EXPECT_NEAR(t.px[1], 127, 1);
  EXPECT_EQ(t.px[3], 255);
  EXPECT_NEAR(t.px[16 + 0], 128, 1);  // row 1 was transparent
  EXPECT_EQ(t.px[16 + 1], 0);
  EXPECT_NEAR(t.px[16 + 3], 128, 1);
}

// Every example character, at a frame size the shows use: at least 99% of pixels within 16/255
// of the 4x supersampled frame (`--supersample 4`: the canvas at 4x, box-filtered). For the
// drawings, also of an independent reference: SDL's aliased triangles at 4x, box-filtered (a
// textured character samples its image bilinearly, SDL nearest, so there the two references
// differ inside the picture, not at its edges). MARIONETTE_TEST_DUMP=DIR keeps the pictures.
TEST(Raster, EveryExampleCharacterMatchesFourTimesSupersampling) {
  const char* dump = std::getenv("MARIONETTE_TEST_DUMP");
  for (const char* name : {"figure", "butterfly", "koi", "singer", "candle", "boy", "boy.png"}) {
    const std::string file = std::string(name).find('.') == std::string::npos ? std::string(name) + ".svg" : name;
    auto ch = load_character((test::characters_dir() / file).string());
    ASSERT_TRUE(ch.ok()) << ch.error;
    const CharacterMesh mesh = prepare_mesh(*ch.value);
    RenderOptions o;
    o.width = 640;
    o.height = 720;
    o.background = Rgba{1, 1, 1, 1};
    auto aa = render_character(*ch.value, mesh, o);
    o.supersample = 4;
    auto ss = render_character(*ch.value, mesh, o);
    o.antialias = false;
    auto sdl = render_character(*ch.value, mesh, o);
    o.supersample = 1;
    auto hard = render_character(*ch.value, mesh, o);
    ASSERT_TRUE(aa.ok() && ss.ok() && sdl.ok() && hard.ok());
    if (dump) {
      for (auto [img, what] : {std::pair{&aa, "aa"}, {&ss, "ss4"}, {&sdl, "sdl4"}, {&hard, "aliased"}})
        write_png(std::string(dump) + "/" + file + "." + what + ".png", *img->value);
    }
    const ImageDiff d = compare_images(*aa.value, *ss.value, 16), di = compare_images(*aa.value, *sdl.value, 16);
    const ImageDiff dh = compare_images(*hard.value, *ss.value, 16);
    const bool textured = file.ends_with(".png");
    std::cout << file << ": anti-aliased " << 100.0 * (1 - d.differing_share()) << "% of pixels within 16/255 of --supersample 4 ("
              << d.differing << " off, max " << d.max_channel_diff << "), " << 100.0 * (1 - di.differing_share())
              << "% of SDL's triangles at 4x; aliased " << 100.0 * (1 - dh.differing_share()) << "%" << std::endl;
    EXPECT_GE(1 - d.differing_share(), 0.99) << file;
    if (!textured) {
      EXPECT_GE(1 - di.differing_share(), 0.99) << file;
    }
    EXPECT_GT(dh.differing, d.differing) << file;
  }
}

}  // namespace
}  // namespace mar
