#include "character/color.h"
#include "character/load.h"
#include "character/svg_loader.h"
#include "character/svg_parse.h"
#include "geom/polygon.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>

namespace mar {
namespace {

Character load(const std::string& body, const std::string& root_attrs = R"svg(width="100" height="100")svg",
               double tol = 0.1) {
  const std::string text = "<svg xmlns=\"http://www.w3.org/2000/svg\" "
                           "xmlns:xlink=\"http://www.w3.org/1999/xlink\" "
                           "xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\" " +
                           root_attrs + ">\n" + body + "\n</svg>\n";
  SvgOptions o;
  o.tolerance = tol;
  auto r = load_svg_string(text, "test.svg", o);
  EXPECT_TRUE(r.ok()) << r.error;
  return r.ok() ? *r.value : Character{};
}

const SubShape* find(const Character& ch, const std::string& id) {
  for (const SubShape& s : ch.shapes)
    if (s.id == id) return &s;
  return nullptr;
}

bool has_warning(const Character& ch, const std::string& needle) {
  for (const auto& w : ch.warnings)
    if (w.find(needle) != std::string::npos) return true;
  return false;
}

void expect_bounds(const SubShape& s, double x0, double y0, double x1, double y1, double eps = 1e-9) {
  const Bounds b = s.bounds();
  EXPECT_NEAR(b.lo.x(), x0, eps);
  EXPECT_NEAR(b.lo.y(), y0, eps);
  EXPECT_NEAR(b.hi.x(), x1, eps);
  EXPECT_NEAR(b.hi.y(), y1, eps);
}

TEST(load_svg, RectPlainAndRounded) {
  auto ch = load(R"svg(<rect id="a" x="10" y="20" width="30" height="40"/>
                    <rect id="b" x="10" y="20" width="30" height="40" rx="5"/>
                    <rect id="c" x="0" y="0" width="30" height="40" ry="100"/>
                    <rect id="zero" width="0" height="10"/>)svg");
  ASSERT_EQ(ch.shapes.size(), 3u);
  EXPECT_EQ(find(ch, "a")->points.size(), 4u);
  EXPECT_TRUE(find(ch, "a")->closed());
  expect_bounds(*find(ch, "a"), 10, 20, 40, 60);
  EXPECT_GT(find(ch, "b")->points.size(), 8u);
  expect_bounds(*find(ch, "b"), 10, 20, 40, 60, 1e-6);
  // ry alone sets rx too; both clamp to half the size -> a capsule as wide as the rect.
  const SubShape& c = *find(ch, "c");
  expect_bounds(c, 0, 0, 30, 40, 1e-6);
  // Area of the capsule; the inscribed flattening loses at most tolerance x curved length.
  const double exact = 30 * 40 - (4 - M_PI) * 15 * 20;
  EXPECT_LE(std::abs(signed_area(c.points)), exact + 1e-9);
  EXPECT_GE(std::abs(signed_area(c.points)), exact - 0.1 * 2 * M_PI * 17.7);
}

TEST(load_svg, CircleEllipseFlattenedToTolerance) {
  for (double tol : {1.0, 0.1, 0.01}) {
    auto ch = load(R"svg(<circle id="c" cx="50" cy="50" r="40"/>)svg", R"svg(width="100" height="100")svg", tol);
    const SubShape& c = ch.shapes.at(0);
    const size_t n = c.points.size();
    for (size_t i = 0; i < n; ++i) {
      const Vec2 mid = 0.5 * (c.points[i] + c.points[(i + 1) % n]);
      EXPECT_NEAR((c.points[i] - Vec2(50, 50)).norm(), 40, 1e-3);
      EXPECT_LE(40 - (mid - Vec2(50, 50)).norm(), tol * 1.01);
    }
  }
  auto e = load(R"svg(<ellipse id="e" cx="50" cy="50" rx="40" ry="20"/>)svg");
  expect_bounds(e.shapes.at(0), 10, 30, 90, 70, 1e-9);
}

TEST(load_svg, ToleranceIsInOutputUnits) {
  // The same circle drawn through a 10x scale must get proportionally more points.
  auto small = load(R"svg(<circle cx="5" cy="5" r="4"/>)svg", R"svg(width="100" height="100" viewBox="0 0 100 100")svg");
  auto big = load(R"svg(<circle cx="5" cy="5" r="4"/>)svg", R"svg(width="1000" height="1000" viewBox="0 0 100 100")svg");
  EXPECT_GT(big.shapes.at(0).points.size(), 2 * small.shapes.at(0).points.size());
}

TEST(load_svg, LinePolylinePolygon) {
  auto ch = load(R"svg(<line id="l" x1="0" y1="0" x2="10" y2="10" stroke="black"/>
                    <polyline id="pl" points="0,0 10,0 10,10" fill="none" stroke="red"/>
                    <polygon id="pg" points="0,0 10,0 10,10"/>)svg");
  ASSERT_EQ(ch.shapes.size(), 3u);
  EXPECT_FALSE(find(ch, "l")->closed());
  EXPECT_FALSE(find(ch, "l")->fill.enabled);  // lines never fill
  EXPECT_TRUE(find(ch, "l")->stroke.enabled);
  EXPECT_FALSE(find(ch, "pl")->closed());
  EXPECT_TRUE(find(ch, "pg")->closed());
  EXPECT_EQ(find(ch, "pg")->points.size(), 3u);
}

// A filled path with no closing z is filled as if closed (SVG's rule): an outline like any
// other to the rig and the solvers; only its stroke keeps its two ends. A filled sub-path with
// no area stays a line; one drawn back to its start loses the repeated point and strokes round.
TEST(load_svg, AFilledOpenPathIsAnOutlineWhoseStrokeKeepsItsEnds) {
  auto ch = load(R"svg(<path id="v" d="M10 10 L90 10 L50 80" fill="red" stroke="black"/>
                    <path id="flat" d="M0 0 L10 10 L20 20" fill="red" stroke="black"/>
                    <path id="back" d="M10 10 L90 10 L50 80 L10 10" fill="red" stroke="black"/>
                    <path id="bare" d="M10 10 L90 10 L50 80" fill="none" stroke="black"/>)svg");
  ASSERT_EQ(ch.shapes.size(), 4u);
  const SubShape& v = *find(ch, "v");
  EXPECT_TRUE(v.closed());
  ASSERT_EQ(v.contours.size(), 1u);
  EXPECT_TRUE(v.contours[0].open_stroke);
  EXPECT_FALSE(v.contours[0].stroke_closed());
  EXPECT_EQ(v.largest_ring().size(), 3u);
  EXPECT_FALSE(find(ch, "flat")->closed());
  const SubShape& back = *find(ch, "back");
  EXPECT_TRUE(back.closed());
  EXPECT_EQ(back.points.size(), 3u);
  EXPECT_TRUE(back.contours[0].stroke_closed());
  EXPECT_FALSE(find(ch, "bare")->closed()) << "not filled: a line";
}

TEST(load_svg, LineWithoutStrokeDrawsNothing) {
  auto ch = load(R"svg(<line x1="0" y1="0" x2="10" y2="10"/>)svg");
  EXPECT_TRUE(ch.shapes.empty());
}

TEST(load_svg, PathWithSeveralSubpathsIsOneShape) {
  auto ch = load(R"svg(<path id="p" fill-rule="evenodd" d="M0 0 H50 V50 H0 Z M10 10 H40 V40 H10 Z"/>)svg");
  ASSERT_EQ(ch.shapes.size(), 1u);
  EXPECT_EQ(ch.shapes[0].contours.size(), 2u);
  EXPECT_EQ(ch.shapes[0].fill.rule, FillRule::EvenOdd);
}

TEST(load_svg, BadPathDataDrawsUpToTheErrorAndWarns) {
  auto ch = load(R"svg(<path id="p" d="M0 0 L10 0 L10 10 L5"/>)svg");
  ASSERT_EQ(ch.shapes.size(), 1u);
  EXPECT_EQ(ch.shapes[0].points.size(), 3u);
  EXPECT_TRUE(has_warning(ch, "path data error"));
  EXPECT_TRUE(has_warning(ch, "test.svg:2"));
}

TEST(load_svg, TransformsNest) {
  auto ch = load(R"svg(<g transform="translate(10 20)"><g transform="scale(2)">
                    <rect id="r" x="1" y="1" width="2" height="2" transform="rotate(90 2 2)"/></g></g>)svg");
  expect_bounds(ch.shapes.at(0), 12, 22, 16, 26, 1e-9);
}

TEST(load_svg, UseOfDefsWithOffsetAndBothHrefForms) {
  auto ch = load(R"svg(<defs><rect id="src" width="10" height="10"/></defs>
                    <use id="u1" href="#src" x="20" y="5"/>
                    <use id="u2" xlink:href="#src" transform="translate(50 0)"/>)svg");
  ASSERT_EQ(ch.shapes.size(), 2u);  // defs themselves are not drawn
  expect_bounds(*find(ch, "u1:src"), 20, 5, 30, 15);
  expect_bounds(*find(ch, "u2:src"), 50, 0, 60, 10);
}

TEST(load_svg, UseInheritsStyleFromUse) {
  auto ch = load(R"svg(<defs><rect id="src" width="10" height="10"/></defs>
                    <use href="#src" fill="#00ff00"/>)svg");
  ASSERT_EQ(ch.shapes.size(), 1u);
  EXPECT_EQ(color_hex(ch.shapes[0].fill.color), "#00ff00");
}

TEST(load_svg, UseOfSymbolWithViewBox) {
  auto ch = load(R"svg(<symbol id="sym" viewBox="0 0 10 10"><rect width="10" height="10"/></symbol>
                    <use href="#sym" x="5" y="5" width="40" height="40"/>)svg");
  ASSERT_EQ(ch.shapes.size(), 1u);
  expect_bounds(ch.shapes[0], 5, 5, 45, 45, 1e-9);
}

TEST(load_svg, RecursiveUseIsCutWithAWarning) {
  auto ch = load(R"svg(<g id="a"><rect width="5" height="5"/><use href="#a" x="10"/></g>
                    <use id="b" href="#c"/><use id="c" href="#b"/>)svg");
  EXPECT_EQ(ch.shapes.size(), 1u);
  EXPECT_TRUE(has_warning(ch, "use"));
}

TEST(load_svg, ViewBoxAndPreserveAspectRatio) {
  auto meet = load(R"svg(<rect width="100" height="100"/>)svg",
                   R"svg(width="200" height="100" viewBox="0 0 100 100")svg");  // xMidYMid meet
  expect_bounds(meet.shapes.at(0), 50, 0, 150, 100);
  auto none = load(R"svg(<rect width="100" height="100"/>)svg",
                   R"svg(width="200" height="100" viewBox="0 0 100 100" preserveAspectRatio="none")svg");
  expect_bounds(none.shapes.at(0), 0, 0, 200, 100);
  auto min = load(R"svg(<rect width="100" height="100"/>)svg",
                  R"svg(width="200" height="100" viewBox="0 0 100 100" preserveAspectRatio="xMinYMin")svg");
  expect_bounds(min.shapes.at(0), 0, 0, 100, 100);
  auto slice = load(R"svg(<rect width="100" height="100"/>)svg",
                    R"svg(width="200" height="100" viewBox="0 0 100 100" preserveAspectRatio="xMidYMax slice")svg");
  expect_bounds(slice.shapes.at(0), 0, -100, 200, 100);
  auto offset = load(R"svg(<rect x="10" y="10" width="10" height="10"/>)svg",
                     R"svg(width="100" height="100" viewBox="10 10 10 10")svg");
  expect_bounds(offset.shapes.at(0), 0, 0, 100, 100);
  EXPECT_EQ(meet.width, 200);
  EXPECT_EQ(meet.height, 100);
}

TEST(load_svg, SizeFromViewBoxAndUnits) {
  auto vb = load(R"svg(<rect width="1" height="1"/>)svg", R"svg(viewBox="0 0 300 150")svg");
  EXPECT_EQ(vb.width, 300);
  EXPECT_EQ(vb.height, 150);
  auto mm = load(R"svg(<rect width="1in" height="2.54cm"/>)svg", R"svg(width="1in" height="25.4mm")svg");
  EXPECT_NEAR(mm.width, 96, 1e-9);
  EXPECT_NEAR(mm.height, 96, 1e-9);
  expect_bounds(mm.shapes.at(0), 0, 0, 96, 96, 1e-9);
  auto pct = load(R"svg(<rect width="50%" height="25%"/>)svg", R"svg(width="200" height="100")svg");
  expect_bounds(pct.shapes.at(0), 0, 0, 100, 25, 1e-9);
}

TEST(load_svg, StyleAttributeBeatsPresentationAttribute) {
  auto ch = load(R"svg(<rect width="1" height="1" fill="red" style="fill: blue ; stroke:#0f0;stroke-width:3"/>)svg");
  const SubShape& s = ch.shapes.at(0);
  EXPECT_EQ(color_hex(s.fill.color), "#0000ff");
  EXPECT_TRUE(s.stroke.enabled);
  EXPECT_EQ(color_hex(s.stroke.color), "#00ff00");
  EXPECT_DOUBLE_EQ(s.stroke.width, 3);
}

TEST(load_svg, InheritanceAndOpacity) {
  auto ch = load(R"svg(<g fill="green" stroke="black" stroke-linejoin="round" opacity="0.5">
                      <rect id="a" width="1" height="1" fill-opacity="0.5"/>
                      <rect id="b" width="1" height="1" fill="inherit" stroke="none" style="opacity:.5"/>
                    </g>)svg");
  // The group's opacity is its layer's (Character::composites); a shape with one paint keeps its
  // own opacity in that paint.
  ASSERT_EQ(ch.composites.size(), 1u);
  EXPECT_FLOAT_EQ(ch.composites[0].opacity, 0.5f);
  const SubShape& a = *find(ch, "a");
  EXPECT_EQ(color_hex(a.fill.color), "#008000");
  EXPECT_NEAR(a.fill.opacity, 0.5, 1e-6);
  EXPECT_NEAR(a.stroke.opacity, 1, 1e-6);
  EXPECT_EQ(a.stroke.join, LineJoin::Round);
  const SubShape& b = *find(ch, "b");
  EXPECT_FALSE(b.stroke.enabled);
  EXPECT_NEAR(b.fill.opacity, 0.5, 1e-6);
}

TEST(load_svg, CurrentColor) {
  auto ch = load(R"svg(<g color="#123456"><rect width="1" height="1" fill="currentColor"/></g>)svg");
  EXPECT_EQ(color_hex(ch.shapes.at(0).fill.color), "#123456");
}

TEST(load_svg, CurrentColorIsInheritedAsTheKeyword) {
  // A group's fill="currentColor" paints each child in the child's own color (CSS Color 4).
  auto ch = load(R"svg(<g fill="currentColor" stroke="currentColor"><g color="#00ff00"><rect id="a" width="1" height="1"/></g>
      <rect id="b" x="2" width="1" height="1" color="#0000ff"/><rect id="c" x="4" width="1" height="1" fill="red"/></g>)svg");
  EXPECT_EQ(color_hex(find(ch, "a")->fill.color), "#00ff00");
  EXPECT_EQ(color_hex(find(ch, "a")->stroke.color), "#00ff00");
  EXPECT_EQ(color_hex(find(ch, "b")->fill.color), "#0000ff");
  EXPECT_EQ(color_hex(find(ch, "c")->fill.color), "#ff0000");
}

TEST(load_svg, StyleCommentsCssTransformsAndFontRelativeLengths) {
  auto ch = load(R"svg(<rect id="commented" width="10" height="10" style="/* a note */fill:#00ff00/* another */"/>
      <rect id="scaled" x="10" y="10" width="10" height="10" style="transform: translate(5px, 0) scale(2)"/>
      <rect id="none" x="10" width="1" height="1" transform="scale(3)" style="transform:none"/>
      <g font-size="20"><rect id="em" x="1em" width="2em" height="1ex"/><g font-size="50%"><rect id="half" width="1em" height="1em"/></g></g>)svg");
  EXPECT_EQ(color_hex(find(ch, "commented")->fill.color), "#00ff00");
  const Bounds s = find(ch, "scaled")->bounds();
  EXPECT_NEAR(s.lo.x(), 25, 1e-9) << "the style's transform, its units read";
  EXPECT_NEAR(s.hi.y(), 40, 1e-9);
  EXPECT_NEAR(find(ch, "none")->bounds().hi.x(), 11, 1e-9) << "transform: none over the attribute";
  const Bounds e = find(ch, "em")->bounds();
  EXPECT_NEAR(e.lo.x(), 20, 1e-9);
  EXPECT_NEAR(e.hi.x(), 60, 1e-9);
  EXPECT_NEAR(e.hi.y(), 10, 1e-9) << "an ex is half an em";
  EXPECT_NEAR(find(ch, "half")->bounds().hi.x(), 10, 1e-9) << "a percentage of the parent's font-size";
}

TEST(load_svg, DisplayAndVisibility) {
  auto ch = load(R"svg(<g style="display:none"><rect id="gone" width="1" height="1"/></g>
                    <g visibility="hidden"><rect id="hidden" width="1" height="1"/>
                      <rect id="shown" width="1" height="1" visibility="visible"/></g>
                    <rect id="none" display="none" width="1" height="1"/>)svg");
  ASSERT_EQ(ch.shapes.size(), 1u);
  EXPECT_EQ(ch.shapes[0].id, "shown");
}

TEST(load_svg, StrokeWidthFollowsTransformScale) {
  auto ch = load(R"svg(<g transform="scale(2)"><path d="M0 0 L10 0" stroke="black" stroke-width="3"/></g>)svg");
  EXPECT_DOUBLE_EQ(ch.shapes.at(0).stroke.width, 6);
}

TEST(load_svg, PatternsTextAndFiltersWarnAndGradientStrokesAreTextures) {
  auto ch = load(R"svg(<defs><linearGradient id="g"><stop offset="0" stop-color="#ff0000"/>
                      <stop offset="1" stop-color="#0000ff"/></linearGradient>
                      <linearGradient id="g2" xlink:href="#g"/>
                      <pattern id="pat"><rect width="2" height="2" fill="#00ff00"/></pattern></defs>
                    <rect id="a" width="1" height="1" fill="none" stroke="url(#g)"/>
                    <rect id="b" width="1" height="1" fill="none" stroke="url(#g2)"/>
                    <rect id="c" width="1" height="1" fill="url(#pat)"/>
                    <rect id="d" width="1" height="1" fill="url(#missing) #00ffff"/>
                    <text x="0" y="0"><textPath href="#a">hi</textPath></text>
                    <rect id="e" width="1" height="1" filter="url(#f)"/>)svg");
  // A gradient stroke samples a texture over the shape's bounds widened by half its width.
  for (const char* id : {"a", "b"}) {
    const SubShape& s = *find(ch, id);
    ASSERT_TRUE(s.stroke.enabled && s.stroke.texture) << id;
    EXPECT_NEAR(s.stroke.uv_from_point.apply(Vec2(-0.5, -0.5)).x(), 0, 1e-9);
    EXPECT_NEAR(s.stroke.uv_from_point.apply(Vec2(1.5, 1.5)).y(), 1, 1e-9);
    const Texture& t = *s.stroke.texture;  // red on the left, blue on the right (stops via href for b)
    EXPECT_GT(t.rgba[0], 200);
    EXPECT_GT(t.rgba[size_t(t.width - 1) * 4 + 2], 200);
  }
  EXPECT_EQ(color_hex(find(ch, "c")->fill.color), "#00ff00");
  EXPECT_EQ(color_hex(find(ch, "d")->fill.color), "#00ffff");  // fallback colour
  EXPECT_TRUE(find(ch, "e"));
  EXPECT_FALSE(has_warning(ch, "linearGradient 'g' drawn as its mean colour"));
  EXPECT_TRUE(has_warning(ch, "pattern 'pat'"));
  EXPECT_TRUE(has_warning(ch, "textPath is not supported; its text skipped"));
  EXPECT_TRUE(has_warning(ch, "filter 'url(#f)' names no filter"));
}

TEST(load_svg, DashesPaintOrderAndNonScalingStrokes) {
  auto ch = load(R"svg(<g transform="scale(2)" stroke="black" fill="red">
                      <path id="odd" d="M0 0 H40" stroke-dasharray="4, 2 1" stroke-dashoffset="3"/>
                      <path id="pct" d="M0 0 H40" stroke-dasharray="10%"/>
                      <path id="zero" d="M0 0 H40" stroke-dasharray="0 0"/>
                      <path id="neg" d="M0 0 H40" stroke-dasharray="4 -1"/>
                      <path id="many" d="M0 0 H40" stroke-dasharray="0.0001"/>
                      <rect id="under" width="5" height="5" paint-order="stroke fill"/>
                      <rect id="markers" width="5" height="5" paint-order="markers stroke"/>
                      <rect id="normal" width="5" height="5" paint-order="fill"/>
                      <rect id="thin" width="5" height="5" stroke-width="3" vector-effect="non-scaling-stroke"/>
                    </g>)svg");
  // An odd list repeats; lengths and offset scale with the transform (x2).
  EXPECT_EQ(find(ch, "odd")->stroke.dashes, (std::vector<double>{8, 4, 2, 8, 4, 2}));
  EXPECT_DOUBLE_EQ(find(ch, "odd")->stroke.dash_offset, 6);
  // A percentage is of the viewport's normalised diagonal (100 x 100: 10 % is 10), doubled.
  ASSERT_EQ(find(ch, "pct")->stroke.dashes.size(), 2u);
  EXPECT_NEAR(find(ch, "pct")->stroke.dashes[0], 20, 1e-9);
  EXPECT_TRUE(find(ch, "zero")->stroke.dashes.empty());  // all zero: solid
  EXPECT_TRUE(find(ch, "neg")->stroke.dashes.empty());   // negative: solid, said
  EXPECT_TRUE(has_warning(ch, "stroke-dasharray=\"4 -1\""));
  EXPECT_TRUE(find(ch, "many")->stroke.dashes.empty());  // 800,000 dashes: solid, said
  EXPECT_TRUE(has_warning(ch, "more than 20000 dashes"));
  EXPECT_TRUE(find(ch, "under")->stroke.under_fill);
  EXPECT_TRUE(find(ch, "markers")->stroke.under_fill);  // (fill, left out, comes last)
  EXPECT_FALSE(find(ch, "normal")->stroke.under_fill);
  EXPECT_DOUBLE_EQ(find(ch, "thin")->stroke.width, 3);  // not 6
  EXPECT_DOUBLE_EQ(find(ch, "normal")->stroke.width, 2);
}

TEST(load_svg, MarkersAtVerticesTurnedScaledAndPlaced) {
  auto ch = load(R"svg(<defs>
      <marker id="arrow" orient="auto" markerUnits="userSpaceOnUse" refX="1" refY="0" overflow="visible">
        <path id="tip" d="M1 0 L5 0" stroke="black" stroke-width="1"/></marker>
      <marker id="dot" markerWidth="2" markerHeight="2" viewBox="0 0 10 10" refX="5" refY="5" orient="90">
        <rect id="sq" width="10" height="4" fill="red"/></marker></defs>
    <path id="p" d="M10 10 L50 10 L50 50" fill="none" stroke="blue" stroke-width="2"
          marker-start="url(#arrow)" marker-mid="url(#arrow)" marker-end="url(#dot)"/>
    <path id="q" d="M0 90 L10 90" style="marker: url(#missing)"/>)svg");
  // The path, then its markers in vertex order, named after it.
  ASSERT_NE(find(ch, "p:tip"), nullptr);
  ASSERT_NE(find(ch, "p:tip.2"), nullptr);
  ASSERT_NE(find(ch, "p:sq"), nullptr);
  auto near = [](const Vec2& a, const Vec2& b) { return (a - b).norm() < 1e-6; };
  // Start: along the first segment, the ref point (1, 0) on the vertex.
  const SubShape& start = *find(ch, "p:tip");
  EXPECT_TRUE(near(start.points.front(), {10, 10}));
  EXPECT_TRUE(near(start.points.back(), {14, 10}));
  // The corner: the bisector of east and south, 45 degrees.
  const SubShape& mid = *find(ch, "p:tip.2");
  EXPECT_TRUE(near(mid.points.back(), Vec2(50, 10) + 4 * Vec2(1, 1) / std::sqrt(2.0)));
  // End: viewBox 10 x 10 into 2 x 2 stroke widths (x 2: 4 units), centred by refX/refY on the
  // vertex and turned 90 degrees: the 10 x 4 rectangle becomes 1.6 wide, 4 tall.
  const Bounds b = find(ch, "p:sq")->bounds();
  EXPECT_NEAR(b.width(), 1.6, 1e-6);
  EXPECT_NEAR(b.height(), 4, 1e-6);
  EXPECT_NEAR(b.hi.x(), 52, 1e-6);  // (the rect's top edge, y = 0 -> 5 above the ref, turned)
  EXPECT_NEAR(b.lo.y(), 48, 1e-6);
  EXPECT_TRUE(has_warning(ch, "marker 'url(#missing)' is no marker"));
}

TEST(load_svg, InkscapeLayersInDocumentOrder) {
  auto ch = load(R"svg(<rect id="loose" width="1" height="1"/>
                    <g inkscape:groupmode="layer" inkscape:label="Back"><rect id="a" width="1" height="1"/>
                      <g inkscape:groupmode="layer" inkscape:label="Sub"><rect id="b" width="1" height="1"/></g>
                    </g>
                    <g id="front"><g><rect id="c" width="1" height="1"/></g></g>)svg");
  ASSERT_EQ(ch.layers.size(), 4u);
  EXPECT_EQ(ch.layers[0], "(root)");
  EXPECT_EQ(ch.layers[1], "Back");
  EXPECT_EQ(ch.layers[2], "Sub");
  EXPECT_EQ(ch.layers[3], "front");
  EXPECT_EQ(find(ch, "b")->layer, 2);
  EXPECT_EQ(find(ch, "c")->layer, 3);
  EXPECT_EQ(ch.shapes.back().id, "c");  // paint order = document order
}

TEST(load_svg, IdsAreKeptAndMadeUnique) {
  auto ch = load(R"svg(<rect id="x" width="1" height="1"/><rect id="x" width="1" height="1"/>
<rect width="1" height="1"/>)svg");
  ASSERT_EQ(ch.shapes.size(), 3u);
  EXPECT_EQ(ch.shapes[0].id, "x");
  EXPECT_EQ(ch.shapes[1].id, "x.2");
  EXPECT_EQ(ch.shapes[2].id, "rect-L3");
}

TEST(load_svg, SwitchPicksFirstMatchingChild) {
  auto ch = load(R"svg(<switch><rect id="fr" systemLanguage="fr" width="1" height="1"/>
                    <rect id="en" systemLanguage="de, en-GB" width="1" height="1"/>
                    <rect id="other" width="1" height="1"/></switch>)svg");
  ASSERT_EQ(ch.shapes.size(), 1u);
  EXPECT_EQ(ch.shapes[0].id, "en");
}

// Text is drawn as its glyphs' outlines (in the font fontconfig picks), one shape a run, laid out
// along the baseline from x, y; text-anchor, tspans, letter-spacing and white space as SVG has them.
TEST(load_svg, TextIsItsGlyphsLaidOutAlongTheBaseline) {
  auto ch = load(R"svg(<text id="hi" x="10" y="50" font-family="DejaVu Sans" font-size="20">Hi</text>
                    <text id="mid" x="50" y="80" text-anchor="middle" font-family="DejaVu Sans" font-size="10">Hello</text>
                    <text id="end" x="50" y="90" text-anchor="end" font-family="DejaVu Sans" font-size="10">Hello</text>
                    <text id="spaced" x="0" y="20" font-family="DejaVu Sans" font-size="10">  a   b
                       c </text>
                    <text id="plain" x="0" y="30" font-family="DejaVu Sans" font-size="10">a b c</text>
                    <text id="wide" x="0" y="40" font-family="DejaVu Sans" font-size="10" letter-spacing="2">a b c</text>
                    <text x="0" y="60" font-family="DejaVu Sans" font-size="10">one <tspan id="two" x="60" fill="#f00">two</tspan></text>)svg",
                 R"svg(width="100" height="100")svg");
  EXPECT_TRUE(ch.warnings.empty()) << ch.warnings.front();
  const SubShape* hi = find(ch, "hi");
  ASSERT_TRUE(hi);
  EXPECT_EQ(hi->contours.size(), 3u);  // H, and i's stem and dot
  EXPECT_TRUE(hi->fill.enabled);
  EXPECT_EQ(color_hex(hi->fill.color), "#000000");
  const Bounds b = hi->bounds();
  EXPECT_NEAR(b.hi.y(), 50, 0.01);         // on the baseline
  EXPECT_NEAR(50 - b.lo.y(), 0.76 * 20, 1); // i's dot a little over the capitals (0.73 em)
  EXPECT_GT(b.lo.x(), 10);
  EXPECT_LT(b.lo.x(), 13);
  // Anchored: the middle about x, the end at x (within the glyphs' side bearings).
  const Bounds m = find(ch, "mid")->bounds(), e = find(ch, "end")->bounds();
  EXPECT_NEAR(0.5 * (m.lo.x() + m.hi.x()), 50, 0.6);
  EXPECT_NEAR(e.hi.x(), 50, 1.0);
  EXPECT_NEAR(m.hi.x() - m.lo.x(), e.hi.x() - e.lo.x(), 1e-9);
  // White space collapsed (newlines gone, runs of spaces one, none leading) as in "a b c".
  const Bounds sp = find(ch, "spaced")->bounds(), pl = find(ch, "plain")->bounds(), w = find(ch, "wide")->bounds();
  EXPECT_NEAR(sp.lo.x(), pl.lo.x(), 1e-9);
  EXPECT_NEAR(sp.hi.x(), pl.hi.x(), 1e-9);
  EXPECT_NEAR((w.hi.x() - w.lo.x()) - (pl.hi.x() - pl.lo.x()), 4 * 2, 1e-6);  // four gaps between five characters
  // A tspan is a run of its own: its own paint, from its own x.
  const SubShape* two = find(ch, "two");
  ASSERT_TRUE(two);
  EXPECT_EQ(color_hex(two->fill.color), "#ff0000");
  EXPECT_GE(two->bounds().lo.x(), 60);
  EXPECT_LT(two->bounds().lo.x(), 61);
}

// A tspan in a tspan ... 100,000 deep (a 1.5 MB file) overflowed the stack of the text's walk
// (a crash); it stops at 200 levels, as elements do, and says so.
TEST(load_svg, TextNestedPastTwoHundredLevelsIsSkipped) {
  std::string deep;
  for (int i = 0; i < 100000; ++i) deep += "<tspan>";
  deep += "x";
  for (int i = 0; i < 100000; ++i) deep += "</tspan>";
  auto ch = load("<text id=\"t\" x=\"0\" y=\"20\" font-family=\"DejaVu Sans\">ok " + deep + "</text>");
  EXPECT_TRUE(has_warning(ch, "nesting deeper than 200 levels; skipped"));
  ASSERT_TRUE(find(ch, "t"));  // the text above the cut is drawn
}

TEST(load_svg, NestedSvgViewport) {
  auto ch = load(R"svg(<svg x="10" y="10" width="20" height="20" viewBox="0 0 2 2"><rect width="1" height="1"/></svg>)svg");
  expect_bounds(ch.shapes.at(0), 10, 10, 20, 20, 1e-9);
}

TEST(load_svg, MalformedXmlNamesFileAndLine) {
  auto r = load_svg_string("<svg xmlns=\"http://www.w3.org/2000/svg\">\n<g>\n<rect/>\n</svg>\n", "broken.svg");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("broken.svg:4"), std::string::npos) << r.error;
  auto not_svg = load_svg_string("<html/>", "page.svg");
  ASSERT_FALSE(not_svg.ok());
  EXPECT_NE(not_svg.error.find("not <svg>"), std::string::npos);
  auto missing = load_svg_file("/nonexistent/file.svg");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error.find("cannot open"), std::string::npos);
}

// Work, not bytes: <use> nested ten deep over ten references each would visit 10^10 elements
// from 2 KB; the element bound refuses it after max_elements, naming the element it reached.
std::string laughs(int levels) {
  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\"><g id=\"a0\"><rect width=\"1\" height=\"1\"/></g>";
  for (int l = 1; l < levels; ++l) {
    s += "<g id=\"a" + std::to_string(l) + "\">";
    for (int k = 0; k < 10; ++k) s += "<use xlink:href=\"#a" + std::to_string(l - 1) + "\"/>";
    s += "</g>";
  }
  return s + "</svg>";
}

TEST(load_svg, UseExpansionIsBoundedByWorkNotBytes) {
  SvgOptions o;
  o.max_elements = 5000;
  auto r = load_svg_string(laughs(10), "laughs.svg", o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("laughs.svg:1: "), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("more than 5000 elements once <use> references are expanded"), std::string::npos) << r.error;
  // Three levels (1 + 10 + 100 rects with their groups and uses) load within it.
  auto ok = load_svg_string(laughs(3), "small.svg", o);
  ASSERT_TRUE(ok.ok()) << ok.error;
  EXPECT_EQ(ok.value->shapes.size(), 1u + 10u + 100u);
}

// One shape's points are bounded before its fill is triangulated.
TEST(load_svg, OneShapeOfTooManyPointsIsRefused) {
  SvgOptions o;
  o.max_shape_points = 1000;
  auto r = load_svg_string("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" height=\"100\" viewBox=\"0 0 1e-3 1e-3\"><circle r=\"1\"/></svg>", "c.svg", o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("c.svg:1: <circle>: one shape of"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("(at most 1000 a shape)"), std::string::npos) << r.error;
}

// Namespaces as XML defines them: the SVG namespace as the default with xmlns:svg declared too
// (2,102 of openclipart's files; their gradients' <stop>s were looked for as <svg:stop>, found
// nowhere, and the shapes dropped), only svg: prefixes, and the namespace under another prefix
// all load the same drawing. An element of another namespace is not drawn.
TEST(load_svg, ElementsAreMatchedByNamespaceNotByPrefix) {
  const std::string body =
      "<P:defs><P:linearGradient id=\"g\"><P:stop offset=\"0\" stop-color=\"#ff0000\"/><P:stop offset=\"1\" "
      "stop-color=\"#0000ff\"/></P:linearGradient></P:defs><P:rect width=\"10\" height=\"10\" fill=\"url(#g)\"/>"
      "<P:circle cx=\"20\" cy=\"5\" r=\"4\" fill=\"#00ff00\"/>";
  auto with = [&](const std::string& root, const std::string& prefix) {
    std::string b = body;
    for (size_t at = b.find("P:"); at != std::string::npos; at = b.find("P:", at)) b.replace(at, 2, prefix), at += prefix.size();
    return root + b + "</" + prefix + "svg>";
  };
  const std::vector<std::pair<std::string, std::string>> forms = {
      {with("<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:svg=\"http://www.w3.org/2000/svg\">", ""), "default and svg:"},
      {with("<svg:svg xmlns:svg=\"http://www.w3.org/2000/svg\">", "svg:"), "svg: only"},
      {with("<s:svg xmlns:s=\"http://www.w3.org/2000/svg\">", "s:"), "another prefix"},
      {with("<svg>", ""), "no namespace declared"}};
  for (const auto& [text, what] : forms) {
    auto r = load_svg_string(text, "ns.svg");
    ASSERT_TRUE(r.ok()) << what << ": " << r.error;
    ASSERT_EQ(r.value->shapes.size(), 2u) << what;
    EXPECT_TRUE(r.value->shapes[0].fill.enabled) << what;
    ASSERT_TRUE(r.value->shapes[0].fill.texture) << what << ": the gradient's stops were found";
    EXPECT_GT(r.value->shapes[0].fill.texture->rgba[0], 240) << what << ": red at the left";
    EXPECT_EQ(r.value->shapes[0].element, "rect") << what;
    EXPECT_EQ(r.value->shapes[1].element, "circle") << what;
    EXPECT_TRUE(r.value->dropped.empty()) << what;
    EXPECT_TRUE(r.value->approximated.empty()) << what;
  }
  auto foreign = load_svg_string(
      "<svg xmlns=\"http://www.w3.org/2000/svg\"><g xmlns=\"http://example.org/other\"><rect width=\"5\" height=\"5\"/></g>"
      "<x:rect xmlns:x=\"http://example.org/other\" width=\"5\" height=\"5\"/><rect width=\"2\" height=\"2\"/></svg>",
      "foreign.svg");
  ASSERT_TRUE(foreign.ok()) << foreign.error;
  EXPECT_EQ(foreign.value->shapes.size(), 1u) << "only the SVG rect";
}

// A shape whose paint cannot be resolved (a gradient with no stops, a missing paint) is
// dropped with a warning that names it, and counted by reason for inspect.
TEST(load_svg, ADroppedShapeIsSaidAndCounted) {
  auto r = load_svg_string(
      "<svg xmlns=\"http://www.w3.org/2000/svg\"><defs><linearGradient id=\"empty\"/></defs>"
      "<rect id=\"body\" width=\"10\" height=\"10\" fill=\"url(#empty)\"/><rect id=\"arm\" width=\"3\" height=\"3\" "
      "fill=\"url(#nowhere)\"/><rect id=\"leg\" width=\"3\" height=\"3\" fill=\"#000\" filter=\"url(#f)\"/></svg>",
      "drop.svg");
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.value->shapes.size(), 1u);
  EXPECT_EQ(r.value->dropped.at("its paint could not be resolved"), 2);
  EXPECT_EQ(r.value->approximated.at("a filter not found"), 1);
  std::string all;
  for (const std::string& w : r.value->warnings) all += w + "\n";
  EXPECT_NE(all.find("<rect id=\"body\">: linearGradient 'empty' has no stops; painted as none"), std::string::npos) << all;
  EXPECT_NE(all.find("<rect id=\"arm\">: paint url(#nowhere) not found"), std::string::npos) << all;
}

// Gradient fills are textures over the shape's rest bounds, evaluated at load: a linear one
// runs from its first stop's colour to its last along x1,y1 -> x2,y2, a radial one from the
// focal point outwards; objectBoundingBox and userSpaceOnUse units, gradientTransform, the
// spread methods and href inheritance of stops and attributes all change what is sampled.
TEST(load_svg, GradientFillsAreTexturesThatFollowTheShape) {
  auto texel = [](const SubShape& s, double fx, double fy) {
    const Texture& t = *s.fill.texture;
    const int x = std::clamp(int(fx * t.width), 0, t.width - 1), y = std::clamp(int(fy * t.height), 0, t.height - 1);
    const uint8_t* p = &t.rgba[(size_t(y) * size_t(t.width) + size_t(x)) * 4];
    return std::array<int, 4>{p[0], p[1], p[2], p[3]};
  };
  auto r = load_svg_string(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\">"
      "<defs><linearGradient id=\"rb\"><stop offset=\"0\" stop-color=\"red\"/><stop offset=\"1\" stop-color=\"blue\" "
      "stop-opacity=\"0.5\"/></linearGradient>"
      "<linearGradient id=\"down\" xlink:href=\"#rb\" x2=\"0\" y2=\"1\"/>"
      "<linearGradient id=\"user\" xlink:href=\"#rb\" gradientUnits=\"userSpaceOnUse\" x1=\"0\" x2=\"20\" "
      "spreadMethod=\"reflect\"/>"
      "<radialGradient id=\"spot\"><stop offset=\"0\" stop-color=\"white\"/><stop offset=\"1\" stop-color=\"black\"/>"
      "</radialGradient></defs>"
      "<rect width=\"40\" height=\"20\" fill=\"url(#rb)\"/>"
      "<rect y=\"30\" width=\"40\" height=\"20\" fill=\"url(#down)\"/>"
      "<rect y=\"60\" width=\"40\" height=\"20\" fill=\"url(#user)\"/>"
      "<circle cx=\"70\" cy=\"20\" r=\"10\" fill=\"url(#spot)\"/></svg>",
      "grad.svg");
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.value->shapes.size(), 4u);
  for (const SubShape& s : r.value->shapes) ASSERT_TRUE(s.fill.enabled && s.fill.texture) << s.id;
  const SubShape &across = r.value->shapes[0], &down = r.value->shapes[1], &user = r.value->shapes[2], &spot = r.value->shapes[3];
  // Left red and opaque, right blue at half opacity; along y nothing changes.
  EXPECT_GT(texel(across, 0.01, 0.5)[0], 245);
  EXPECT_LT(texel(across, 0.01, 0.5)[2], 10);
  EXPECT_GT(texel(across, 0.99, 0.5)[2], 245);
  EXPECT_NEAR(texel(across, 0.99, 0.5)[3], 128, 3);
  EXPECT_EQ(texel(across, 0.5, 0.1), texel(across, 0.5, 0.9));
  // x2 = 0, y2 = 1 inherited stops: red at the top, blue at the bottom.
  EXPECT_GT(texel(down, 0.5, 0.01)[0], 245);
  EXPECT_GT(texel(down, 0.5, 0.99)[2], 245);
  // userSpaceOnUse 0..20 with reflect over a 40-wide rect: blue at x = 20, red again at 40.
  EXPECT_GT(texel(user, 0.5, 0.5)[2], 240);
  EXPECT_GT(texel(user, 0.99, 0.5)[0], 240);
  // The radial: white in the middle, black at the rim.
  EXPECT_GT(texel(spot, 0.5, 0.5)[0], 240);
  EXPECT_LT(texel(spot, 0.02, 0.5)[0], 20);
  // The texture lies over the rest bounds: uv of the shape's corners are 0 and 1.
  const Bounds b = across.bounds();
  EXPECT_NEAR(across.fill.uv_from_point.apply(b.lo).x(), 0, 1e-9);
  EXPECT_NEAR(across.fill.uv_from_point.apply(b.hi).y(), 1, 1e-9);
  EXPECT_EQ(r.value->approximated.count("a gradient drawn as its mean colour"), 0u);
}

TEST(load_svg, TooComplexFileIsRejected) {
  std::string body;
  for (int i = 0; i < 50; ++i) body += "<circle cx=\"50\" cy=\"50\" r=\"40\"/>";
  SvgOptions o;
  o.max_points = 500;
  auto r = load_svg_string("<svg xmlns=\"http://www.w3.org/2000/svg\">" + body + "</svg>", "big.svg", o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("too complex"), std::string::npos);
}

// One huge path stops at the point budget while it is flattened (memory stays bounded), a path
// with more commands than the budget is refused while it is parsed, and a file past the size limit
// is refused before it is read.
TEST(load_svg, HugePathsAndFilesAreRefusedWithinTheirLimits) {
  std::string d = "M0 0";
  for (int i = 0; i < 3000; ++i) d += " L" + std::to_string(i % 97) + " " + std::to_string(i % 89);
  SvgOptions o;
  o.max_points = 1000;
  auto r = load_svg_string("<svg xmlns=\"http://www.w3.org/2000/svg\"><path d=\"" + d + "\"/></svg>", "long.svg", o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("long.svg:1: <path>: more than 1000 points"), std::string::npos) << r.error;
  const svg::PathData pd = svg::parse_path(d, 500);
  EXPECT_NE(pd.error.find("more than 500 path commands"), std::string::npos) << pd.error;
  EXPECT_TRUE(pd.cmds.empty());
  bool over = false;
  EXPECT_TRUE(svg::flatten_path(svg::parse_path(d).cmds, Affine2::identity(), 0.1, 100, &over).empty());
  EXPECT_TRUE(over);
  // A path's last curve over the budget is seen too, with the curve cut short at the budget.
  over = false;
  const svg::PathData curve = svg::parse_path("M0 0 C0 1e9 1e9 1e9 1e9 0");
  EXPECT_TRUE(svg::flatten_path(curve.cmds, Affine2::identity(), 1e-9, 100, &over).empty());
  EXPECT_TRUE(over);
  r = load_svg_string("<svg xmlns=\"http://www.w3.org/2000/svg\"><path d=\"M0 0 C0 1e9 1e9 1e9 1e9 0\"/></svg>", "curve.svg", o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("curve.svg:1: <path>: more than 1000 points"), std::string::npos) << r.error;
  const std::string big = test::write_temp("big.svg", "<svg xmlns=\"http://www.w3.org/2000/svg\">" + std::string(4096, ' ') + "</svg>");
  o.max_bytes = 1024;
  r = load_svg_file(big, o);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("big.svg: is 4 KB; at most 1 KB for an SVG character"), std::string::npos) << r.error;
}

// The issue's hostile files: 100,000 nested groups load (what is deeper than 200 levels is
// skipped with a warning; the XML parser and the walk are not recursive past that), and a path
// of 10 million commands is refused at the 4 million command budget without keeping any.
TEST(load_svg, ADeeplyNestedFileAndTenMillionPathCommandsStayWithinTheirLimits) {
  std::string deep = "<svg xmlns=\"http://www.w3.org/2000/svg\"><path d=\"M0 0 L10 0 L10 10 Z\"/>";
  for (int i = 0; i < 100000; ++i) deep += "<g>";
  deep += "<path d=\"M0 0 L5 0 L5 5 Z\"/>";
  for (int i = 0; i < 100000; ++i) deep += "</g>";
  deep += "</svg>";
  auto r = load_svg_string(deep, "deep.svg");
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.value->shapes.size(), 1u);
  bool warned = false;
  for (const std::string& w : r.value->warnings) warned = warned || w.find("nesting deeper than 200 levels") != std::string::npos;
  EXPECT_TRUE(warned);

  std::string d = "M0 0";
  d.reserve(50'000'010);
  for (int i = 0; i < 10'000'000; ++i) d += " l1 1";
  const svg::PathData pd = svg::parse_path(d);
  EXPECT_TRUE(pd.too_long);
  EXPECT_TRUE(pd.cmds.empty());
  EXPECT_NE(pd.error.find("more than 4000000 path commands"), std::string::npos) << pd.error;
}

TEST(load_svg, ExampleCharactersHaveOverlappingPartsAndOpenStrokes) {
  for (const char* name : {"butterfly", "figure", "koi"}) {
    auto r = load_svg_file(std::string(MARIONETTE_SOURCE_DIR) + "/config/characters/" + name + ".svg");
    ASSERT_TRUE(r.ok()) << r.error;
    const Character& ch = *r.value;
    EXPECT_TRUE(ch.warnings.empty()) << name << ": " << ch.warnings.front();
    size_t open = 0;
    for (const SubShape& s : ch.shapes) open += s.closed() ? 0 : 1;
    EXPECT_GE(ch.shapes.size(), 5u) << name;
    EXPECT_GE(open, 2u) << name;
    EXPECT_GE(ch.layers.size(), 3u) << name;
  }
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

TEST(load_svg, IllustratorStyleSheetWithClasses) {
  // Illustrator's default "internal CSS" export.
  auto ch = load(R"svg(<defs><style><![CDATA[
      .st0{fill:#FF0000;}
      .st1{fill:none;stroke:#0000FF;stroke-width:4;}
      /* comment */ rect.big, #special { fill: #00ff00 }
      @media print { .st0 { fill: black } }
      g > rect { fill: yellow }
    ]]></style></defs>
    <rect id="a" class="st0" width="1" height="1"/>
    <path id="b" class="st1" d="M0 0 L10 0"/>
    <rect id="c" class="st0 big" width="1" height="1"/>
    <circle id="special" class="st0" r="1"/>
    <rect id="d" class="st0" style="fill:#123456" width="1" height="1"/>
    <rect id="e" fill="#abcdef" width="1" height="1"/>)svg");
  EXPECT_EQ(color_hex(find(ch, "a")->fill.color), "#ff0000");
  EXPECT_FALSE(find(ch, "b")->fill.enabled);
  EXPECT_EQ(color_hex(find(ch, "b")->stroke.color), "#0000ff");
  EXPECT_DOUBLE_EQ(find(ch, "b")->stroke.width, 4);
  EXPECT_EQ(color_hex(find(ch, "c")->fill.color), "#00ff00");        // more specific rule wins
  EXPECT_EQ(color_hex(find(ch, "special")->fill.color), "#00ff00");  // id beats class
  EXPECT_EQ(color_hex(find(ch, "d")->fill.color), "#123456");        // style attribute beats CSS
  EXPECT_EQ(color_hex(find(ch, "e")->fill.color), "#abcdef");
  EXPECT_TRUE(has_warning(ch, "CSS selector 'g > rect' not supported"));
}

TEST(load_svg, CssImportantAndUniversal) {
  auto ch = load(R"svg(<style>* { fill: blue } .x { fill: green !important }</style>
    <rect id="a" width="1" height="1"/>
    <rect id="b" class="x" style="fill:red" width="1" height="1"/>)svg");
  EXPECT_EQ(color_hex(find(ch, "a")->fill.color), "#0000ff");
  EXPECT_EQ(color_hex(find(ch, "b")->fill.color), "#008000");
}

}  // namespace
}  // namespace mar

#include "render/image.h"
#include "test_util.h"

namespace mar {
namespace {

TEST(load_svg, ImageElementBecomesTexturedRectangle) {
  const auto dir = test::temp_dir("svg-image");
  Image img{4, 2, std::vector<std::uint8_t>(4 * 2 * 4, 255)};
  ASSERT_EQ(write_png((dir / "pic.png").string(), img), "");
  const std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" height=\"100\">\n"
                          "<image id=\"a\" href=\"pic.png\" x=\"10\" y=\"10\" width=\"40\" height=\"40\"/>\n"
                          "<image id=\"b\" href=\"pic.png\" x=\"10\" y=\"60\" width=\"40\" height=\"40\" "
                          "preserveAspectRatio=\"none\" transform=\"translate(50 0)\"/>\n"
                          "<image id=\"c\" href=\"missing.png\" width=\"5\" height=\"5\"/>\n"
                          "<image id=\"d\" href=\"data:image/png;base64,!!!!\" width=\"5\" height=\"5\"/>\n</svg>\n";
  std::ofstream((dir / "doc.svg").string()) << svg;
  auto r = load_svg_file((dir / "doc.svg").string());
  ASSERT_TRUE(r.ok()) << r.error;
  const Character& ch = *r.value;
  ASSERT_EQ(ch.shapes.size(), 2u);
  // 4x2 image in a 40x40 box, xMidYMid meet: 40 wide, 20 high, centred vertically.
  expect_bounds(ch.shapes[0], 10, 20, 50, 40, 1e-9);
  ASSERT_TRUE(ch.shapes[0].fill.texture);
  EXPECT_EQ(ch.shapes[0].fill.texture->width, 4);
  const Vec2 uv = ch.shapes[0].fill.uv_from_point.apply(Vec2(50, 40));
  EXPECT_NEAR(uv.x(), 1, 1e-12);
  EXPECT_NEAR(uv.y(), 1, 1e-12);
  expect_bounds(ch.shapes[1], 60, 60, 100, 100, 1e-9);  // stretched, moved by the transform
  EXPECT_NEAR(ch.shapes[1].fill.uv_from_point.apply(Vec2(80, 80)).x(), 0.5, 1e-12);
  EXPECT_TRUE(has_warning(ch, "No such file or directory"));
  EXPECT_TRUE(has_warning(ch, "cannot decode image"));
}

// An SVG document as an image is drawn as one: its shapes in the image's box (its viewBox fitted
// by the image's preserveAspectRatio, clipped to the box), read on its own (its ids and styles;
// none of the drawing's), from a file or a data URI; one nesting itself stops at 3 deep.
TEST(load_svg, AnSvgImageIsDrawnAsItsShapesInTheImagesBox) {
  const auto dir = test::temp_dir("svg-svg-image");
  std::ofstream((dir / "inner.svg").string())
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 20 10\"><style>.c { fill: #00ff00 }</style>"
         "<rect id=\"r\" class=\"c\" width=\"20\" height=\"10\"/></svg>";
  std::ofstream((dir / "self.svg").string())
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10\" height=\"10\"><rect width=\"1\" height=\"1\"/>"
         "<image href=\"self.svg\" width=\"10\" height=\"10\"/></svg>";
  const std::string inline_svg = "<svg xmlns='http://www.w3.org/2000/svg' width='4' height='4'><circle cx='2' cy='2' r='2'/></svg>";
  static const char* k64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string b64;
  for (size_t i = 0; i < inline_svg.size(); i += 3) {
    const unsigned v = (unsigned(uint8_t(inline_svg[i])) << 16) | (i + 1 < inline_svg.size() ? unsigned(uint8_t(inline_svg[i + 1])) << 8 : 0) |
                       (i + 2 < inline_svg.size() ? unsigned(uint8_t(inline_svg[i + 2])) : 0);
    b64 += k64[(v >> 18) & 63];
    b64 += k64[(v >> 12) & 63];
    b64 += i + 1 < inline_svg.size() ? k64[(v >> 6) & 63] : '=';
    b64 += i + 2 < inline_svg.size() ? k64[v & 63] : '=';
  }
  std::ofstream((dir / "doc.svg").string())
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" height=\"100\"><style>.c { fill: red }</style>\n"
         "<image id=\"a\" href=\"inner.svg\" x=\"10\" y=\"10\" width=\"40\" height=\"40\"/>\n"
         "<image id=\"b\" href=\"data:;base64," + b64 + "\" x=\"60\" y=\"60\" width=\"auto\"/>\n"
         "<image id=\"s\" href=\"self.svg\" x=\"80\" width=\"10\" height=\"10\"/>\n</svg>\n";
  auto r = load_svg_file((dir / "doc.svg").string());
  ASSERT_TRUE(r.ok()) << r.error;
  const Character& ch = *r.value;
  // The inner rect: 20 x 10 in a 40 x 40 box, xMidYMid meet: 40 x 20, centred; its own style sheet's green.
  const SubShape* rect = nullptr;
  for (const SubShape& sh : ch.shapes)
    if (sh.element == "rect" && sh.bounds().lo.x() < 50) rect = &sh;
  ASSERT_TRUE(rect);
  expect_bounds(*rect, 10, 20, 50, 40, 1e-9);
  EXPECT_EQ(color_hex(rect->fill.color), "#00ff00") << "the image's document styles itself";
  // The data URI with no type: an SVG by its bytes, its own size (4 x 4) where width is auto.
  const SubShape* circle = nullptr;
  for (const SubShape& sh : ch.shapes)
    if (sh.element == "circle") circle = &sh;
  ASSERT_TRUE(circle);
  expect_bounds(*circle, 60, 60, 64, 64, 0.05);
  // The self-nesting image: three deep, then said and stopped.
  int small = 0;
  for (const SubShape& sh : ch.shapes) small += sh.element == "rect" && sh.bounds().lo.x() >= 80;
  EXPECT_EQ(small, 3);
  EXPECT_TRUE(has_warning(ch, "SVG images nest more than 3 deep"));
}

// Where SVG 2 and SVG 1.1 differ as drawings meet them: href over xlink:href; a use of an svg
// keeps the svg's x and y; a symbol has no transform; a switch passes over elements SVG does
// not know; systemLanguage holds outside a switch too.
TEST(load_svg, HrefPrecedenceNestedSvgPlacementSwitchAndSystemLanguage) {
  auto ch = load(R"svg(<defs><rect id="red" width="5" height="5" fill="red"/><rect id="green" width="5" height="5" fill="#00ff00"/>
      <svg id="inner" x="40" y="40" width="10" height="10"><rect id="in" width="10" height="10"/></svg>
      <symbol id="sym" transform="skewX(30)"><rect id="sy" width="4" height="4"/></symbol></defs>
      <use id="u" xlink:href="#red" href="#green"/>
      <use id="v" href="#inner"/>
      <use id="w" href="#sym" x="80"/>
      <switch><unknown/><rect id="picked" y="90" width="2" height="2"/></switch>
      <rect id="russian" y="95" width="2" height="2" systemLanguage="ru-RU"/>)svg");
  bool green = false;
  for (const SubShape& sh : ch.shapes) green = green || color_hex(sh.fill.color) == "#00ff00";
  EXPECT_TRUE(green) << "href wins";
  for (const SubShape& sh : ch.shapes) EXPECT_NE(color_hex(sh.fill.color), "#ff0000") << sh.id;
  const SubShape* in = nullptr;
  const SubShape* sy = nullptr;
  for (const SubShape& sh : ch.shapes) {
    if (sh.id.find("in") != std::string::npos && sh.bounds().lo.x() >= 39) in = &sh;
    if (sh.bounds().lo.x() >= 79) sy = &sh;
  }
  ASSERT_TRUE(in);
  expect_bounds(*in, 40, 40, 50, 50, 1e-9);
  ASSERT_TRUE(sy);
  expect_bounds(*sy, 80, 0, 84, 4, 1e-9);
  EXPECT_TRUE(find(ch, "picked"));
  EXPECT_FALSE(find(ch, "russian"));
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

// Curves are flattened against the canvas: a 20-unit circle shown 40 times larger is within
// 0.1 px of the true circle there (0.0025 units), not 0.1 units (4 px); shown smaller, it keeps
// its 0.1 units.
TEST(load_character, CurvesAreFlattenedAgainstTheCanvasTheyAreDrawnOn) {
  const std::string path = test::write_temp("small.svg", R"svg(<svg xmlns="http://www.w3.org/2000/svg" width="20" height="20">
      <circle cx="10" cy="10" r="8"/></svg>)svg");
  auto deviation = [](const Character& ch) {
    double worst = 0;
    const Points& p = ch.shapes.at(0).points;
    for (size_t i = 0; i < p.size(); ++i) {
      const Vec2 mid = 0.5 * (p[i] + p[(i + 1) % p.size()]);  // (a chord's middle is its farthest point)
      worst = std::max(worst, 8 - (mid - Vec2(10, 10)).norm());
    }
    return worst;
  };
  auto plain = load_character(path);
  ASSERT_TRUE(plain.ok()) << plain.error;
  EXPECT_LE(deviation(*plain.value), 0.1);
  EXPECT_GT(deviation(*plain.value), 0.0025);
  LoadOptions lo;
  double asked_w = 0;
  lo.pixels_per_unit = [&](double w, double) {
    asked_w = w;
    return 40.0;
  };
  auto large = load_character(path, lo);
  ASSERT_TRUE(large.ok()) << large.error;
  EXPECT_EQ(asked_w, 20);  // (the document's size)
  EXPECT_LE(deviation(*large.value), 0.1 / 40);
  EXPECT_GT(large.value->shapes[0].points.size(), 3 * plain.value->shapes[0].points.size());
  lo.pixels_per_unit = [](double, double) { return 0.5; };
  auto small = load_character(path, lo);
  ASSERT_TRUE(small.ok());
  EXPECT_EQ(small.value->shapes[0].points.size(), plain.value->shapes[0].points.size());
}

}  // namespace
}  // namespace mar
