// Layers drawn (render/composite.h): group opacity over overlapping shapes, clip paths, masks
// and blur, at rest and deformed, on the anti-aliased rasterizer.
#include "character/svg_loader.h"
#include "render/canvas.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

Character svg(const std::string& body, int w = 100, int h = 60) {
  auto r = load_svg_string("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(w) + "\" height=\"" +
                               std::to_string(h) + "\">" + body + "</svg>",
                           "t.svg");
  EXPECT_TRUE(r.ok()) << r.error;
  return *r.value;
}

// Every shape's points moved by `d` (a pose).
std::vector<Points> moved_by(const Character& ch, const Vec2& d) {
  std::vector<Points> out;
  for (const SubShape& s : ch.shapes) {
    out.push_back(s.points);
    for (Vec2& p : out.back()) p += d;
  }
  return out;
}

const uint8_t* px(const Image& img, int x, int y) { return &img.rgba[(size_t(y) * size_t(img.width) + size_t(x)) * 4]; }

Image draw(const Character& ch, std::span<const Points> at = {}) {
  RenderOptions o;
  o.background = Rgba{1, 1, 1, 1};
  auto img = render_character(ch, prepare_mesh(ch), o, at);
  EXPECT_TRUE(img.ok()) << img.error;
  return img.ok() ? *img.value : Image{};
}

// Two overlapping squares in a group at half opacity: the overlap is no darker than the rest
// (the group is one layer), where multiplying the opacity into each would darken it.
TEST(Composite, AGroupAtHalfOpacityIsOneLayer) {
  const Image img = draw(svg(R"svg(<g opacity="0.5"><rect x="10" y="10" width="40" height="40" fill="#000"/>
      <rect x="30" y="20" width="40" height="40" fill="#000"/></g>)svg"));
  EXPECT_NEAR(px(img, 20, 15)[0], 128, 2);  // one square
  EXPECT_NEAR(px(img, 40, 30)[0], 128, 2);  // both
  EXPECT_EQ(px(img, 5, 5)[0], 255);
}

// A rectangle clipped by a circle: inside the circle it shows, outside it does not; move the
// shapes (a deformed pose) and the clip goes with them.
TEST(Composite, AClipPathClipsAndFollowsTheShapes) {
  const Character ch = svg(R"svg(<defs><clipPath id="c"><circle cx="30" cy="30" r="15"/></clipPath></defs>
      <rect x="5" y="5" width="50" height="50" fill="#f00" clip-path="url(#c)"/>)svg");
  const Image rest = draw(ch);
  EXPECT_EQ(px(rest, 30, 30)[1], 0);    // red inside
  EXPECT_EQ(px(rest, 8, 8)[1], 255);    // white in the rect's corner, outside the circle
  EXPECT_EQ(px(rest, 30, 17)[1], 0);    // just inside the top of the circle
  const Image m = draw(ch, moved_by(ch, Vec2(40, 0)));
  EXPECT_EQ(px(m, 70, 30)[1], 0);
  EXPECT_EQ(px(m, 30, 30)[1], 255);
  EXPECT_EQ(px(m, 48, 8)[1], 255);
}

// A luminance mask: white lets the shape through, 25% grey a quarter of it, black none.
TEST(Composite, ALuminanceMaskWeighsTheShape) {
  const Image img = draw(svg(R"svg(<defs><mask id="m"><rect x="0" y="0" width="30" height="60" fill="#fff"/>
      <rect x="30" y="0" width="30" height="60" fill="#404040"/></mask></defs>
      <rect x="5" y="5" width="80" height="50" fill="#000" mask="url(#m)"/>)svg"));
  EXPECT_EQ(px(img, 15, 30)[0], 0);
  EXPECT_NEAR(px(img, 45, 30)[0], 255 - 255 * 0x40 / 255, 3);
  EXPECT_EQ(px(img, 75, 30)[0], 255);
}

// A blurred square: its edge is soft over a few standard deviations, its middle unchanged, and
// its ink is kept (the blur moves coverage, it does not make or lose it).
TEST(Composite, ABlurSoftensEdgesAndKeepsTheInk) {
  const Character sharp = svg(R"svg(<rect x="30" y="15" width="40" height="30" fill="#000"/>)svg");
  const Character soft = svg(R"svg(<defs><filter id="b"><feGaussianBlur stdDeviation="3"/></filter></defs>
      <rect x="30" y="15" width="40" height="30" fill="#000" filter="url(#b)"/>)svg");
  const Image a = draw(sharp), b = draw(soft);
  EXPECT_EQ(px(b, 50, 30)[0], 0);               // the middle
  EXPECT_NEAR(px(b, 30, 30)[0], 128, 25);       // the edge: half
  EXPECT_LT(px(b, 27, 30)[0], 250);             // outside, a little ink
  EXPECT_GT(px(b, 33, 30)[0], 5);               // inside, a little light
  long ink_a = 0, ink_b = 0;
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 100; ++x) {
      ink_a += 255 - px(a, x, y)[0];
      ink_b += 255 - px(b, x, y)[0];
    }
  EXPECT_NEAR(double(ink_b) / double(ink_a), 1.0, 0.03);
}

// A blur and its shift go with the part: grown to twice its size and turned a quarter, a
// blurred, shifted shape is blurred twice as far and shifted along its turn.
TEST(Composite, ABlurScalesAndTurnsWithItsPart) {
  const Character ch = svg(R"svg(<defs><filter id="b"><feGaussianBlur stdDeviation="2"/><feOffset dx="4" dy="0"/></filter></defs>
      <rect x="30" y="15" width="40" height="30" fill="#000" filter="url(#b)"/>)svg");
  DrawList rest, grown;
  build_draw_list(ch, prepare_mesh(ch), {}, Affine2{}, 0.25, rest);
  std::vector<Points> at{ch.shapes[0].points};
  for (Vec2& p : at[0]) p = Vec2(50, 30) + 2 * Vec2(-(p.y() - 30), p.x() - 50);  // (x2, turned 90 degrees)
  build_draw_list(ch, prepare_mesh(ch), at, Affine2{}, 0.25, grown);
  ASSERT_EQ(rest.layers.size(), 1u);
  ASSERT_EQ(grown.layers.size(), 1u);
  EXPECT_NEAR(rest.layers[0].blur_px, 2, 1e-4);
  EXPECT_NEAR(grown.layers[0].blur_px, 4, 1e-4);
  EXPECT_NEAR(grown.layers[0].offset_px.x(), 0, 1e-6);
  EXPECT_NEAR(grown.layers[0].offset_px.y(), 8, 1e-6);
}

// A pattern fill: tiles inside the shape, none outside it; the tiles move with the shape.
TEST(Composite, APatternFillsItsShapeWithTiles) {
  const Character ch = svg(R"svg(<defs><pattern id="p" width="10" height="10" patternUnits="userSpaceOnUse">
      <rect width="5" height="5" fill="#f00"/></pattern></defs>
      <circle cx="30" cy="30" r="20" fill="url(#p)"/>)svg");
  const Image img = draw(ch);
  EXPECT_EQ(px(img, 22, 22)[1], 0);    // a red square (20..25)
  EXPECT_EQ(px(img, 27, 27)[1], 255);  // between squares
  EXPECT_EQ(px(img, 2, 2)[1], 255);    // the square at 0..5 is outside the circle
  const Image m = draw(ch, moved_by(ch, Vec2(3, 0)));
  EXPECT_EQ(px(m, 24, 22)[1], 0);
  EXPECT_EQ(px(m, 22, 22)[1], 255);
}

// Inkscape's drop shadow: the shape as drawn, over a blurred copy of its silhouette in the
// flood's colour, shifted.
TEST(Composite, ADropShadowLiesUnderTheShapeShifted) {
  const Image img = draw(svg(R"svg(<defs><filter id="s"><feFlood flood-color="#0000ff" flood-opacity="1" result="f"/>
      <feComposite in="f" in2="SourceGraphic" operator="in" result="c"/><feGaussianBlur in="c" stdDeviation="1"/>
      <feOffset dx="10" dy="10" result="o"/><feComposite in="SourceGraphic" in2="o" operator="over"/></filter></defs>
      <rect x="20" y="10" width="30" height="30" fill="#f00" filter="url(#s)"/>)svg"));
  const uint8_t* shape = px(img, 35, 25);
  EXPECT_EQ(shape[0], 255);  // the shape itself, on top
  EXPECT_EQ(shape[2], 0);
  const uint8_t* shade = px(img, 55, 45);  // beside and below it: the shadow
  EXPECT_LT(shade[0], 40);
  EXPECT_GT(shade[2], 200);
  EXPECT_EQ(px(img, 10, 45)[0], 255);  // (not on the other side)
}

}  // namespace
}  // namespace mar
