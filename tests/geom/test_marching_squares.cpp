#include "geom/marching_squares.h"
#include "geom/polygon.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

// A 100x100 image with an annulus (outer r 30, inner r 12) around (35, 50) and a solid
// 20x20 square at (70..90, 10..30).
std::vector<float> test_image() {
  std::vector<float> v(100 * 100, 0.0f);
  for (int y = 0; y < 100; ++y) {
    for (int x = 0; x < 100; ++x) {
      const double d = std::hypot(x + 0.5 - 35, y + 0.5 - 50);
      if (d <= 30 && d >= 12) v[y * 100 + x] = 1.0f;
      if (x >= 70 && x < 90 && y >= 10 && y < 30) v[y * 100 + x] = 1.0f;
    }
  }
  return v;
}

TEST(trace_iso_rings, OuterPositiveHolesNegative) {
  const auto rings = trace_iso_rings(test_image(), 100, 100, 0.5f);
  ASSERT_EQ(rings.size(), 3u);
  int pos = 0, neg = 0;
  for (const auto& r : rings) (r.area > 0 ? pos : neg)++;
  EXPECT_EQ(pos, 2);
  EXPECT_EQ(neg, 1);
}

TEST(trace_iso_rings, SquareAreaMatchesPixelCount) {
  std::vector<float> v(10 * 10, 0.0f);
  for (int y = 2; y < 6; ++y)
    for (int x = 3; x < 8; ++x) v[y * 10 + x] = 1.0f;
  const auto rings = trace_iso_rings(v, 10, 10, 0.5f);
  ASSERT_EQ(rings.size(), 1u);
  // Midpoint crossings cut each corner by half a pixel squared: 5x4 - 4 * 1/8.
  EXPECT_NEAR(rings[0].area, 20.0 - 0.5, 1e-9);
}

TEST(trace_iso_rings, SoftAlphaGivesSubPixelEdges) {
  std::vector<float> v(8 * 3, 0.0f);
  for (int x = 0; x < 8; ++x) {
    v[8 + x] = 1.0f;
  }
  v[8 + 0] = 0.75f;  // interpolated crossing moves with the alpha
  const auto rings = trace_iso_rings(v, 8, 3, 0.5f);
  ASSERT_EQ(rings.size(), 1u);
  double min_x = 1e9;
  for (const Vec2& p : rings[0].points) min_x = std::min(min_x, p.x());
  // crossing between sample -1 (outside, value -1) and sample 0 (0.75): t = 1.5/1.75
  EXPECT_NEAR(min_x, -0.5 + 1.5 / 1.75, 1e-6);
}

TEST(trace_iso_rings, EmptyAndFullImages) {
  EXPECT_TRUE(trace_iso_rings(std::vector<float>(16, 0.0f), 4, 4, 0.5f).empty());
  const auto full = trace_iso_rings(std::vector<float>(16, 1.0f), 4, 4, 0.5f);
  ASSERT_EQ(full.size(), 1u);
  EXPECT_GT(full[0].area, 0);
  EXPECT_TRUE(trace_iso_rings(std::vector<float>(3, 1.0f), 4, 4, 0.5f).empty());  // too small buffer
}

TEST(trace_iso_rings, DiagonalPixelsStayConnected) {
  std::vector<float> v(4 * 4, 0.0f);
  v[1 * 4 + 1] = 1;
  v[2 * 4 + 2] = 1;
  EXPECT_EQ(trace_iso_rings(v, 4, 4, 0.5f).size(), 1u);
}

TEST(trace_regions, GroupsHolesWithTheirOutline) {
  const auto regions = trace_regions(test_image(), 100, 100, 0.5f, 0.5, 4.0);
  ASSERT_EQ(regions.size(), 2u);
  const Region& annulus = regions[0].holes.empty() ? regions[1] : regions[0];
  const Region& square = regions[0].holes.empty() ? regions[0] : regions[1];
  ASSERT_EQ(annulus.holes.size(), 1u);
  EXPECT_TRUE(square.holes.empty());
  const double area = signed_area(annulus.outer) + signed_area(annulus.holes[0]);
  EXPECT_NEAR(area, M_PI * (30 * 30 - 12 * 12), 0.03 * M_PI * (30 * 30 - 12 * 12));
  EXPECT_LT(annulus.outer.size(), 80u);  // simplified
}

TEST(trace_regions, DropsSpecks) {
  std::vector<float> v(20 * 20, 0.0f);
  v[5 * 20 + 5] = 1.0f;  // a single pixel: area 0.5 after tracing
  EXPECT_TRUE(trace_regions(v, 20, 20, 0.5f, 0.5, 4.0).empty());
}

}  // namespace
}  // namespace mar
