// Fringe anti-aliasing (DrawList::fringe): the geometry the GPU draws. A GPU colours a pixel
// when its centre is inside a triangle, with the vertex colours interpolated there; sampled that
// way here, on the CPU, the fringed triangles must give what the exact-coverage rasterizer gives
// for the plain ones.
#include "character/load.h"
#include "character/svg_loader.h"
#include "render/canvas.h"
#include "render/raster.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

namespace mar {
namespace {

// What a GPU draws: every triangle in order, pixel centres inside it take the interpolated
// straight-alpha colour blended over the premultiplied target (SDL_BLENDMODE_BLEND).
// Untextured triangles only.
void sample_centres(const DrawList& l, std::vector<float>& px, int w, int h) {
  for (size_t t = 0; t + 2 < l.indices.size(); t += 3) {
    const SDL_Vertex* v[3] = {&l.vertices[size_t(l.indices[t])], &l.vertices[size_t(l.indices[t + 1])],
                              &l.vertices[size_t(l.indices[t + 2])]};
    const double ax = v[0]->position.x, ay = v[0]->position.y, bx = v[1]->position.x, by = v[1]->position.y;
    const double cx = v[2]->position.x, cy = v[2]->position.y;
    const double det = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    if (std::abs(det) < 1e-12) continue;
    const int x0 = std::max(0, int(std::floor(std::min({ax, bx, cx})))), x1 = std::min(w - 1, int(std::ceil(std::max({ax, bx, cx}))));
    const int y0 = std::max(0, int(std::floor(std::min({ay, by, cy})))), y1 = std::min(h - 1, int(std::ceil(std::max({ay, by, cy}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        // (nudged: a centre on an edge two triangles share goes to one of them, as a GPU's fill
        // rule has it)
        const double px_ = x + 0.5 + 1.1e-6, py = y + 0.5 + 1.3e-6;
        const double u = ((px_ - ax) * (cy - ay) - (py - ay) * (cx - ax)) / det;
        const double s = ((bx - ax) * (py - ay) - (by - ay) * (px_ - ax)) / det;
        if (u < 0 || s < 0 || u + s > 1) continue;
        const double wt[3] = {1 - u - s, u, s};
        double c[4] = {0, 0, 0, 0};
        for (int k = 0; k < 3; ++k) {
          const SDL_Color& col = v[k]->color;
          c[0] += wt[k] * col.r / 255.0;
          c[1] += wt[k] * col.g / 255.0;
          c[2] += wt[k] * col.b / 255.0;
          c[3] += wt[k] * col.a / 255.0;
        }
        float* d = &px[(size_t(y) * size_t(w) + size_t(x)) * 4];
        for (int k = 0; k < 3; ++k) d[k] = float(c[k] * c[3] + d[k] * (1 - c[3]));
        d[3] = float(c[3] + d[3] * (1 - c[3]));
      }
  }
}

struct Sampled {
  int w, h;
  std::vector<float> px;
  Sampled(int w_, int h_) : w(w_), h(h_), px(size_t(w_) * size_t(h_) * 4, 0.0f) {}
  double alpha(int x, int y) const { return px[(size_t(y) * size_t(w) + size_t(x)) * 4 + 3]; }
};

// A stroke thinner than a pixel: a 1 px fringe at alpha = its width, the coverage the exact
// rasterizer gives it (Raster.AStrokeThinnerThanAPixelCoversItsWidth).
TEST(Fringe, AStrokeThinnerThanAPixelIsDrawnAtItsCoverage) {
  DrawList l;
  l.fringe = true;
  StrokeStyle st;
  st.half_width = 0.15;
  const std::vector<Vec2> line{{5, 10.5}, {35, 10.5}};
  stroke_polyline(line, false, st, {0, 0, 0, 255}, l);
  Sampled s(40, 20);
  sample_centres(l, s.px, s.w, s.h);
  for (int x = 6; x < 34; ++x) {
    EXPECT_NEAR(s.alpha(x, 10), 0.3, 0.01) << x;
    EXPECT_NEAR(s.alpha(x, 9), 0, 1e-3) << x;  // (its centre a pixel away: the fringe's outer edge)
    EXPECT_NEAR(s.alpha(x, 11), 0, 1e-3) << x;
  }
}

// A thick stroke: pixels a whole pixel inside are opaque, its edges carry their coverage, and
// the butt end stops where the line does.
TEST(Fringe, AThickStrokeHasAnOpaqueCoreAndEdgesAtTheirCoverage) {
  DrawList l;
  l.fringe = true;
  StrokeStyle st;
  st.half_width = 2.25;  // rows 8.25 .. 12.75
  const std::vector<Vec2> line{{5, 10.5}, {30.25, 10.5}};
  stroke_polyline(line, false, st, {0, 0, 0, 255}, l);
  Sampled s(40, 20);
  sample_centres(l, s.px, s.w, s.h);
  for (int x = 7; x < 29; ++x) {
    EXPECT_NEAR(s.alpha(x, 8), 0.75, 0.01) << x;
    for (int y = 9; y <= 11; ++y) EXPECT_NEAR(s.alpha(x, y), 1, 1e-6) << x << "," << y;
    EXPECT_NEAR(s.alpha(x, 12), 0.75, 0.01) << x;
    EXPECT_EQ(s.alpha(x, 13), 0) << x;
  }
  EXPECT_NEAR(s.alpha(30, 10), 0.25, 0.01);  // the end at x = 30.25
  EXPECT_NEAR(s.alpha(5, 10), 1.0, 0.01);
  EXPECT_NEAR(s.alpha(4, 10), 0.0, 0.01);
}

// A gradient stroke on the GPU: its triangles sample the gradient's texture, which is uploaded
// premultiplied, so their modulation colours are premultiplied too; texture coordinates run
// from the left of the stroke (0) to its right (1). (A gradient in objectBoundingBox units on a
// straight line paints nothing, as SVG says: its box has no height.)
TEST(Fringe, AGradientStrokeCarriesPremultipliedColoursAndItsTextureCoordinates) {
  auto ch = load_svg_string(R"svg(<svg xmlns="http://www.w3.org/2000/svg" width="60" height="30">
      <defs><linearGradient id="g" gradientUnits="userSpaceOnUse" x1="5" x2="55"><stop offset="0" stop-color="#f00"/>
      <stop offset="1" stop-color="#00f"/></linearGradient></defs>
      <path d="M5 15 H55" fill="none" stroke="url(#g)" stroke-width="6" stroke-opacity="0.5"/></svg>)svg", "g.svg");
  ASSERT_TRUE(ch.ok()) << ch.error;
  DrawList l;
  l.fringe = true;
  build_draw_list(*ch.value, prepare_mesh(*ch.value), {}, Affine2{}, 0.25, l);
  ASSERT_EQ(l.batches.size(), 1u);
  ASSERT_TRUE(l.batches[0].texture);
  float left = 1, right = 0;
  for (const SDL_Vertex& v : l.vertices) {
    EXPECT_LE(v.color.r, v.color.a);
    EXPECT_LE(v.color.a, 128);
    if (v.position.x < 6) left = std::min(left, v.tex_coord.x);
    if (v.position.x > 54) right = std::max(right, v.tex_coord.x);
  }
  EXPECT_LT(left, 0.1f);
  EXPECT_GT(right, 0.9f);
}

// The GPU draws no layers: on its list a group's opacity is multiplied into its shapes.
TEST(Fringe, AGroupsOpacityIsInItsShapesOnTheGpusList) {
  auto ch = load_svg_string(R"svg(<svg xmlns="http://www.w3.org/2000/svg" width="60" height="30">
      <g opacity="0.5"><rect width="20" height="20" fill="#f00"/><rect x="10" width="20" height="20" fill="#00f" fill-opacity="0.5"/></g>
      <rect x="40" width="10" height="10" fill="#0f0"/></svg>)svg", "o.svg");
  ASSERT_TRUE(ch.ok()) << ch.error;
  DrawList gpu, cpu;
  gpu.fringe = true;
  build_draw_list(*ch.value, prepare_mesh(*ch.value), {}, Affine2{}, 0.25, gpu);
  build_draw_list(*ch.value, prepare_mesh(*ch.value), {}, Affine2{}, 0.25, cpu);
  EXPECT_TRUE(gpu.layers.empty());
  ASSERT_EQ(cpu.layers.size(), 1u);
  int most[3] = {0, 0, 0};  // the largest alpha of red, blue and green vertices
  for (const SDL_Vertex& v : gpu.vertices) {
    const int k = v.color.r > 200 ? 0 : v.color.b > 200 ? 1 : v.color.g > 200 ? 2 : -1;
    if (k >= 0) most[k] = std::max(most[k], int(v.color.a));
  }
  EXPECT_NEAR(most[0], 128, 1);
  EXPECT_NEAR(most[1], 64, 1);
  EXPECT_EQ(most[2], 255);  // (after the group)
}

// A whole drawing at an opacity (a cast's character fading in): on the software rasterizer's
// list one layer round all of it, outside its own groups' layers; on the GPU's, the factor in
// every shape's alpha.
TEST(Fringe, AWholeDrawingsOpacityIsOneLayerOrInEveryShape) {
  auto ch = load_svg_string(R"svg(<svg xmlns="http://www.w3.org/2000/svg" width="60" height="30">
      <g opacity="0.5"><rect width="20" height="20" fill="#f00"/></g>
      <rect x="40" width="10" height="10" fill="#0f0"/></svg>)svg", "o.svg");
  ASSERT_TRUE(ch.ok()) << ch.error;
  DrawList gpu, cpu;
  gpu.fringe = true;
  build_draw_list(*ch.value, prepare_mesh(*ch.value), {}, Affine2{}, 0.25, gpu, {}, 0.5f);
  build_draw_list(*ch.value, prepare_mesh(*ch.value), {}, Affine2{}, 0.25, cpu, {}, 0.5f);
  EXPECT_TRUE(gpu.layers.empty());
  ASSERT_EQ(cpu.layers.size(), 2u);
  EXPECT_EQ(cpu.layers[0].begin, 0);  // (outer first: the whole drawing, then its group)
  EXPECT_EQ(cpu.layers[0].mask_end, int(cpu.indices.size()));
  EXPECT_FLOAT_EQ(cpu.layers[0].opacity, 0.5f);
  EXPECT_FLOAT_EQ(cpu.layers[1].opacity, 0.5f);
  EXPECT_LT(cpu.layers[1].mask_end, cpu.layers[0].mask_end);
  int most[2] = {0, 0};  // the largest alpha of red and green vertices
  for (const SDL_Vertex& v : gpu.vertices) {
    const int k = v.color.r > 100 ? 0 : v.color.g > 100 ? 1 : -1;
    if (k >= 0) most[k] = std::max(most[k], int(v.color.a));
  }
  EXPECT_NEAR(most[0], 64, 1);
  EXPECT_NEAR(most[1], 128, 1);
  DrawList plain;
  build_draw_list(*ch.value, prepare_mesh(*ch.value), {}, Affine2{}, 0.25, plain);
  EXPECT_EQ(plain.layers.size(), 1u);  // (at opacity 1: no layer of its own)
}

// Fills: one thinner than a pixel is drawn at its coverage (0.4 px wide: alpha 0.4 along its
// middle), and a long rectangle, triangulated into slivers from side to side, stays opaque
// inside (a sliver turned over by the pull is not a thin part).
TEST(Fringe, AThinFillIsFaintAndAThickOneOpaque) {
  const std::string svg = R"(<svg xmlns="http://www.w3.org/2000/svg" width="60" height="40" viewBox="0 0 60 40">
    <rect x="5" y="10.3" width="50" height="0.4" fill="#000"/>
    <path d="M5 20 L15 20.5 L25 20 L35 20.5 L45 20 L55 20.5 L55 35 L45 34.5 L35 35 L25 34.5 L15 35 L5 34.5 Z" fill="#000"/></svg>)";
  auto ch = load_character(test::write_temp("thin-fill.svg", svg));
  ASSERT_TRUE(ch.ok()) << ch.error;
  DrawList l;
  l.fringe = true;
  build_draw_list(*ch.value, prepare_mesh(*ch.value), {}, Affine2::identity(), 0.2, l);
  Sampled s(60, 40);
  sample_centres(l, s.px, s.w, s.h);
  for (int x = 8; x < 52; ++x) EXPECT_NEAR(s.alpha(x, 10), 0.4, 0.05) << x;
  for (int y = 22; y < 33; ++y)
    for (int x = 7; x < 53; ++x) EXPECT_NEAR(s.alpha(x, y), 1.0, 1e-3) << x << "," << y;
}

// Every drawn example character at 640x720: sampled at pixel centres as a GPU does, the
// fringed triangles put at least 99% of pixels within 16/255 of the exact rasterizer's; the
// plain triangles (aliased) far fewer.
TEST(Fringe, EveryExampleCharacterMatchesTheExactRasterizer) {
  for (const char* name : {"figure", "butterfly", "koi", "singer", "candle", "boy"}) {
    auto ch = load_character((test::characters_dir() / (std::string(name) + ".svg")).string());
    ASSERT_TRUE(ch.ok()) << ch.error;
    const CharacterMesh mesh = prepare_mesh(*ch.value);
    const int w = 640, h = 720;
    const Affine2 view = fit_view(ch.value->width, ch.value->height, w, h);
    DrawList plain, fringed;
    fringed.fringe = true;
    build_draw_list(*ch.value, mesh, {}, view, 0.2, plain);
    build_draw_list(*ch.value, mesh, {}, view, 0.2, fringed);
    std::vector<std::uint8_t> exact(size_t(w) * size_t(h) * 4, 0);
    Rasterizer r;
    Compositor layers;  // (the koi's fin, stroked and at 0.9 opacity, is a layer)
    layers.draw(r, plain, {exact.data(), w, h, w * 4});
    Sampled f(w, h), a(w, h);
    sample_centres(fringed, f.px, w, h);
    sample_centres(plain, a.px, w, h);
    auto off = [&](const Sampled& s) {
      int n = 0;
      for (size_t i = 0; i < exact.size(); i += 4) {
        int d = 0;
        for (size_t k = 0; k < 4; ++k) d = std::max(d, std::abs(int(std::lround(s.px[i + k] * 255)) - int(exact[i + k])));
        n += d > 16;
      }
      return n;
    };
    const int nf = off(f), na = off(a);
    std::cout << name << ": fringed " << 100.0 * (1 - double(nf) / (w * h)) << "% of pixels within 16/255 of the exact coverage, aliased "
              << 100.0 * (1 - double(na) / (w * h)) << "%" << std::endl;
    EXPECT_LE(nf, w * h / 100) << name;
    EXPECT_LT(nf * 3, na) << name;
  }
}

}  // namespace
}  // namespace mar
