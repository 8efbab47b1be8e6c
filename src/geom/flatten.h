// Adaptive flattening of Bézier curves and elliptical arcs into polylines.
#pragma once

#include <cstdint>

#include "geom/types.h"

namespace mar {

/// Appends points approximating the cubic p0..p3 (p0 itself not appended) so that
/// no point of the curve is farther than `tolerance` from the polyline.
/// Recursive subdivision: flat pieces stop early, curved pieces split further (at most 2^18
/// points a curve). `out` never grows past `max_size` points: the curve is cut short there, and
/// a caller with a point budget treats a full `out` as over it — so a hostile curve costs
/// no more than the budget, whatever its tolerance.
void flatten_cubic(const Vec2& p0, const Vec2& p1, const Vec2& p2, const Vec2& p3,
                   double tolerance, Points& out, size_t max_size = SIZE_MAX);

/// Same for a quadratic Bézier (degree-elevated to a cubic).
void flatten_quad(const Vec2& p0, const Vec2& p1, const Vec2& p2, double tolerance, Points& out);

/// One cubic Bézier segment: control points c1, c2 and end point p.
struct CubicSeg {
  Vec2 c1, c2, p;
};

/// SVG endpoint-parameterised elliptical arc (SVG 1.1 F.6.5/F.6.6: out-of-range radii
/// scaled up, zero radius = straight line) from `p0` to `p1`, as cubic segments of at
/// most 45 degrees each (radial error below 1e-5 of the radius). Appends to `out`.
void arc_to_cubics(const Vec2& p0, double rx, double ry, double x_axis_rotation_deg,
                   bool large_arc, bool sweep, const Vec2& p1, std::vector<CubicSeg>& out);

}  // namespace mar
