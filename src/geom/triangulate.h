// Fill triangulation of a multi-contour shape (holes and fill rule respected).
// CGAL's constrained Delaunay triangulation lives behind this plain interface, in
// exactly one translation unit (triangulate.cpp).
#pragma once

#include "geom/types.h"

#include <span>

namespace mar {

enum class FillRule { NonZero, EvenOdd };

/// A contour inside a shared point array: points[begin .. begin+count).
/// For filling, every contour is treated as closed.
struct Ring {
  int begin = 0;
  int count = 0;
};

/// Triangles covering the filled region of the contours. A one-point ring is an interior
/// point: a vertex of the mesh (where it lies in the filled region), no edge.
/// Every mesh vertex is expressed through the input points as
/// lerp(points[src_a], points[src_b], src_t), so the same mesh follows a deformed
/// copy of the points: input vertices have src_a == src_b, intersection points of
/// crossing contours lie on the segment (src_a, src_b).
struct FillMesh {
  Points vertices;             ///< #V rest positions
  std::vector<int> src_a;      ///< #V
  std::vector<int> src_b;      ///< #V
  std::vector<double> src_t;   ///< #V
  std::vector<int> triangles;  ///< 3 * #T vertex indices, counter-clockwise (shoelace-positive)
};

FillMesh triangulate_fill(std::span<const Vec2> points, std::span<const Ring> rings,
                          FillRule rule);

/// Constrained Delaunay triangulation of all the points with every ring edge (open
/// polylines given as rings with `closed` false) as a constraint, keeping every face of
/// the convex hull: one connected mesh over a whole multi-part character, as a single
/// outline-based method would use. Vertices are the input points (duplicates merged,
/// intersection points appended); triangles counter-clockwise.
struct HullMesh {
  Points vertices;
  std::vector<int> triangles;
};
HullMesh triangulate_hull(std::span<const Vec2> points, std::span<const Ring> rings, std::span<const char> closed);

/// Recomputes mesh vertex positions from (possibly deformed) input points.
/// Writes #V entries into `out` (which must have that size); allocates nothing.
void fill_mesh_positions(const FillMesh& mesh, std::span<const Vec2> points, std::span<Vec2> out);

/// Total area of the mesh triangles.
double fill_mesh_area(const FillMesh& mesh);

}  // namespace mar
