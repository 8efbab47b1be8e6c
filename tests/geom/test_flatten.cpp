#include "geom/flatten.h"
#include "geom/polygon.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

Vec2 cubic_at(const Vec2& p0, const Vec2& p1, const Vec2& p2, const Vec2& p3, double t) {
  const double u = 1 - t;
  return u * u * u * p0 + 3 * u * u * t * p1 + 3 * u * t * t * p2 + t * t * t * p3;
}

double max_deviation(const Points& poly, const Vec2& p0, const Vec2& p1, const Vec2& p2, const Vec2& p3) {
  double worst = 0;
  for (int k = 0; k <= 2000; ++k) {
    const Vec2 q = cubic_at(p0, p1, p2, p3, k / 2000.0);
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i + 1 < poly.size(); ++i) best = std::min(best, point_segment_distance(q, poly[i], poly[i + 1]));
    worst = std::max(worst, best);
  }
  return worst;
}

TEST(flatten_cubic, StaysWithinToleranceAndAdaptsToCurvature) {
  const Vec2 p0(0, 0), p1(0, 100), p2(100, 100), p3(100, 0);
  for (double tol : {1.0, 0.1, 0.01}) {
    Points poly{p0};
    flatten_cubic(p0, p1, p2, p3, tol, poly);
    EXPECT_LE(max_deviation(poly, p0, p1, p2, p3), tol * 1.0001) << "tol " << tol;
    EXPECT_EQ(poly.back(), p3);
  }
  Points coarse{p0}, fine{p0};
  flatten_cubic(p0, p1, p2, p3, 1.0, coarse);
  flatten_cubic(p0, p1, p2, p3, 0.01, fine);
  EXPECT_GT(fine.size(), coarse.size() * 4);
}

TEST(flatten_cubic, StraightCurveGivesOneSegment) {
  Points poly{Vec2(0, 0)};
  flatten_cubic({0, 0}, {10, 0}, {20, 0}, {30, 0}, 0.1, poly);
  EXPECT_EQ(poly.size(), 2u);
}

TEST(flatten_cubic, SkipsNonFiniteInput) {
  Points poly;
  flatten_cubic({0, 0}, {NAN, 0}, {20, 0}, {30, 0}, 0.1, poly);
  EXPECT_TRUE(poly.empty());
}

// A curve whose tolerance is tiny beside its size splits to the depth limit, 2^18 points; a
// caller's cap stops the subdivision as soon as `out` holds that many (the fuzzer's 14 KB SVG
// spent 1.5 s instrumented flattening such curves past a 20,000-point budget).
TEST(flatten_cubic, StopsAtTheCallersCap) {
  const Vec2 p0(0, 0), p1(0, 1e9), p2(1e9, 1e9), p3(1e9, 0);
  Points all{p0}, capped{p0};
  flatten_cubic(p0, p1, p2, p3, 1e-9, all);
  EXPECT_EQ(all.size(), (1u << 18) + 1);
  flatten_cubic(p0, p1, p2, p3, 1e-9, capped, 1001);
  ASSERT_EQ(capped.size(), 1001u);
  for (size_t i = 0; i < capped.size(); ++i) EXPECT_EQ(capped[i], all[i]) << i;
  Points full(5000, p0);
  flatten_cubic(p0, p1, p2, p3, 1e-9, full, 10);
  EXPECT_EQ(full.size(), 5000u);
}

TEST(flatten_quad, MatchesElevatedCubic) {
  Points a{Vec2(0, 0)}, b{Vec2(0, 0)};
  flatten_quad({0, 0}, {50, 100}, {100, 0}, 0.05, a);
  flatten_cubic({0, 0}, Vec2(0, 0) + 2.0 / 3.0 * Vec2(50, 100), Vec2(100, 0) + 2.0 / 3.0 * Vec2(-50, 100),
                {100, 0}, 0.05, b);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_NEAR((a[i] - b[i]).norm(), 0, 1e-12);
}

TEST(arc_to_cubics, SemicircleStaysOnCircle) {
  std::vector<CubicSeg> segs;
  arc_to_cubics({0, 0}, 50, 50, 0, false, true, {100, 0}, segs);
  ASSERT_GE(segs.size(), 4u);  // <= 45 degrees each
  Vec2 prev(0, 0);
  for (const CubicSeg& s : segs) {
    for (int k = 0; k <= 20; ++k) {
      const Vec2 q = cubic_at(prev, s.c1, s.c2, s.p, k / 20.0);
      EXPECT_NEAR((q - Vec2(50, 0)).norm(), 50.0, 50.0 * 1e-5);
    }
    prev = s.p;
  }
  EXPECT_EQ(segs.back().p, Vec2(100, 0));
  // sweep=1 from (0,0) to (100,0) around (50,0) goes through y < 0 (SVG's y-down "clockwise").
  EXPECT_LT(segs[1].p.y(), 0);
}

TEST(arc_to_cubics, RadiiTooSmallAreScaledUp) {
  std::vector<CubicSeg> segs;
  arc_to_cubics({0, 0}, 1, 1, 0, false, true, {100, 0}, segs);  // F.6.6: becomes r = 50
  Vec2 prev(0, 0);
  for (const CubicSeg& s : segs) {
    const Vec2 q = cubic_at(prev, s.c1, s.c2, s.p, 0.5);
    EXPECT_NEAR((q - Vec2(50, 0)).norm(), 50.0, 1e-3);
    prev = s.p;
  }
}

TEST(arc_to_cubics, ZeroRadiusIsLineAndSamePointIsNothing) {
  std::vector<CubicSeg> segs;
  arc_to_cubics({0, 0}, 0, 10, 0, false, true, {10, 0}, segs);
  ASSERT_EQ(segs.size(), 1u);
  EXPECT_NEAR(segs[0].c1.y(), 0, 1e-12);
  segs.clear();
  arc_to_cubics({5, 5}, 10, 10, 0, true, true, {5, 5}, segs);
  EXPECT_TRUE(segs.empty());
}

TEST(arc_to_cubics, LargeArcFlagPicksTheLongWay) {
  std::vector<CubicSeg> small_arc, large_arc;
  arc_to_cubics({0, 0}, 100, 100, 0, false, true, {100, 0}, small_arc);
  arc_to_cubics({0, 0}, 100, 100, 0, true, true, {100, 0}, large_arc);
  EXPECT_GT(large_arc.size(), small_arc.size());
}

}  // namespace
}  // namespace mar
