#include "geom/polygon.h"
#include "geom/triangulate.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

Points square(double x, double y, double s, bool ccw = true) {
  Points p{{x, y}, {x + s, y}, {x + s, y + s}, {x, y + s}};
  if (!ccw) std::reverse(p.begin(), p.end());
  return p;
}

// Five points of a regular pentagram, radius 100: its edges cross five times.
Points pentagram() {
  Points star;
  for (int k = 0; k < 5; ++k) {
    const double a = M_PI / 2 + k * 4 * M_PI / 5;
    star.emplace_back(100 * std::cos(a), 100 * std::sin(a));
  }
  return star;
}

struct Shape {
  Points pts;
  std::vector<Ring> rings;
  void add(const Points& r) {
    rings.push_back({static_cast<int>(pts.size()), static_cast<int>(r.size())});
    pts.insert(pts.end(), r.begin(), r.end());
  }
};

TEST(triangulate_fill, SquareAreaAndOrientation) {
  Shape s;
  s.add(square(0, 0, 10));
  const FillMesh m = triangulate_fill(s.pts, s.rings, FillRule::NonZero);
  EXPECT_NEAR(fill_mesh_area(m), 100.0, 1e-9);
  EXPECT_EQ(m.triangles.size(), 6u);
}

TEST(triangulate_fill, HoleRespectsFillRule) {
  for (bool same_orientation : {true, false}) {
    Shape s;
    s.add(square(0, 0, 10));
    s.add(square(3, 3, 4, same_orientation));
    const double evenodd = fill_mesh_area(triangulate_fill(s.pts, s.rings, FillRule::EvenOdd));
    const double nonzero = fill_mesh_area(triangulate_fill(s.pts, s.rings, FillRule::NonZero));
    EXPECT_NEAR(evenodd, 84.0, 1e-9);
    EXPECT_NEAR(nonzero, same_orientation ? 100.0 : 84.0, 1e-9);
  }
}

TEST(triangulate_fill, SelfIntersectingStar) {
  Shape s;
  s.add(pentagram());
  const FillMesh nz = triangulate_fill(s.pts, s.rings, FillRule::NonZero);
  const FillMesh eo = triangulate_fill(s.pts, s.rings, FillRule::EvenOdd);
  // The inner pentagon is winding 2: filled by nonzero, empty by evenodd.
  const double r_in = 100 * std::cos(2 * M_PI / 5) / std::cos(M_PI / 5);
  const double pentagon = 2.5 * r_in * r_in * std::sin(2 * M_PI / 5);
  EXPECT_NEAR(fill_mesh_area(nz) - fill_mesh_area(eo), pentagon, 1e-6 * pentagon);
  EXPECT_GT(nz.vertices.size(), 5u);  // the five intersection points were inserted
}

TEST(triangulate_fill, MeshFollowsDeformedPoints) {
  Shape s;
  s.add(pentagram());
  const FillMesh m = triangulate_fill(s.pts, s.rings, FillRule::NonZero);
  std::vector<Vec2> rest(m.vertices.size());
  fill_mesh_positions(m, s.pts, rest);
  for (size_t i = 0; i < rest.size(); ++i) EXPECT_NEAR((rest[i] - m.vertices[i]).norm(), 0, 1e-9);
  Points moved = s.pts;
  for (Vec2& p : moved) p += Vec2(7, -3);
  std::vector<Vec2> out(m.vertices.size());
  fill_mesh_positions(m, moved, out);
  for (size_t i = 0; i < out.size(); ++i) EXPECT_NEAR((out[i] - m.vertices[i] - Vec2(7, -3)).norm(), 0, 1e-9);
}

TEST(triangulate_fill, DegenerateInputsGiveEmptyMeshes) {
  Shape line;
  line.add({{0, 0}, {10, 0}, {20, 0}});
  EXPECT_TRUE(triangulate_fill(line.pts, line.rings, FillRule::NonZero).triangles.empty());
  Shape two;
  two.add({{0, 0}, {10, 0}});
  EXPECT_TRUE(triangulate_fill(two.pts, two.rings, FillRule::NonZero).triangles.empty());
  Shape dup;
  dup.add({{0, 0}, {0, 0}, {10, 0}, {10, 0}, {0, 10}});
  EXPECT_NEAR(fill_mesh_area(triangulate_fill(dup.pts, dup.rings, FillRule::NonZero)), 50.0, 1e-9);
  std::vector<Ring> bad{{3, 100}};
  EXPECT_TRUE(triangulate_fill(dup.pts, bad, FillRule::NonZero).triangles.empty());
}

TEST(triangulate_fill, OverlappingContoursWithSharedEdge) {
  Shape s;
  s.add(square(0, 0, 10));
  s.add(square(10, 0, 10));  // touches along x = 10
  EXPECT_NEAR(fill_mesh_area(triangulate_fill(s.pts, s.rings, FillRule::NonZero)), 200.0, 1e-9);
  Shape twice;
  twice.add(square(0, 0, 10));
  twice.add(square(0, 0, 10));  // same square twice: winding 2
  EXPECT_NEAR(fill_mesh_area(triangulate_fill(twice.pts, twice.rings, FillRule::NonZero)), 100.0, 1e-9);
  EXPECT_NEAR(fill_mesh_area(triangulate_fill(twice.pts, twice.rings, FillRule::EvenOdd)), 0.0, 1e-9);
}

}  // namespace
}  // namespace mar
