#include "geom/polygon.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

TEST(signed_area, SignFollowsOrientation) {
  Points sq{{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  EXPECT_DOUBLE_EQ(signed_area(sq), 100.0);
  std::reverse(sq.begin(), sq.end());
  EXPECT_DOUBLE_EQ(signed_area(sq), -100.0);
}

TEST(winding_number, InsideOutsideAndDoubleLoop) {
  Points sq{{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  EXPECT_EQ(winding_number(sq, {5, 5}), 1);
  EXPECT_EQ(winding_number(sq, {15, 5}), 0);
  Points twice = sq;
  twice.insert(twice.end(), sq.begin(), sq.end());
  EXPECT_EQ(winding_number(twice, {5, 5}), 2);
}

TEST(simplify_polyline, KeepsEndsAndBoundsDeviation) {
  Points pts;
  for (int i = 0; i <= 200; ++i) pts.emplace_back(i, std::sin(i * 0.05) * 20);
  const Points s = simplify_polyline(pts, 0.5, false);
  EXPECT_LT(s.size(), pts.size() / 4);
  EXPECT_EQ(s.front(), pts.front());
  EXPECT_EQ(s.back(), pts.back());
  for (const Vec2& p : pts) {
    double best = 1e9;
    for (size_t i = 0; i + 1 < s.size(); ++i) best = std::min(best, point_segment_distance(p, s[i], s[i + 1]));
    EXPECT_LE(best, 0.5 + 1e-12);
  }
}

TEST(simplify_polyline, ClosedRingCoversWrapAround) {
  Points ring;
  for (int i = 0; i < 360; ++i) ring.emplace_back(50 * std::cos(i * M_PI / 180), 50 * std::sin(i * M_PI / 180));
  const Points s = simplify_polyline(ring, 0.25, true);
  EXPECT_LT(s.size(), 60u);
  EXPECT_GT(s.size(), 8u);
  for (const Vec2& p : ring) {
    double best = 1e9;
    for (size_t i = 0; i < s.size(); ++i) best = std::min(best, point_segment_distance(p, s[i], s[(i + 1) % s.size()]));
    EXPECT_LE(best, 0.25 + 1e-9);
  }
}

TEST(remove_duplicate_points, DropsRepeatsAndClosingPoint) {
  Points p{{0, 0}, {0, 0}, {1, 0}, {1, 1}, {1, 1}, {0, 0}};
  remove_duplicate_points(p, true);
  EXPECT_EQ(p.size(), 3u);
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

TEST(affine_fit, RecoversAnAffineMapAndFallsBackOnALine) {
  const Affine2 m{1.5, 0.25, -0.5, 0.75, 10, -4};
  std::vector<Vec2> from{{0, 0}, {10, 0}, {10, 5}, {0, 5}, {3, 2}}, to;
  for (const Vec2& p : from) to.push_back(m.apply(p));
  const Affine2 f = affine_fit(from, to);
  for (double v : {f.a - m.a, f.b - m.b, f.c - m.c, f.d - m.d, f.e - m.e, f.f - m.f}) EXPECT_NEAR(v, 0, 1e-9);
  // Points on one line do not fix the map across it: the centroids' translation.
  const std::vector<Vec2> line{{0, 0}, {10, 0}}, moved{{1, 2}, {11, 2}};
  const Affine2 t = affine_fit(line, moved);
  EXPECT_NEAR(t.apply(Vec2(5, 7)).x(), 6, 1e-9);
  EXPECT_NEAR(t.apply(Vec2(5, 7)).y(), 9, 1e-9);
  EXPECT_NEAR(affine_fit({}, {}).det(), 1, 1e-12);
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

// The brush's Gaussian (app/loop/brush.h) uses portable_exp_neg: the same bits on x86-64 and
// arm64, within a few ulp of glibc's exp over the range it is used on.
TEST(PortableExp, AgreesWithExpToAFewUlp) {
  double worst = 0;
  for (int i = 0; i <= 20000; ++i) {
    const double x = -40.0 * i / 20000.0;
    const double e = std::exp(x);
    worst = std::max(worst, std::abs(portable_exp_neg(x) - e) / e);
  }
  EXPECT_LT(worst, 1e-15);
  EXPECT_EQ(portable_exp_neg(0.0), 1.0);
  EXPECT_EQ(portable_exp_neg(-1000.0), 0.0);
  EXPECT_EQ(portable_exp_neg(std::nan("")), 0.0);
}

}  // namespace
}  // namespace mar
