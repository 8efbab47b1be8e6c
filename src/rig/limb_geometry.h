// Geometry the automatic rig reads a drawing's parts with: a ring's centroid, where two
// outlines cross, how near two outlines come, and a limb's medial axis.
#pragma once

#include "geom/types.h"

#include <vector>

namespace mar {

/// The area centroid of a closed ring (the mean of its points when it has no area).
Vec2 ring_centroid(const Points& r);

/// Points where two closed outlines cross.
std::vector<Vec2> crossings(const Points& a, const Points& b);

/// The smallest distance from a point of `a` to an edge of the closed ring `b`.
double ring_distance(const Points& a, const Points& b);

/// Whether `q` is inside the closed ring `r` or within `tol` of its edges (false for a ring of
/// fewer than three points).
bool ring_holds(const Points& r, const Vec2& q, double tol);

/// How near the closed ring `b` comes to `a`, from 32 of `a`'s points (evenly spaced) to `b`'s
/// edges; `mid`, if given, gets the middle of that nearest step (where one would hinge on the
/// other across the gap). Infinity when either is empty.
double ring_gap(const Points& a, const Points& b, Vec2* mid = nullptr);

/// A limb's medial axis, from its free end to its attached end: on a grid over the limb, the
/// free end is the middle of what lies farthest (walking inside the limb, 8-neighbour
/// Dijkstra) from where it is attached — a hand, a fan of a tail's edge — and the axis is the
/// centroids of bands of equal distance from that free end: cross-sections, so it follows a
/// curved limb. Empty for a ring with no inside.
std::vector<Vec2> medial_path(const Points& ring, const Vec2& attached);

}  // namespace mar
