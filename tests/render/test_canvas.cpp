#include "character/svg_loader.h"
#include "render/canvas.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

Character svg(const std::string& body, int w = 20, int h = 20) {
  auto r = load_svg_string("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(w) +
                               "\" height=\"" + std::to_string(h) + "\">" + body + "</svg>",
                           "t.svg");
  EXPECT_TRUE(r.ok()) << r.error;
  return *r.value;
}

const uint8_t* px(const Image& img, int x, int y) { return &img.rgba[(static_cast<size_t>(y) * img.width + x) * 4]; }

TEST(render_character, FillsInsideLeavesOutsideTransparent) {
  const Character ch = svg(R"(<rect x="5" y="5" width="10" height="10" fill="#ff0000"/>)");
  auto img = render_character(ch, prepare_mesh(ch), RenderOptions{});
  ASSERT_TRUE(img.ok()) << img.error;
  EXPECT_EQ(img.value->width, 20);
  const uint8_t* in = px(*img.value, 10, 10);
  EXPECT_EQ(in[0], 255);
  EXPECT_EQ(in[1], 0);
  EXPECT_EQ(in[3], 255);
  EXPECT_EQ(px(*img.value, 2, 2)[3], 0);
  EXPECT_EQ(px(*img.value, 17, 17)[3], 0);
}

TEST(render_character, TranslucentOnTransparentKeepsStraightColour) {
  const Character ch = svg(R"(<rect width="20" height="20" fill="#ff8000" fill-opacity="0.5"/>)");
  auto img = render_character(ch, prepare_mesh(ch), RenderOptions{});
  ASSERT_TRUE(img.ok());
  const uint8_t* p = px(*img.value, 10, 10);
  EXPECT_NEAR(p[0], 255, 2);
  EXPECT_NEAR(p[1], 128, 2);
  EXPECT_NEAR(p[3], 128, 1);
}

TEST(render_character, BackgroundSizeAndLayerOrder) {
  const Character ch = svg(R"(<rect width="20" height="20" fill="#0000ff"/><rect x="5" y="5" width="10" height="10" fill="#00ff00"/>)");
  RenderOptions o;
  o.width = 40;
  o.height = 40;
  o.background = Rgba{1, 1, 1, 1};
  auto img = render_character(ch, prepare_mesh(ch), o);
  ASSERT_TRUE(img.ok());
  EXPECT_EQ(img.value->width, 40);
  EXPECT_EQ(px(*img.value, 20, 20)[1], 255);  // later shape on top
  EXPECT_EQ(px(*img.value, 3, 3)[2], 255);
}

TEST(render_character, SupersamplingSmoothsAliasedEdges) {
  const Character ch = svg(R"(<rect x="0" y="0" width="10.5" height="20" fill="#000000"/>)");
  RenderOptions o;
  o.antialias = false;  // SDL's triangles: a pixel is in or out
  auto hard = render_character(ch, prepare_mesh(ch), o);
  const int h = px(*hard.value, 10, 10)[3];
  EXPECT_TRUE(h == 0 || h == 255);
  o.supersample = 4;
  auto img = render_character(ch, prepare_mesh(ch), o);
  ASSERT_TRUE(img.ok());
  const int a = px(*img.value, 10, 10)[3];
  EXPECT_GT(a, 90);
  EXPECT_LT(a, 165);  // half-covered pixel
}

TEST(render_character, TexturedFillSamplesTheImage) {
  Character ch;
  ch.width = ch.height = 8;
  ch.layers = {"image"};
  auto tex = std::make_shared<Texture>();
  tex->width = tex->height = 4;  // quadrants: red, green / blue, white
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      const int q = (y >= 2) * 2 + (x >= 2);
      const uint8_t c[4][4] = {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, {255, 255, 255, 255}};
      tex->rgba.insert(tex->rgba.end(), c[q], c[q] + 4);
    }
  }
  SubShape s;
  s.points = {{0, 0}, {8, 0}, {8, 8}, {0, 8}};
  s.contours = {{0, 4, true}};
  s.fill.enabled = true;
  s.fill.color = Rgba{1, 1, 1, 1};
  s.fill.texture = tex;
  s.fill.uv_from_point = Affine2::scale(1.0 / 8, 1.0 / 8);
  ch.shapes.push_back(s);
  auto img = render_character(ch, prepare_mesh(ch), RenderOptions{});
  ASSERT_TRUE(img.ok()) << img.error;
  // SDL's software renderer maps texture coordinates with up to one texel of stretch,
  // so only the quadrant interiors are checked.
  auto rgb = [&](int x, int y) {
    const uint8_t* p = px(*img.value, x, y);
    return (p[0] > 200) * 4 + (p[1] > 200) * 2 + (p[2] > 200);
  };
  EXPECT_EQ(rgb(1, 1), 4);  // red
  EXPECT_EQ(rgb(7, 1), 2);  // green
  EXPECT_EQ(rgb(1, 7), 1);  // blue
  EXPECT_EQ(rgb(7, 7), 7);  // white
}

TEST(Canvas, RejectsBadSizes) {
  EXPECT_FALSE(Canvas::offscreen(0, 10).ok());
  EXPECT_FALSE(Canvas::offscreen(10, 100000).ok());
}

TEST(fit_view, CentresAndScalesUniformly) {
  const Affine2 v = fit_view(100, 50, 200, 200);
  EXPECT_EQ(v.apply({0, 0}), Vec2(0, 50));
  EXPECT_EQ(v.apply({100, 50}), Vec2(200, 150));
}

}  // namespace
}  // namespace mar
