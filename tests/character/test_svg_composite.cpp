// Groups drawn as layers (Character::composites): opacity, filter, clip-path and mask as the
// loader reads them.
#include "character/svg_loader.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mar {
namespace {

Character load(const std::string& body) {
  auto r = load_svg_string("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" height=\"100\">" + body + "</svg>", "c.svg");
  EXPECT_TRUE(r.ok()) << r.error;
  return r.ok() ? *r.value : Character{};
}

bool said(const Character& ch, const std::string& part) {
  for (const std::string& w : ch.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

TEST(composites, GroupOpacityIsALayerAndALoneShapeKeepsItInItsPaint) {
  const Character ch = load(R"svg(<g id="pair" opacity="0.5"><rect width="10" height="10" fill="red" opacity="0.8"/>
      <rect x="5" width="10" height="10" fill="blue"/></g>
      <rect id="lone" y="20" width="10" height="10" fill="green" opacity="0.5"/>
      <rect id="both" y="40" width="10" height="10" fill="green" stroke="black" opacity="0.5"/>)svg");
  ASSERT_EQ(ch.composites.size(), 2u);
  const Composite& g = ch.composites[0];
  EXPECT_EQ(g.id, "pair");
  EXPECT_FLOAT_EQ(g.opacity, 0.5f);
  EXPECT_EQ(g.first, 0);
  EXPECT_EQ(g.end, 2);
  // Inside the layer, the children keep only their own opacity.
  EXPECT_FLOAT_EQ(ch.shapes[0].fill.opacity, 0.8f);
  EXPECT_FLOAT_EQ(ch.shapes[1].fill.opacity, 1.0f);
  // One paint: no layer, the opacity in the paint; fill and stroke: a layer.
  EXPECT_FLOAT_EQ(ch.shapes[2].fill.opacity, 0.5f);
  EXPECT_EQ(ch.composites[1].id, "both");
  EXPECT_FLOAT_EQ(ch.shapes[3].fill.opacity, 1.0f);
}

TEST(composites, ClipPathsAndMasksAreShapesOfTheirOwnThatDeformAlong) {
  const Character ch = load(R"svg(<defs>
        <clipPath id="c" clipPathUnits="objectBoundingBox"><rect width="0.5" height="1" clip-rule="evenodd"/></clipPath>
        <mask id="m" style="mask-type: alpha"><circle cx="70" cy="70" r="10" fill="white"/></mask></defs>
      <g transform="translate(10 0)"><rect id="clipped" width="40" height="20" fill="red" clip-path="url(#c)"/></g>
      <rect id="masked" x="60" y="60" width="20" height="20" fill="blue" mask="url(#m)"/>)svg");
  ASSERT_EQ(ch.composites.size(), 2u);
  const Composite& c = ch.composites[0];
  ASSERT_EQ(c.clip.size(), 1u);
  const SubShape& clip = ch.shapes[size_t(c.clip[0])];
  EXPECT_EQ(clip.role, ShapeRole::Clip);
  EXPECT_EQ(clip.owner, 0);
  EXPECT_EQ(clip.fill.rule, FillRule::EvenOdd);
  // The box of the clipped rect (its left half), in character units: the group's translate too.
  EXPECT_NEAR(clip.bounds().lo.x(), 10, 1e-9);
  EXPECT_NEAR(clip.bounds().hi.x(), 30, 1e-9);
  EXPECT_NEAR(clip.bounds().hi.y(), 20, 1e-9);
  const Composite& m = ch.composites[1];
  ASSERT_EQ(m.mask.size(), 1u);
  EXPECT_TRUE(m.mask_alpha);
  EXPECT_EQ(ch.shapes[size_t(m.mask[0])].role, ShapeRole::Mask);
  EXPECT_EQ(m.first + 1, m.end);  // (the masked rect)
}

TEST(composites, BlurOffsetAndDropShadowsAreDrawnAndOtherFiltersAreSaid) {
  const Character ch = load(R"svg(<defs><filter id="f"><feGaussianBlur stdDeviation="2"/><feOffset dx="3" dy="1"/></filter>
        <filter id="two"><feGaussianBlur stdDeviation="1 4"/></filter>
        <filter id="ink"><feFlood flood-opacity="0.5" flood-color="rgb(0,0,255)" result="flood"/>
          <feComposite in="flood" in2="SourceGraphic" operator="in" result="c1"/><feGaussianBlur in="c1" stdDeviation="3"/>
          <feOffset dx="6" dy="6" result="offset"/><feComposite in="SourceGraphic" in2="offset" operator="over"/></filter>
        <filter id="old"><feGaussianBlur in="SourceAlpha" stdDeviation="2"/><feOffset dx="1" dy="1" result="o"/>
          <feMerge><feMergeNode in="o"/><feMergeNode in="SourceGraphic"/></feMerge></filter>
        <filter id="grey"><feGaussianBlur stdDeviation="2"/><feColorMatrix type="saturate" values="0"/></filter></defs>
      <g transform="scale(2)"><rect width="10" height="10" filter="url(#f)"/></g>
      <rect y="50" width="10" height="10" filter="url(#two)"/>
      <rect x="20" width="10" height="10" filter="url(#ink)"/>
      <rect x="40" width="10" height="10" filter="url(#old)"/>
      <rect x="60" width="10" height="10" filter="url(#grey)"/>
      <rect y="70" width="10" height="10" filter="url(#none)" clip-path="url(#none)"/>)svg");
  ASSERT_EQ(ch.composites.size(), 4u);
  EXPECT_NEAR(ch.composites[0].blur, 4, 1e-9);
  EXPECT_NEAR(ch.composites[0].offset.x(), 6, 1e-9);
  EXPECT_NEAR(ch.composites[0].offset.y(), 2, 1e-9);
  EXPECT_FALSE(ch.composites[0].shadow);
  EXPECT_NEAR(ch.composites[1].blur, 2, 1e-9);  // (sqrt(1 x 4): one radius for both)
  // Inkscape's drop shadow: its flood's colour and opacity, blurred and shifted, under the shape.
  const Composite& ink = ch.composites[2];
  EXPECT_TRUE(ink.shadow);
  EXPECT_NEAR(ink.blur, 3, 1e-9);
  EXPECT_NEAR(ink.offset.x(), 6, 1e-9);
  EXPECT_FLOAT_EQ(ink.shadow_color.b, 1.0f);
  EXPECT_FLOAT_EQ(ink.shadow_color.a, 0.5f);
  EXPECT_TRUE(ch.composites[3].shadow);  // (the older one, black)
  EXPECT_FLOAT_EQ(ch.composites[3].shadow_color.a, 1.0f);
  EXPECT_TRUE(said(ch, "filter 'url(#grey)' is more than a blur"));
  EXPECT_TRUE(said(ch, "filter 'url(#none)' names no filter"));
  EXPECT_TRUE(said(ch, "clip-path 'url(#none)' names no clipPath"));
  EXPECT_EQ(ch.shapes.size(), 6u);  // (drawn without them)
}

TEST(composites, AnEmptyClipShowsNothingAndAClipInsideItselfIsCut) {
  const Character ch = load(R"svg(<defs><clipPath id="e"/><clipPath id="self"><rect width="5" height="5" clip-path="url(#self)"/></clipPath></defs>
      <rect width="10" height="10" clip-path="url(#e)"/><rect y="20" width="10" height="10" clip-path="url(#self)"/>)svg");
  ASSERT_EQ(ch.composites.size(), 2u);
  EXPECT_EQ(ch.composites[0].opacity, 0.0f);
  EXPECT_EQ(ch.composites[1].clip.size(), 1u);
  EXPECT_TRUE(said(ch, "clip-path inside a clip path or mask is not drawn"));
}

// Each nesting of layers is a canvas-sized buffer when drawn: at most 8 nest, deeper ones are
// drawn without their layer (190 nested opacity groups took 1.6 GB at 1920x1080 before).
TEST(composites, LayersNestAtMostEightDeep) {
  std::string body;
  for (int k = 0; k < 50; ++k) body += "<g opacity=\"0.99\">";
  body += "<rect width=\"10\" height=\"10\" fill=\"red\"/>";
  for (int k = 0; k < 50; ++k) body += "</g>";
  const Character ch = load(body);
  EXPECT_EQ(ch.composites.size(), 8u);
  EXPECT_TRUE(said(ch, "layers nested deeper than 8"));
  ASSERT_EQ(ch.shapes.size(), 1u);
  EXPECT_NEAR(ch.shapes[0].fill.opacity, std::pow(0.99, 42), 1e-4);  // (the rest folded into the paint)
}

// A nested svg clips what crosses its viewport (a layer clipped by its rectangle); content
// inside it, or overflow: visible, needs no layer.
TEST(composites, ANestedViewportClipsWhatCrossesIt) {
  const Character ch = load(R"svg(<svg x="10" y="10" width="20" height="20"><circle cx="20" cy="10" r="8"/></svg>
      <svg x="50" y="10" width="20" height="20"><circle cx="10" cy="10" r="5"/></svg>
      <svg x="10" y="50" width="20" height="20" overflow="visible"><circle cx="20" cy="10" r="8"/></svg>)svg");
  ASSERT_EQ(ch.composites.size(), 1u);
  const Composite& c = ch.composites[0];
  ASSERT_EQ(c.clip.size(), 1u);
  const Bounds b = ch.shapes[size_t(c.clip[0])].bounds();
  EXPECT_NEAR(b.lo.x(), 10, 1e-9);
  EXPECT_NEAR(b.hi.x(), 30, 1e-9);
  EXPECT_EQ(c.end - c.first, 1);
}

// A pattern fill: its tiles over the shape's box, in a layer the shape clips; the shape keeps
// its stroke. Too many tiles, or a tile with no size, paint a colour instead, said.
TEST(composites, APatternIsTilesClippedByTheShape) {
  const Character ch = load(R"svg(<defs><pattern id="p" width="10" height="10" patternUnits="userSpaceOnUse">
        <rect width="5" height="5" fill="red"/></pattern>
      <pattern id="tiny" width="0.1" height="0.1" patternUnits="userSpaceOnUse"><rect width="0.05" height="0.05"/></pattern>
      <pattern id="bbox" width="0.5" height="1"><rect width="2" height="4" fill="blue"/></pattern></defs>
      <rect id="r" x="0" y="0" width="30" height="20" fill="url(#p)" stroke="black"/>
      <rect id="t" y="30" width="30" height="20" fill="url(#tiny)"/>
      <rect id="b" x="40" y="0" width="8" height="4" fill="url(#bbox)"/>)svg");
  ASSERT_GE(ch.composites.size(), 2u);
  const Composite& p = ch.composites[0];
  EXPECT_EQ(p.end - p.first, 6);  // 3 x 2 tiles, one square each
  ASSERT_EQ(p.clip.size(), 1u);
  const SubShape& clip = ch.shapes[size_t(p.clip[0])];
  EXPECT_EQ(clip.role, ShapeRole::Clip);
  EXPECT_NEAR(clip.bounds().hi.x(), 30, 1e-9);
  EXPECT_NEAR(ch.shapes[size_t(p.first + 1)].bounds().lo.y(), 10, 1e-9);  // (the tile below the first)
  const SubShape* r = nullptr;
  for (const SubShape& s : ch.shapes)
    if (s.id == "r") r = &s;
  ASSERT_NE(r, nullptr);
  EXPECT_FALSE(r->fill.enabled);
  EXPECT_TRUE(r->stroke.enabled);
  EXPECT_TRUE(said(ch, "pattern 'tiny' would take more than 256 tiles"));
  // objectBoundingBox tiles: half the 8 x 4 box each, two of them.
  const Composite& b = ch.composites.back();
  EXPECT_EQ(b.end - b.first, 2);
  EXPECT_NEAR(ch.shapes[size_t(b.first + 1)].bounds().lo.x(), 44, 1e-9);
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

// transform-origin: the transform turns about that point (lengths, percentages of the viewport,
// keywords in either order), on shapes, gradients and clip paths alike.
TEST(TransformOrigin, TheTransformTurnsAboutIt) {
  auto r = load_svg_string(R"svg(<svg xmlns="http://www.w3.org/2000/svg" width="200" height="100">
      <rect id="px" x="90" y="40" width="20" height="20" transform="scale(2)" transform-origin="100px 50px"/>
      <rect id="kw" x="90" y="40" width="20" height="20" transform="scale(2)" transform-origin="top left"/>
      <rect id="pc" x="90" y="40" width="20" height="20" transform="scale(2)" style="transform-origin: 50% 50%"/>
      <rect id="one" x="90" y="40" width="20" height="20" transform="scale(2)" transform-origin="bottom"/></svg>)svg", "o.svg");
  ASSERT_TRUE(r.ok()) << r.error;
  auto box = [&](const char* id) {
    for (const SubShape& s : r.value->shapes)
      if (s.id == id) return s.bounds();
    return Bounds{};
  };
  EXPECT_NEAR(box("px").lo.x(), 80, 1e-9);  // (about the square's centre: it grows both ways)
  EXPECT_NEAR(box("px").lo.y(), 30, 1e-9);
  EXPECT_NEAR(box("kw").lo.x(), 180, 1e-9);  // (about 0, 0)
  EXPECT_NEAR(box("pc").lo.x(), 80, 1e-9);   // (50% of 200 x 100)
  EXPECT_NEAR(box("one").lo.x(), 80, 1e-9);  // (bottom: x centre, y 100)
  EXPECT_NEAR(box("one").lo.y(), -20, 1e-9);
}

}  // namespace
}  // namespace mar
