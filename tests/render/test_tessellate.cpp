#include "render/tessellate.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mar {
namespace {

// Area covered by the triangles (union approximated by rasterising on a fine grid, so
// overlaps at joins are not double counted).
double covered_area(const DrawList& d, double x0, double y0, double x1, double y1, double step = 0.05) {
  double area = 0;
  for (double y = y0 + step / 2; y < y1; y += step) {
    for (double x = x0 + step / 2; x < x1; x += step) {
      for (size_t t = 0; t + 2 < d.indices.size(); t += 3) {
        const SDL_FPoint& a = d.vertices[static_cast<size_t>(d.indices[t])].position;
        const SDL_FPoint& b = d.vertices[static_cast<size_t>(d.indices[t + 1])].position;
        const SDL_FPoint& c = d.vertices[static_cast<size_t>(d.indices[t + 2])].position;
        auto edge = [&](const SDL_FPoint& p, const SDL_FPoint& q) {
          return (q.x - p.x) * (y - p.y) - (q.y - p.y) * (x - p.x);
        };
        const double e0 = edge(a, b), e1 = edge(b, c), e2 = edge(c, a);
        if ((e0 >= 0 && e1 >= 0 && e2 >= 0) || (e0 <= 0 && e1 <= 0 && e2 <= 0)) {
          area += step * step;
          break;
        }
      }
    }
  }
  return area;
}

TEST(stroke_polyline, ButtSquareAndRoundCaps) {
  const Points line{{0, 0}, {10, 0}};
  StrokeStyle st;
  st.half_width = 1;
  st.tolerance = 0.01;
  DrawList butt, square, round;
  st.cap = LineCap::Butt;
  stroke_polyline(line, false, st, {}, butt);
  st.cap = LineCap::Square;
  stroke_polyline(line, false, st, {}, square);
  st.cap = LineCap::Round;
  stroke_polyline(line, false, st, {}, round);
  EXPECT_NEAR(covered_area(butt, -2, -2, 12, 2), 20, 0.3);
  EXPECT_NEAR(covered_area(square, -2, -2, 12, 2), 24, 0.3);
  EXPECT_NEAR(covered_area(round, -2, -2, 12, 2), 20 + M_PI, 0.3);
}

TEST(stroke_polyline, JoinsFillTheOuterCorner) {
  const Points corner{{0, 0}, {10, 0}, {10, 10}};
  StrokeStyle st;
  st.half_width = 1;
  st.tolerance = 0.01;
  DrawList miter, bevel, round;
  st.join = LineJoin::Miter;
  stroke_polyline(corner, false, st, {}, miter);
  st.join = LineJoin::Bevel;
  stroke_polyline(corner, false, st, {}, bevel);
  st.join = LineJoin::Round;
  stroke_polyline(corner, false, st, {}, round);
  const double base = 20 + 20 - 1;  // two 10x2 bars overlapping in a 1x1 square
  EXPECT_NEAR(covered_area(miter, -2, -2, 12, 12), base + 1.0, 0.3);
  EXPECT_NEAR(covered_area(bevel, -2, -2, 12, 12), base + 0.5, 0.3);
  EXPECT_NEAR(covered_area(round, -2, -2, 12, 12), base + M_PI / 4, 0.3);
}

TEST(stroke_polyline, MiterLimitFallsBackToBevel) {
  const Points sharp{{0, 0}, {10, 0}, {0, 1}};  // very acute turn
  StrokeStyle st;
  st.half_width = 1;
  st.join = LineJoin::Miter;
  st.miter_limit = 4;
  DrawList d;
  stroke_polyline(sharp, false, st, {}, d);
  for (const SDL_Vertex& v : d.vertices) EXPECT_LT(v.position.x, 12.5f);  // no long spike
}

TEST(stroke_polyline, ClosedRingAndDegenerateInput) {
  const Points sq{{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  StrokeStyle st;
  st.half_width = 1;
  DrawList closed;
  stroke_polyline(sq, true, st, {}, closed);
  EXPECT_NEAR(covered_area(closed, -2, -2, 12, 12, 0.1), 12 * 12 - 8 * 8, 0.5);
  DrawList dot;
  st.cap = LineCap::Round;
  st.tolerance = 0.01;
  stroke_polyline(Points{{5, 5}, {5, 5}}, false, st, {}, dot);
  EXPECT_NEAR(covered_area(dot, 3, 3, 7, 7), M_PI, 0.2);
  DrawList none;
  stroke_polyline(Points{{5, 5}}, false, st, {}, none);
  EXPECT_TRUE(none.indices.empty());
}

TEST(build_draw_list, FollowsDeformedPositionsAndKeepsPaintOrder) {
  Character ch;
  ch.width = ch.height = 10;
  ch.layers = {"l"};
  for (int k = 0; k < 2; ++k) {
    SubShape s;
    s.id = "s" + std::to_string(k);
    s.points = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
    s.contours = {{0, 4, true}};
    s.fill.enabled = true;
    s.fill.color = k == 0 ? Rgba{1, 0, 0, 1} : Rgba{0, 0, 1, 1};
    ch.shapes.push_back(s);
  }
  const CharacterMesh mesh = prepare_mesh(ch);
  DrawList rest, moved;
  build_draw_list(ch, mesh, {}, Affine2::identity(), 0.25, rest);
  std::vector<Points> pos{ch.shapes[0].points, ch.shapes[1].points};
  for (Vec2& p : pos[1]) p += Vec2(5, 5);
  build_draw_list(ch, mesh, pos, Affine2::identity(), 0.25, moved);
  ASSERT_EQ(rest.vertices.size(), moved.vertices.size());
  ASSERT_EQ(moved.batches.size(), 1u);  // same (no) texture: one batch
  // First shape's triangles come first and are red; second's are moved and blue.
  EXPECT_EQ(moved.vertices[static_cast<size_t>(moved.indices.front())].color.r, 255);
  const SDL_Vertex& last = moved.vertices[static_cast<size_t>(moved.indices.back())];
  EXPECT_EQ(last.color.b, 255);
  EXPECT_GE(last.position.x, 5.0f);
}

// A stroke whose pen is squashed (Stroke::pen, from a transform scaling x and y apart) is wider
// across x than across y; turned with its shape, the wide side turns with it.
TEST(build_draw_list, ASquashedPenTurnsWithItsShape) {
  Character ch;
  ch.width = ch.height = 40;
  ch.layers = {"l"};
  SubShape s;
  s.id = "ring";
  for (int k = 0; k < 64; ++k) s.points.push_back(Vec2(10 * std::cos(k * M_PI / 32), 10 * std::sin(k * M_PI / 32)));
  s.contours = {{0, 64, true}};
  s.stroke.enabled = true;
  s.stroke.width = 2;               // the pen's area is a circle's of radius 1:
  s.stroke.pen = Affine2::scale(2, 0.5);  // 2 across x, 0.5 across y
  ch.shapes.push_back(s);
  const CharacterMesh mesh = prepare_mesh(ch);
  auto extent = [&](const std::vector<Points>& pos) {
    DrawList d;
    build_draw_list(ch, mesh, pos, Affine2::identity(), 0.05, d);
    Vec2 hi(-1e9, -1e9);
    for (const SDL_Vertex& v : d.vertices) hi = hi.cwiseMax(Vec2(v.position.x, v.position.y));
    return hi;
  };
  const Vec2 rest = extent({});
  EXPECT_NEAR(rest.x(), 12.0, 0.05);
  EXPECT_NEAR(rest.y(), 10.5, 0.05);
  std::vector<Points> turned{s.points};
  for (Vec2& p : turned[0]) p = Vec2(-p.y(), p.x());  // a quarter turn
  const Vec2 moved = extent(turned);
  EXPECT_NEAR(moved.x(), 10.5, 0.05);
  EXPECT_NEAR(moved.y(), 12.0, 0.05);
}

}  // namespace
}  // namespace mar
