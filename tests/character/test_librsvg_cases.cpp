// Each paint server, filter, clip, mask, opacity and text case drawn beside librsvg's rendering of the
// same file (rsvg-convert): at least 97% of the pixels drawn in either picture are within
// 24/255 of librsvg's in every channel (blur is three box blurs here, an exact Gaussian there;
// edges are anti-aliased a little differently). Skipped, saying so, without rsvg-convert
// (apt-get install librsvg2-bin).
#include "character/load.h"
#include "render/canvas.h"
#include "render/image.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace mar {
namespace {

struct Case {
  const char* name;
  const char* body;
};

const Case kCases[] = {
    {"linear", R"svg(<defs><linearGradient id="g" x1="0" y1="0" x2="1" y2="1" gradientTransform="rotate(10)"><stop offset="0" stop-color="#f00"/>
       <stop offset="0.5" stop-color="#ff0" stop-opacity="0.5"/><stop offset="1" stop-color="#00f"/></linearGradient></defs>
       <rect x="10" y="10" width="80" height="60" fill="url(#g)"/>)svg"},
    {"radial", R"svg(<defs><radialGradient id="g" cx="0.5" cy="0.5" r="0.5" fx="0.3" fy="0.3" spreadMethod="reflect"><stop offset="0" stop-color="#fff"/>
       <stop offset="1" stop-color="#063"/></radialGradient></defs><ellipse cx="50" cy="40" rx="40" ry="30" fill="url(#g)"/>)svg"},
    {"stroke", R"svg(<defs><linearGradient id="g" gradientUnits="userSpaceOnUse" x1="10" x2="90"><stop offset="0" stop-color="#f0f"/>
       <stop offset="1" stop-color="#0a0"/></linearGradient></defs>
       <path d="M10 60 C 30 10, 70 10, 90 60" fill="none" stroke="url(#g)" stroke-width="8"/>)svg"},
    {"pattern", R"svg(<defs><pattern id="p" width="12" height="12" patternUnits="userSpaceOnUse" patternTransform="rotate(30)">
       <rect width="6" height="6" fill="#c30"/><circle cx="9" cy="9" r="2" fill="#039"/></pattern></defs>
       <circle cx="50" cy="40" r="32" fill="url(#p)" stroke="#000"/>)svg"},
    {"blur", R"svg(<defs><filter id="f"><feGaussianBlur stdDeviation="3"/></filter></defs>
       <rect x="25" y="20" width="50" height="40" fill="#036" filter="url(#f)"/>)svg"},
    {"shadow", R"svg(<defs><filter id="f" x="-0.5" y="-0.5" width="2" height="2"><feFlood flood-opacity="0.5" flood-color="#000" result="flood"/>
       <feComposite in="flood" in2="SourceGraphic" operator="in" result="c"/><feGaussianBlur in="c" stdDeviation="2"/>
       <feOffset dx="5" dy="5" result="o"/><feComposite in="SourceGraphic" in2="o" operator="over"/></filter></defs>
       <rect x="20" y="15" width="50" height="40" fill="#fc0" filter="url(#f)"/>)svg"},
    {"clip", R"svg(<defs><clipPath id="c" clipPathUnits="objectBoundingBox"><circle cx="0.5" cy="0.5" r="0.45"/></clipPath></defs>
       <g clip-path="url(#c)"><rect x="10" y="10" width="80" height="60" fill="#393"/><rect x="10" y="30" width="80" height="10" fill="#fff"/></g>)svg"},
    {"mask", R"svg(<defs><linearGradient id="g"><stop offset="0" stop-color="#fff"/><stop offset="1" stop-color="#000"/></linearGradient>
       <mask id="m"><rect x="0" y="0" width="100" height="80" fill="url(#g)"/></mask>
       <mask id="a" style="mask-type:alpha"><circle cx="70" cy="40" r="20" fill="#000" fill-opacity="0.5"/></mask></defs>
       <rect x="10" y="10" width="50" height="60" fill="#90c" mask="url(#m)"/><rect x="50" y="20" width="40" height="40" fill="#c60" mask="url(#a)"/>)svg"},
    {"opacity", R"svg(<g opacity="0.5"><circle cx="40" cy="40" r="25" fill="#00c"/><circle cx="60" cy="40" r="25" fill="#c00"/></g>
       <rect x="10" y="60" width="80" height="12" fill="#0c0" stroke="#000" stroke-width="4" opacity="0.6"/>)svg"},
    {"text", R"svg(<text x="8" y="30" font-family="DejaVu Sans" font-size="16" fill="#036">Hello <tspan font-weight="bold" fill="#c00">there</tspan></text>
       <text x="50" y="62" text-anchor="middle" font-family="serif" font-size="15" font-style="italic" letter-spacing="1">centred</text>)svg"},
    {"dashes_markers", R"svg(<defs><marker id="m" orient="auto" markerWidth="6" markerHeight="6" refX="3" refY="3">
       <path d="M0 0 L6 3 L0 6 z" fill="#c00"/></marker></defs>
       <path d="M10 20 L50 60 L90 20" fill="none" stroke="#000" stroke-width="2" stroke-dasharray="8 4" marker-end="url(#m)" marker-mid="url(#m)"/>)svg"},
};

// A pen squashed by the shape's transform: wider across one axis than the other, as SVG strokes
// in the element's own units (its miter limit is taken there too, as SVG and resvg take it;
// librsvg takes it on the screen).
const Case kStrokeCases[] = {
    {"squashed_pen", R"svg(<g transform="matrix(2.4,0,0,0.8,-40,8)"><circle cx="37" cy="40" r="20" fill="none" stroke="#000" stroke-width="6"/></g>)svg"},
};

// The share of the pixels drawn in either picture (a channel under 239) within `tolerance` of
// librsvg's in every channel, `c` drawn at 300x240 by both.
double agreement(const Case& c, const std::filesystem::path& dir, int tolerance) {
  const std::string svg = (dir / (std::string(c.name) + ".svg")).string(), ref = (dir / (std::string(c.name) + ".png")).string();
  std::ofstream(svg) << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"100\" height=\"80\">" << c.body << "</svg>";
  EXPECT_EQ(std::system(("rsvg-convert -w 300 -h 240 -b white '" + svg + "' -o '" + ref + "'").c_str()), 0) << c.name;
  LoadOptions lo;
  lo.pixels_per_unit = [](double w, double h) { return fit_view(w, h, 300, 240).max_scale(); };
  auto ch = load_character(svg, lo);
  EXPECT_TRUE(ch.ok()) << ch.error;
  if (!ch.ok()) return 0;
  EXPECT_TRUE(ch.value->warnings.empty()) << c.name << ": " << ch.value->warnings.front();
  RenderOptions o;
  o.width = 300;
  o.height = 240;
  o.background = Rgba{1, 1, 1, 1};
  auto ours = render_character(*ch.value, prepare_mesh(*ch.value), o);
  auto theirs = read_png_image(ref);
  EXPECT_TRUE(ours.ok() && theirs.ok()) << c.name;
  if (!ours.ok() || !theirs.ok()) return 0;
  size_t drawn = 0, close = 0;
  for (size_t i = 0; i + 3 < ours.value->rgba.size(); i += 4) {
    bool ink = false, near = true;
    for (size_t k = 0; k < 3; ++k) {
      ink = ink || ours.value->rgba[i + k] < 239 || theirs.value->rgba[i + k] < 239;
      near = near && std::abs(int(ours.value->rgba[i + k]) - int(theirs.value->rgba[i + k])) <= tolerance;
    }
    drawn += ink;
    close += ink && near;
  }
  EXPECT_GT(drawn, 1000u) << c.name;
  std::printf("%-15s %5.1f%% of %zu drawn pixels within %d/255 of librsvg's\n", c.name, 100.0 * double(close) / double(drawn), drawn,
              tolerance);
  return drawn ? double(close) / double(drawn) : 0.0;
}

TEST(Librsvg, AStrokeTakesItsPenFromItsTransform) {
  if (std::system("command -v rsvg-convert >/dev/null 2>&1") != 0) GTEST_SKIP() << "rsvg-convert is not installed (apt-get install librsvg2-bin)";
  const auto dir = test::temp_dir("librsvg_strokes");
  for (const Case& c : kStrokeCases) EXPECT_GE(agreement(c, dir, 16), 0.97) << c.name;  // (66.5% with a round pen)
}

TEST(Librsvg, EachCaseIsDrawnAsLibrsvgDrawsIt) {
  if (std::system("command -v rsvg-convert >/dev/null 2>&1") != 0) GTEST_SKIP() << "rsvg-convert is not installed (apt-get install librsvg2-bin)";
  const auto dir = test::temp_dir("librsvg_cases");
  for (const Case& c : kCases) EXPECT_GE(agreement(c, dir, 24), 0.97) << c.name;
}

}  // namespace
}  // namespace mar
