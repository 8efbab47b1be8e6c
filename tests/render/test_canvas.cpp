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

// A filled open path fills as if closed, and its stroke leaves the closing edge bare.
TEST(render_character, AFilledOpenPathsStrokeDoesNotClose) {
  auto edge_alpha = [](const std::string& close) {
    const Character ch = svg(R"(<path d="M2 4 L18 4 L10 18)" + close + R"(" fill="#ff0000" stroke="#0000ff" stroke-width="2"/>)");
    auto img = render_character(ch, prepare_mesh(ch), RenderOptions{});
    EXPECT_TRUE(img.ok()) << img.error;
    // pixel (5, 11): its centre 0.68 px outside the closing edge from (10, 18) to (2, 4)
    return img.ok() ? int(px(*img.value, 5, 11)[3]) : -1;
  };
  EXPECT_LT(edge_alpha(""), 60);
  EXPECT_GT(edge_alpha(" z"), 150);
  const Character open = svg(R"(<path d="M2 4 L18 4 L10 18" fill="#ff0000"/>)");
  auto img = render_character(open, prepare_mesh(open), RenderOptions{});
  ASSERT_TRUE(img.ok());
  EXPECT_EQ(px(*img.value, 10, 8)[0], 255) << "filled inside";
  EXPECT_EQ(px(*img.value, 10, 8)[3], 255);
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

// A gradient stroke samples its texture where the stroke lies, at rest and when the shape moves:
// red on the left, blue on the right, wherever the shape goes.
TEST(render_character, GradientStrokesFollowTheirShape) {
  const Character ch = svg(R"svg(<defs><linearGradient id="g"><stop offset="0" stop-color="#f00"/>
      <stop offset="1" stop-color="#00f"/></linearGradient></defs>
      <rect x="4" y="4" width="40" height="12" fill="none" stroke="url(#g)" stroke-width="4"/>)svg", 60, 40);
  const CharacterMesh mesh = prepare_mesh(ch);
  auto rest = render_character(ch, mesh, RenderOptions{});
  ASSERT_TRUE(rest.ok()) << rest.error;
  auto red = [](const uint8_t* p) { return p[0] > 180 && p[2] < 80 && p[3] > 200; };
  auto blue = [](const uint8_t* p) { return p[2] > 180 && p[0] < 80 && p[3] > 200; };
  EXPECT_TRUE(red(px(*rest.value, 4, 10)));
  EXPECT_TRUE(blue(px(*rest.value, 44, 10)));
  EXPECT_EQ(px(*rest.value, 24, 10)[3], 0);  // (no fill)
  // Moved 10 right and 20 down: the colours go with it.
  std::vector<Points> moved{ch.shapes[0].points};
  for (Vec2& p : moved[0]) p += Vec2(10, 20);
  auto img = render_character(ch, mesh, RenderOptions{}, moved);
  ASSERT_TRUE(img.ok()) << img.error;
  EXPECT_TRUE(red(px(*img.value, 14, 30)));
  EXPECT_TRUE(blue(px(*img.value, 54, 30)));
  EXPECT_EQ(px(*img.value, 4, 10)[3], 0);
}

TEST(render_character, DashesFollowThePatternAndTheirOffset) {
  const Character ch = svg(R"(<path d="M0 5 H60" stroke="#000" stroke-width="4" stroke-dasharray="10 5" stroke-dashoffset="5"/>)", 60, 10);
  auto img = render_character(ch, prepare_mesh(ch), RenderOptions{});
  ASSERT_TRUE(img.ok()) << img.error;
  // Offset 5: dash 0-5, gap 5-10, dash 10-20, gap 20-25, dash 25-35 ...
  for (int x : {2, 12, 18, 27, 33}) EXPECT_EQ(px(*img.value, x, 5)[3], 255) << x;
  for (int x : {7, 22, 37}) EXPECT_EQ(px(*img.value, x, 5)[3], 0) << x;
  // Squeezed to half its length, every dash and gap is half as long (dashes are measured along
  // the rest outline): dash 0-2.5, gap 2.5-5, dash 5-10, gap 10-12.5, dash 12.5-17.5.
  std::vector<Points> squeezed{ch.shapes[0].points};
  for (Vec2& p : squeezed[0]) p.x() *= 0.5;
  auto half = render_character(ch, prepare_mesh(ch), RenderOptions{}, squeezed);
  ASSERT_TRUE(half.ok()) << half.error;
  for (int x : {1, 6, 8, 13, 16}) EXPECT_EQ(px(*half.value, x, 5)[3], 255) << x;
  for (int x : {3, 10, 40}) EXPECT_EQ(px(*half.value, x, 5)[3], 0) << x;
}

TEST(render_character, PaintOrderPutsTheStrokeUnderTheFill) {
  const Character ch = svg(R"(<rect x="5" y="5" width="10" height="10" fill="#f00" stroke="#00f" stroke-width="4" paint-order="stroke"/>)");
  auto img = render_character(ch, prepare_mesh(ch), RenderOptions{});
  ASSERT_TRUE(img.ok()) << img.error;
  EXPECT_EQ(px(*img.value, 6, 10)[0], 255);  // inside the outline: the fill, over the stroke
  EXPECT_EQ(px(*img.value, 4, 10)[2], 255);  // outside: the stroke's outer half
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
